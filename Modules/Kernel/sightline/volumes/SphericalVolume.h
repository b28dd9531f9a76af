// SPDX-License-Identifier: BSD-3-Clause
// Emission-absorption volume rendering of a spherical grid (SphericalGrid.h), or a cylindrical
// one (CylindricalGrid.h), straight from its cells: every pixel's ray is traversed exactly and
// each cell it crosses contributes its transfer-function colour and extinction over the exact
// length inside it. No resampling.
#pragma once

#include "sightline/core/Camera.h"
#include "sightline/volumes/CylindricalGrid.h"
#include "sightline/core/Framebuffer.h"
#include "sightline/core/Shading.h"
#include "sightline/volumes/SphericalGrid.h"

#include <functional>
#include <limits>
#include <vector>

namespace sightline
{
struct SphericalVolumeOptions
{
  /// Window depth of opaque geometry drawn by someone else, one per pixel (bottom row first);
  /// rays stop there. Null for none.
  const std::vector<float>* depthLimit = nullptr;
  /// The march stops once the transmittance falls below this (early ray termination).
  double minimumTransmittance = 1e-3;
  /// A box of world space (faces may be infinite) every ray is clipped to, half-open as
  /// clipToBox: one MPI rank's region of a partition. Regions that tile space, blended front
  /// to back, give the unclipped image (emission-absorption is multiplicative along the ray).
  dvec3 regionLower{ -std::numeric_limits<double>::infinity() };
  dvec3 regionUpper{ std::numeric_limits<double>::infinity() };
  /// The grid's frame in world space, where the region is given (the camera maps the grid's
  /// own coordinates); an affine map keeps the ray parameter.
  dmat4 objectToWorld{ 1.0 };
  /// Called after each band of rows with the fraction done; returning false stops the frame
  /// (the rows not yet traced stay empty).
  std::function<bool(double)> progress;
};

struct SphericalVolumeStatistics
{
  double seconds = 0.0;
  std::size_t cellsVisited = 0; ///< cell segments composited (transparent cells skipped)
};

/// Renders the grid's cells (`values` ordered as SphericalGrid::cellIndex) through the transfer
/// function into `framebuffer` (resized to the camera). The camera maps the grid's own
/// coordinates to clip space. Colour is not premultiplied; the depth written is where the ray
/// enters its first visible cell. The transfer function is evaluated once per cell per frame.
/// Throws std::invalid_argument for a wrong number of values or depth-limit size.
SphericalVolumeStatistics renderSphericalVolume(const SphericalTraversal& traversal,
  const std::vector<double>& values, const std::function<TransferSample(double)>& transfer,
  const Camera& camera, Framebuffer& framebuffer, const SphericalVolumeOptions& options = {});

/// The same with each cell's colour and extinction given (ordered as SphericalGrid::cellIndex),
/// e.g. already shaded by shadeCells. Throws std::invalid_argument for a wrong count.
SphericalVolumeStatistics renderSphericalVolume(const SphericalTraversal& traversal,
  const std::vector<TransferSample>& cells, const Camera& camera, Framebuffer& framebuffer,
  const SphericalVolumeOptions& options = {});

/// The same for cylindrical grids (rho, phi, z; CylindricalGrid.h): rays are clipped to the
/// cylinder around the outermost shell with a visible cell.
SphericalVolumeStatistics renderCylindricalVolume(const CylindricalTraversal& traversal,
  const std::vector<TransferSample>& cells, const Camera& camera, Framebuffer& framebuffer,
  const SphericalVolumeOptions& options = {});

/// A transfer function sampled at evenly spaced values (as VTK's mappers tabulate theirs), read
/// with linear interpolation and clamped to its range.
struct TransferTable
{
  double minimum = 0.0, maximum = 1.0;
  std::vector<TransferSample> entries; ///< at least one; entry i at minimum + i (max - min) / (n - 1)
  TransferSample operator()(double value) const;
};

/// Point data: `pointValues` at the grid's points ((Nr + 1)(Ntheta + 1)(Nphi + 1), r fastest,
/// then theta, then phi; for cylindrical grids rho, phi, z), interpolated trilinearly in the
/// coordinates inside each cell, and composited by the midpoint rule with samples at most
/// `sampleDistance` apart along each cell segment (so a sample never straddles a cell face).
/// NaN values are empty. Throws std::invalid_argument for a wrong count or a distance <= 0.
SphericalVolumeStatistics renderSphericalVolumePoints(const SphericalTraversal& traversal,
  const std::vector<double>& pointValues, const TransferTable& transfer, double sampleDistance,
  const Camera& camera, Framebuffer& framebuffer, const SphericalVolumeOptions& options = {});
SphericalVolumeStatistics renderCylindricalVolumePoints(const CylindricalTraversal& traversal,
  const std::vector<double>& pointValues, const TransferTable& transfer, double sampleDistance,
  const Camera& camera, Framebuffer& framebuffer, const SphericalVolumeOptions& options = {});

/// The cells of `grid` that may meet the box [lower, upper] (in the grid's own coordinates),
/// as inclusive index ranges first[axis]..last[axis] (r, theta, phi): a superset, from the
/// ranges of r, theta and phi over the box. On a full circle the azimuth range may run across
/// the seam: then first > last, meaning cells first..n-1 followed by 0..last. A box around the
/// z axis gives every phi cell, as does a wedge's range that wraps (its ends are not
/// neighbours). Returns false when no cell can meet the box.
bool cellRangeInBox(const SphericalGrid& grid, const dvec3& lower, const dvec3& upper, int first[3], int last[3]);
/// The same for a cylindrical grid (rho, phi, z).
bool cellRangeInBox(const CylindricalGrid& grid, const dvec3& lower, const dvec3& upper, int first[3], int last[3]);

/// Cartesian gradient of a cell-constant field at each cell centre, by central differences
/// between neighbouring cells in r, theta and phi (one-sided at the section's edges, across
/// phi = 0 on a full circle), in the local frame (e_r, e_theta / r, e_phi / (r sin theta)).
std::vector<dvec3> sphericalCellGradients(const SphericalGrid& grid, const std::vector<double>& values);

/// Gradient of a cell-constant field on a cylindrical grid, as sphericalCellGradients, in the
/// local frame (e_rho, e_phi / rho, e_z).
std::vector<dvec3> cylindricalCellGradients(const CylindricalGrid& grid, const std::vector<double>& values);

/// Cartesian centre of every cell (its coordinate midpoints), ordered as the grid's cellIndex.
std::vector<dvec3> cellCentres(const SphericalGrid& grid);
std::vector<dvec3> cellCentres(const CylindricalGrid& grid);

/// Lights each cell's colour as a surface at its centre whose normal is the field's gradient
/// (VTK's volume shading, two-sided), seen from the camera: Phong with the material's ambient,
/// diffuse and specular terms. Cells with a zero gradient keep their unlit colour times
/// (ambient + diffuse). Shading per cell, not per sample: the field is constant inside a cell.
void shadeCells(const std::vector<dvec3>& centres, const std::vector<dvec3>& gradients,
  const Material& material, const Lighting& lighting, const Camera& camera,
  std::vector<TransferSample>& cells);
} // namespace sightline
