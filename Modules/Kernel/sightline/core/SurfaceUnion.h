// SPDX-License-Identifier: BSD-3-Clause
// The union of solids along a ray (Han et al. 2019, Section 4.3): the intervals where a ray is
// inside each solid part of a primitive, and the entry and exit surfaces of their union, which
// the renderer composites for correct transparency of overlapping primitives.
#pragma once

#include <cstdint>
#include <vector>

namespace sightline
{
/// Where a ray's line is inside one solid part of a primitive: [t0, t1], not clipped to the
/// ray's [tnear, tfar] (t0 is below tnear when the ray starts inside). `part` names the solid
/// for its normal and colour (Geometry::partNormal), `primitive` the Embree primitive.
struct InsideInterval
{
  double t0, t1;
  std::uint32_t primitive;
  std::uint32_t part;
  std::uint32_t geometry = 0; ///< Embree geometry id, filled in by the scene
};

/// A surface of a union of solids along a ray: where the ray enters or leaves the union.
struct UnionSurface
{
  double t;
  bool entering;
  std::uint32_t part;     ///< the solid whose surface this is
  std::uint32_t geometry; ///< and its geometry
};

/// The surfaces of the union of `intervals` strictly inside (tnear, tfar), front to back
/// (Han et al. 2019, Section 4.3.1). Counting entries and exits along the sorted intervals,
/// the union's surfaces are the 0 -> 1 and 1 -> 0 transitions; a sweep that keeps the
/// farthest exit seen is the same count, and a solid reported twice (as an Embree filter may)
/// changes nothing. Intervals that overlap or touch within `gap` merge (no interior surface).
/// Sorts `intervals` in place.
void unionSurfaces(std::vector<InsideInterval>& intervals, double tnear, double tfar, double gap,
  std::vector<UnionSurface>& out);
} // namespace sightline
