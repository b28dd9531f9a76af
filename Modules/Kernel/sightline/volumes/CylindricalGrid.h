// SPDX-License-Identifier: BSD-3-Clause
// Exact ray traversal of cylindrical grids (rho, phi, z), the thesis' remark that the spherical
// scheme carries over: along a line rho^2 (distance from the z axis) is ditone with one hinge
// at the closest approach to the axis, phi is monotone (the same half-planes as spherical
// grids) and z is linear. So the cells follow from the indices at the ray's ends and hinge and
// one formula per crossing, merged from three sorted lists, as in SphericalTraversal.
//
// Conventions: rho >= 0; phi the azimuth from +x towards +y, spanning at most 2 pi (exactly
// 2 pi is the full circle); z any. Breakpoints are cell boundaries, strictly increasing; a grid
// may be a section (a hollow cylinder, a wedge, a slab).
#pragma once

#include "sightline/math/Math.h"
#include "sightline/volumes/SphericalGrid.h" // CellSegment

#include <memory>
#include <vector>

namespace sightline
{
struct CylindricalGrid
{
  std::vector<double> radius;  ///< rho breakpoints, >= 0
  std::vector<double> azimuth; ///< phi breakpoints, radians, spanning at most 2 pi
  std::vector<double> height;  ///< z breakpoints

  /// Throws std::invalid_argument naming the problem: fewer than 2 breakpoints, NaN, not
  /// strictly increasing, rho < 0, phi spanning more than 2 pi.
  void validate() const;
  int radialCells() const { return int(radius.size()) - 1; }
  int azimuthalCells() const { return int(azimuth.size()) - 1; }
  int heightCells() const { return int(height.size()) - 1; }
  std::size_t cellCount() const
  {
    return std::size_t(radialCells()) * std::size_t(azimuthalCells()) * std::size_t(heightCells());
  }
  /// Index of cell (irho, iphi, iz) with rho fastest, then phi, then z (a vtkRectilinearGrid's
  /// point order with x = rho, y = phi, z = z).
  std::size_t cellIndex(int irho, int iphi, int iz) const
  {
    return std::size_t(irho) + std::size_t(radialCells()) * (std::size_t(iphi) + std::size_t(azimuthalCells()) * std::size_t(iz));
  }
  bool fullCircle() const;
};

class CylindricalTraversal
{
public:
  /// Validates the grid (see CylindricalGrid::validate).
  explicit CylindricalTraversal(CylindricalGrid grid);
  const CylindricalGrid& grid() const { return Grid; }
  /// The cells the ray origin + t direction crosses for t in [tmin, tmax], in order, each with
  /// its entry and exit t, as SphericalTraversal::traverse. In the segments, `r` is the rho
  /// index, `phi` the azimuth index and `theta` the height (z) index.
  void traverse(const dvec3& origin, const dvec3& direction, double tmin, double tmax,
    std::vector<CellSegment>& out) const;

  /// The same cells without a list, as SphericalTraversal::forEachCell: `visit(rho, z, phi, t0,
  /// t1)` for each, in order, returning false to stop.
  template <class Visit>
  void forEachCell(const dvec3& origin, const dvec3& direction, double tmin, double tmax, Visit&& visit) const
  {
    traversal::Crossings c;
    if (crossings(origin, direction, tmin, tmax, c))
      traversal::forEachMergedCell(c, visit);
  }

private:
  /// The ray's crossings of cylinders, planes of constant z and half-planes; false when it
  /// misses the grid.
  bool crossings(const dvec3& origin, const dvec3& direction, double tmin, double tmax, traversal::Crossings& out) const;

  CylindricalGrid Grid;
  std::vector<double> RadiusSquared;
  std::shared_ptr<const traversal::AzimuthSweep> Azimuth;
};

/// Line integral of a cell-constant field (ordered as CylindricalGrid::cellIndex) over the
/// segments of a cylindrical traversal: value x length.
double projectCellConstant(const CylindricalGrid& grid, const std::vector<double>& values,
  const std::vector<CellSegment>& segments, double directionLength);
} // namespace sightline
