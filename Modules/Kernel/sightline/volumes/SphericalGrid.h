// SPDX-License-Identifier: BSD-3-Clause
// Exact ray traversal of spherical grids (r, theta, phi) without converting to Cartesian cells,
// after "Ray casting in spherical coordinates" (the thesis in ../shared/seeds): along a line,
// r^2 and the polar angle are ditone (one hinge each: the closest approach to the origin, and
// the extremum of cos theta, which is where a linear function of t vanishes) and the azimuth is
// monotone. So the indices of the shells, cones and half-planes a ray crosses follow from the
// indices at the ray's ends and hinges alone (binary search only there); each crossing's t
// comes from one formula (a square root for a sphere, a quadratic for a cone, a division for a
// half-plane), and the three sorted t-lists merge in linear time into the ordered cells.
//
// Conventions: r >= 0; theta is the colatitude in [0, pi] (0 on +z); phi the azimuth from +x
// towards +y. Breakpoints are cell boundaries, strictly increasing. A grid may be a section:
// r from r0 > 0 (a shell), theta in a sub-range (a cap or a band), phi over less than 2 pi (a
// wedge); phi spanning exactly 2 pi is the full circle. Only cells inside the section are
// reported.
#pragma once

#include "sightline/math/Math.h"
#include "sightline/volumes/CellCrossings.h"

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

namespace sightline
{
namespace traversal
{
class AzimuthSweep;
}

struct SphericalGrid
{
  std::vector<double> radius; ///< r breakpoints, >= 0
  std::vector<double> polar;  ///< theta breakpoints, radians in [0, pi]
  std::vector<double> azimuth; ///< phi breakpoints, radians, spanning at most 2 pi

  /// Throws std::invalid_argument naming the problem: fewer than 2 breakpoints, NaN, not
  /// strictly increasing, r < 0, theta outside [0, pi], phi spanning more than 2 pi.
  void validate() const;
  int radialCells() const { return int(radius.size()) - 1; }
  int polarCells() const { return int(polar.size()) - 1; }
  int azimuthalCells() const { return int(azimuth.size()) - 1; }
  std::size_t cellCount() const
  {
    return std::size_t(radialCells()) * std::size_t(polarCells()) * std::size_t(azimuthalCells());
  }
  /// Index of cell (ir, itheta, iphi) in an array ordered with r fastest, then theta, then phi
  /// (the point order of a vtkRectilinearGrid with x = r, y = theta, z = phi).
  std::size_t cellIndex(int ir, int itheta, int iphi) const
  {
    return std::size_t(ir) + std::size_t(radialCells()) * (std::size_t(itheta) + std::size_t(polarCells()) * std::size_t(iphi));
  }
  /// Whether phi covers the full circle (its span is 2 pi to 1e-12).
  bool fullCircle() const;
};

/// A grid prepared for traversal: the breakpoints as the pseudospherical coordinates the
/// traversal compares (r^2, the signed square of cos theta, the half-planes' cos and sin).
class SphericalTraversal
{
public:
  /// Validates the grid (see SphericalGrid::validate).
  explicit SphericalTraversal(SphericalGrid grid);

  const SphericalGrid& grid() const { return Grid; }

  /// The cells the ray origin + t direction (direction of any nonzero length) crosses for t in
  /// [tmin, tmax], in order, each with its entry and exit t. Cells outside the grid's section
  /// are left out, so the segments need not be contiguous; zero-length pieces (a ray through an
  /// edge or a corner) are left out too. Replaces the contents of `out`.
  void traverse(const dvec3& origin, const dvec3& direction, double tmin, double tmax,
    std::vector<CellSegment>& out) const;

  /// The same cells without a list: `visit(r, theta, phi, t0, t1)` is called for each, in
  /// order, and returns false to stop (a saturated compositing loop). The crossings live in
  /// per-thread lists, so `visit` must not traverse on the same thread.
  template <class Visit>
  void forEachCell(const dvec3& origin, const dvec3& direction, double tmin, double tmax, Visit&& visit) const
  {
    traversal::Crossings c;
    if (crossings(origin, direction, tmin, tmax, c))
      traversal::forEachMergedCell(c, visit);
  }

  /// A 2-D polar grid (r, phi) is the grid with polar breakpoints {0, pi} traversed by rays in
  /// the plane z = 0 (theta stays pi / 2).

private:
  /// The ray's crossings of shells, cones and half-planes; false when it misses the grid.
  bool crossings(const dvec3& origin, const dvec3& direction, double tmin, double tmax, traversal::Crossings& out) const;

