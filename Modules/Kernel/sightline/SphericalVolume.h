// Emission-absorption volume rendering of a spherical grid (SphericalGrid.h) straight from its
// cells: every pixel's ray is traversed exactly and each cell it crosses contributes its
// transfer-function colour and extinction over the exact length inside it. No resampling.
#pragma once

#include "sightline/Camera.h"
#include "sightline/Framebuffer.h"
#include "sightline/SphericalGrid.h"

#include <functional>
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
} // namespace sightline
