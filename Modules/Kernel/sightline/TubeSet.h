// Generalized tubes (Han et al. 2019) as one Embree user geometry: control points with radii,
// each linked to a predecessor (or -1), drawn as a sphere at every point and the tangential cone
// stump (TubeLink.h) to its predecessor. A primitive is a whole link (its end sphere and its
// stump: the paper's "combined" primitive, computed on the fly), which bifurcations need no
// special case for: two links naming the same predecessor simply share its sphere.
// This is the opaque, first-hit path; interior surfaces of overlapping links are not removed.
#pragma once

#include "sightline/Geometry.h"

#include <cstdint>
#include <vector>

namespace sightline
{
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
    const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors = {});

  std::size_t size() const override { return Links.size(); }
  bool hasPrimitiveColors() const override { return !Colors.empty(); }
  vec3 primitiveColor(unsigned primitive) const override;
  std::size_t memoryBytes() const override;
  Box3 bounds() const override { return AllBounds; }

  Box3 bounds(unsigned primitive) const;
  bool intersect(unsigned primitive, const Ray& ray, SurfaceHit& hit) const;

  const ValidationReport& report() const { return Report; }
  /// Input index of the end point of each kept link.
  const std::vector<std::uint32_t>& sourceIndex() const { return SourceIndex; }

private:
  struct Link
  {
    vec3 end;               ///< this point
    float endRadius = 0.0f;
    vec3 start;             ///< its predecessor (equal to end for a tube's first point)
    float startRadius = 0.0f;
    bool hasStart = false;
  };
  std::vector<Link> Links;
  std::vector<std::uint32_t> Colors;
  std::vector<std::uint32_t> SourceIndex;
  Box3 AllBounds;
  ValidationReport Report;
};
} // namespace sightline