  SphericalGrid Grid;
  std::vector<double> RadiusSquared;       ///< r_i^2, increasing
  std::vector<double> SignedCosineSquared; ///< cos(theta_j) |cos(theta_j)|, decreasing
  std::vector<double> PolarCosine;         ///< cos(theta_j)
  std::shared_ptr<const traversal::AzimuthSweep> Azimuth; ///< the half-planes

};

/// Line integral of a cell-constant field over the segments: sum of value(cell) x length
/// (yt's ProjectionSampler). `values` is ordered as SphericalGrid::cellIndex; `directionLength`
/// is |direction| so that lengths are distances.
double projectCellConstant(const SphericalGrid& grid, const std::vector<double>& values,
  const std::vector<CellSegment>& segments, double directionLength);
/// The same integral straight from the traversal, for the ray's part in [tmin, tmax] (no list
/// of segments in between).
double projectCellConstant(const SphericalTraversal& traversal, const std::vector<double>& values,
  const dvec3& origin, const dvec3& direction, double tmin, double tmax);

/// Line integrals of a field given at the radial breakpoints and interpolated in r (or in r^2)
/// inside each cell, constant in theta and phi: `nodeValues[i + (Nr + 1) (j + Ntheta k)]` is the
/// value at radius breakpoint i of the column (theta cell j, phi cell k). The thesis' "data
/// linear with respect to the radius (or the square of the radius)". Exact along each segment:
/// with u the ray parameter from the closest approach to the origin, r = sqrt(p^2 + a u^2), and
/// the integral of r has a closed form (asinh), that of r^2 is a cubic. `origin` and
/// `direction` are the ray the segments came from. Throws std::invalid_argument for a wrong
/// number of node values.
double projectLinearInRadius(const SphericalGrid& grid, const std::vector<double>& nodeValues,
  const std::vector<CellSegment>& segments, const dvec3& origin, const dvec3& direction);
double projectLinearInRadiusSquared(const SphericalGrid& grid, const std::vector<double>& nodeValues,
  const std::vector<CellSegment>& segments, const dvec3& origin, const dvec3& direction);
/// The same integrals straight from the traversal, for the ray's part in [tmin, tmax].
double projectLinearInRadius(const SphericalTraversal& traversal, const std::vector<double>& nodeValues,
  const dvec3& origin, const dvec3& direction, double tmin, double tmax);
double projectLinearInRadiusSquared(const SphericalTraversal& traversal, const std::vector<double>& nodeValues,
  const dvec3& origin, const dvec3& direction, double tmin, double tmax);

/// Node values for the two samplers above from a field f(r, theta, phi): each column's values at
/// the radial breakpoints, at its theta and phi midpoints.
std::vector<double> sampleRadialNodes(
  const SphericalGrid& grid, const std::function<double(double, double, double)>& field);

/// Emission-absorption along the segments, front to back, with cell-constant colour and
/// extinction from a transfer function of the cell's value: each cell multiplies the
/// transmittance by exp(-extinction x length) and adds colour x (1 - that factor). Cells whose
/// extinction is zero are skipped; the march stops once the transmittance falls below
/// `minimumTransmittance`. Returns premultiplied RGB and opacity.
struct TransferSample
{
  vec3 color{ 0.0f };
  double extinction = 0.0; ///< per unit length
};
/// Front-to-back emission-absorption one cell at a time: `add` multiplies the transmittance
/// by exp(-extinction x length) and adds colour x (1 - that factor); cells with zero extinction
/// are skipped. `first` is the t where the first visible cell is entered (-1 if none),
/// `visited` counts the composited cells.
struct CellCompositor
{
  double directionLength = 1.0;
  double minimumTransmittance = 1e-3;
  dvec3 color{ 0.0 };
  double transmittance = 1.0;
  double first = -1.0;
  std::size_t visited = 0;

  /// False once the transmittance has fallen below the minimum: nothing behind can show.
  bool add(const TransferSample& sample, double t0, double t1)
  {
    if (!(sample.extinction > 0.0))
      return true; // fully transparent: nothing to add
    if (first < 0.0)
      first = t0;
    ++visited;
    const double absorbed = 1.0 - std::exp(-sample.extinction * (t1 - t0) * directionLength);
    color += transmittance * absorbed * dvec3(sample.color);
    transmittance *= 1.0 - absorbed;
    return !(transmittance < minimumTransmittance);
  }
  /// Premultiplied RGB and opacity.
  vec4 rgba() const { return vec4(vec3(color), float(1.0 - transmittance)); }
};

/// The same compositing over a list of segments: `sampleOf(segment)` gives a segment's
/// TransferSample. `firstVisible` receives CellCompositor::first, `visited` is incremented per
/// composited segment. Premultiplied RGBA.
template <class SampleOf>
vec4 compositeCells(const SampleOf& sampleOf, const std::vector<CellSegment>& segments,
  double directionLength, double minimumTransmittance, double* firstVisible = nullptr,
  std::size_t* visited = nullptr)
{
  CellCompositor compositor;
  compositor.directionLength = directionLength;
  compositor.minimumTransmittance = minimumTransmittance;
  for (const CellSegment& s : segments)
    if (!compositor.add(sampleOf(s), s.t0, s.t1))
      break;
  if (firstVisible)
    *firstVisible = compositor.first;
  if (visited)
    *visited += compositor.visited;
  return compositor.rgba();
}

vec4 emissionAbsorption(const SphericalGrid& grid, const std::vector<double>& values,
  const std::function<TransferSample(double)>& transfer, const std::vector<CellSegment>& segments,
  double directionLength, double minimumTransmittance = 1e-3);

/// The t-interval where origin + t direction lies inside the sphere of radius R, clipped to
/// [t0, t1]; false when that is empty. Written around the closest approach so that long rays
/// far from the centre keep their precision.
bool sphereChord(const dvec3& origin, const dvec3& direction, double radius, double t0, double t1,
  double& enter, double& leave);

/// Point of spherical coordinates (r, theta = colatitude from +z, phi = azimuth from +x).
inline dvec3 sphericalToCartesian(double r, double theta, double phi)
{
  const double s = std::sin(theta);
  return dvec3(r * s * std::cos(phi), r * s * std::sin(phi), r * std::cos(theta));
}
} // namespace sightline
