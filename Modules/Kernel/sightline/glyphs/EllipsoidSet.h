// SPDX-License-Identifier: BSD-3-Clause
// Ellipsoids p = c + M u, |u| = 1, intersected exactly: the second-order tensor glyph that
// vtkTensorGlyph draws by transforming a sphere source with M = eigenvectors * eigenvalues.
// The ray is mapped into the unit sphere's frame, where the intersection is the sphere's
// quadratic (the seed's Discussion: an explicit ray-ellipsoid intersection beats any implicit
// surface method for this glyph).
#pragma once

#include "sightline/core/Geometry.h"

#include <cstdint>
#include <vector>

namespace sightline
{
class EllipsoidSet : public UserGeometry<EllipsoidSet>
{
public:
  /// One ellipsoid per centre; `axes[i]` is M (its columns are the semi-axes). `colors`
  /// (RGBA8) is empty or one per ellipsoid. Ellipsoids with non-finite input or a (nearly)
  /// singular M (smallest singular value below 1e-9 of the largest) are dropped and reported
  /// in report(); size mismatches throw std::invalid_argument.
  EllipsoidSet(const std::vector<vec3>& centers, const std::vector<dmat3>& axes,
    const std::vector<std::uint32_t>& colors = {});
  /// The same with the centres given relative to `origin` (kept in double), for ellipsoids far
  /// from the world origin: they are intersected in their own frame with double rays.
  EllipsoidSet(const dvec3& origin, const std::vector<vec3>& centers, const std::vector<dmat3>& axes,
    const std::vector<std::uint32_t>& colors = {});

  std::size_t size() const override { return Ellipsoids.size(); }
  bool hasPrimitiveColors() const override { return !Colors.empty(); }
  vec3 primitiveColor(unsigned primitive) const override;
  std::size_t memoryBytes() const override;
  Box3 bounds() const override { return AllBounds; }

  Box3 bounds(unsigned primitive) const;
  bool intersect(unsigned primitive, const DoubleRay& ray, SurfaceHit& hit) const;

  const ValidationReport& report() const { return Report; }
  const std::vector<std::uint32_t>& sourceIndex() const { return SourceIndex; }

private:
  struct Ellipsoid
  {
    dvec3 center;
    dmat3 inverse;   ///< M^-1: world offsets to the unit sphere's frame
    vec3 halfExtent; ///< row norms of M: the axis-aligned box
  };
  std::vector<Ellipsoid> Ellipsoids;
  std::vector<std::uint32_t> Colors;
  std::vector<std::uint32_t> SourceIndex;
  Box3 AllBounds;
  ValidationReport Report;
};
} // namespace sightline
