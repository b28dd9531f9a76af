// SPDX-License-Identifier: BSD-3-Clause
// Generalized tubes (Han et al. 2019) as one Embree user geometry: control points with radii,
// each linked to a predecessor (or -1), drawn as a sphere at every point and the tangential cone
// stump (TubeLink.h) to its predecessor. Bifurcations need no special case: two links naming
// the same predecessor share its sphere.
//
// The paper's four implementation choices (Section 4.2) are all here, picked by TubeLayout:
// - primitives: a "combined" primitive per link (its end sphere and its stump, one BVH leaf) or
//   "separate" spheres and stumps (two BVH leaves per link);
// - transforms: stump parameters computed on the fly from the two control points (the smallest
//   memory: a point, a radius and a predecessor index per link) or precomputed per link.
//
// Opaque scenes use the first-hit path (intersect()). Translucent scenes use the union's
// surfaces instead (insideIntervals() and unionSurfaces() in Geometry.h, Section 4.3): every
// overlap interval along the ray is collected and only transitions between outside and inside
// are drawn, so overlapping links show no interior surfaces.
#pragma once

#include "sightline/core/Geometry.h"
#include "sightline/tubes/TubeLink.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sightline
{
struct TubeLayout
{
  enum class Primitives
  {
    Combined, ///< one primitive per link: end sphere + stump to the predecessor
    Separate, ///< spheres and stumps are primitives of their own
  };
  enum class Transforms
  {
    OnTheFly,    ///< stump parameters derived from the control points at every test
    Precomputed, ///< stump parameters stored per link
  };
  Primitives primitives = Primitives::Combined;
  Transforms transforms = Transforms::OnTheFly;

  /// "combined, on-the-fly" and so on, as the paper's Table 1 names them.
  std::string name() const;
};

class TubeSet : public UserGeometry<TubeSet>
{
public:
  /// One control point per position; `radii` one per point; `predecessors` one per point,
  /// -1 for the first point of a tube. `colors` (RGBA8) is empty or one per point.
  /// Throws std::invalid_argument for size mismatches, a predecessor out of range and cyclic
  /// links (naming a point on the cycle). Points with a non-finite position, a non-finite or
  /// negative radius are dropped with their links and reported in report(); a link of zero
  /// length, or whose one sphere holds the other, draws only its spheres.
  TubeSet(const std::vector<vec3>& points, const std::vector<float>& radii,
    const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors = {},
    TubeLayout layout = {});
  /// The same with the points given relative to `origin`, kept in double: tubes far from the
  /// world origin keep float precision relative to the set's extent and are intersected with
  /// double rays in that frame.
  TubeSet(const dvec3& origin, const std::vector<vec3>& points, const std::vector<float>& radii,
    const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors = {},
    TubeLayout layout = {});

  std::size_t size() const override { return Nodes.size() + StumpEnds.size(); }
  bool hasPrimitiveColors() const override { return !Colors.empty(); }
  vec3 primitiveColor(unsigned primitive) const override;
  std::size_t memoryBytes() const override;
  Box3 bounds() const override { return AllBounds; }
  void insideIntervals(unsigned primitive, const DoubleRay& ray, std::vector<InsideInterval>& out) const override;
  vec3 partNormal(std::uint32_t part, const dvec3& point) const override;
  vec3 partColor(std::uint32_t part) const override;

  Box3 bounds(unsigned primitive) const;
  bool intersect(unsigned primitive, const DoubleRay& ray, SurfaceHit& hit) const;

  const TubeLayout& layout() const { return Layout; }
  /// Control points kept (after dropping bad ones) and links between them.
  std::size_t pointCount() const { return Nodes.size(); }
  std::size_t linkCount() const { return Links; }
  const ValidationReport& report() const { return Report; }
  /// For picking: the kept control point whose link (from its predecessor) and end sphere a
  /// primitive draws, that point's predecessor (a kept index, or -1 where a tube starts), and
  /// its index among the points given to the constructor.
  std::uint32_t nodeOfPrimitive(unsigned primitive) const { return nodeOf(primitive); }
  std::int32_t predecessorOf(std::uint32_t node) const { return Predecessors[node]; }
  std::uint32_t sourceIndexOf(std::uint32_t node) const
  {
    return SourceIndex.empty() ? node : SourceIndex[node];
  }
  /// What control points (and precomputed stumps) are relative to.
  const dvec3& origin() const { return Origin; }

private:
  /// Stump parameters in single precision (the precomputed layouts).
  struct StoredStump
  {
    vec3 base, axis;
    float slope, cosine, radius1, u1, u2;
  };
  ConeStump stumpOf(std::uint32_t node) const;
  std::uint32_t nodeOf(unsigned primitive) const;

  TubeLayout Layout;
  dvec3 Origin{ 0.0 };
  std::vector<vec4> Nodes;                 ///< kept control points: position (from Origin), radius
  std::vector<std::int32_t> Predecessors;  ///< kept index of each node's predecessor, or -1
  std::vector<std::uint32_t> SourceIndex;  ///< constructor index of each node; empty: the same
  std::vector<std::uint32_t> StumpEnds;    ///< separate layout: end node of each stump primitive
  std::vector<StoredStump> Stumps;         ///< precomputed: one per node (combined) or stump
  std::size_t Links = 0;
  std::vector<std::uint32_t> Colors;
  Box3 AllBounds;
  ValidationReport Report;
};
} // namespace sightline
