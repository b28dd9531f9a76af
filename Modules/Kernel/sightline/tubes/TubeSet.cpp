// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/tubes/TubeSet.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
std::string TubeLayout::name() const
{
  return std::string(primitives == Primitives::Combined ? "combined" : "separate") + ", " +
    (transforms == Transforms::OnTheFly ? "on-the-fly" : "precomputed");
}

namespace
{
/// Throws when following predecessors from some point comes back to a point of the same walk.
void checkForCycles(const std::vector<std::int64_t>& predecessors)
{
  const std::size_t n = predecessors.size();
  std::vector<std::uint8_t> state(n, 0); // 0 unvisited, 1 on the current walk, 2 done
  std::vector<std::size_t> walk;
  for (std::size_t start = 0; start < n; ++start)
  {
    walk.clear();
    for (std::size_t i = start; state[i] != 2;)
    {
      if (state[i] == 1)
        throw std::invalid_argument(
          "sightline::TubeSet: the links through point " + std::to_string(i) + " form a cycle");
      state[i] = 1;
      walk.push_back(i);
      if (predecessors[i] < 0)
        break;
      i = std::size_t(predecessors[i]);
    }
    for (std::size_t w : walk)
      state[w] = 2;
  }
}

Box3 sphereBox(const vec4& node)
{
  return Box3{ vec3(node) - vec3(node.w), vec3(node) + vec3(node.w) };
}
} // namespace

TubeSet::TubeSet(const std::vector<vec3>& points, const std::vector<float>& radii,
  const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors,
  TubeLayout layout)
  : Layout(layout)
{
  const std::size_t n = points.size();
  if (radii.size() != n || predecessors.size() != n)
    throw std::invalid_argument("sightline::TubeSet: " + std::to_string(radii.size()) + " radii and " +
      std::to_string(predecessors.size()) + " predecessors for " + std::to_string(n) + " points");
  if (!colors.empty() && colors.size() != n)
    throw std::invalid_argument("sightline::TubeSet: " + std::to_string(colors.size()) +
      " colours for " + std::to_string(n) + " points");
  if (n >= std::size_t(INT32_MAX))
    throw std::invalid_argument("sightline::TubeSet: " + std::to_string(n) +
      " points exceed the 2^31 - 1 a tube set indexes");
  for (std::size_t i = 0; i < n; ++i)
    if (predecessors[i] < -1 || predecessors[i] >= std::int64_t(n))
      throw std::invalid_argument("sightline::TubeSet: point " + std::to_string(i) +
        " has the predecessor " + std::to_string(predecessors[i]) + ", outside [-1, " +
        std::to_string(n - 1) + "]");
  checkForCycles(predecessors);

  auto usable = [&](std::size_t i)
  { return isFinite(points[i]) && std::isfinite(radii[i]) && radii[i] >= 0.0f; };
  std::vector<std::int32_t> keptIndex(n, -1);
  std::vector<std::uint32_t> sourceIndex;
  std::size_t dropped = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!usable(i))
    {
      if (dropped++ == 0)
        Report.reasons.push_back("point " + std::to_string(i) +
          " has a non-finite position or a negative or non-finite radius (first of the points "
          "dropped for this reason, with their links)");
      continue;
    }
    keptIndex[i] = std::int32_t(Nodes.size());
    Nodes.push_back(vec4(points[i], radii[i]));
    sourceIndex.push_back(std::uint32_t(i));
    if (!colors.empty())
      Colors.push_back(colors[i]);
  }
  Report.rejected = dropped;
  Predecessors.resize(Nodes.size(), -1);
  for (std::size_t k = 0; k < Nodes.size(); ++k)
  {
    const std::int64_t p = predecessors[sourceIndex[k]];
    if (p >= 0 && keptIndex[std::size_t(p)] >= 0)
    {
      Predecessors[k] = keptIndex[std::size_t(p)];
      ++Links;
    }
  }

  // Stumps exist only where the link has length and neither sphere holds the other.
  auto computeStump = [&](std::uint32_t node)
  {
    const std::int32_t p = Predecessors[node];
    if (p < 0)
      return ConeStump{};
    return makeConeStump(
      dvec3(vec3(Nodes[std::size_t(p)])), Nodes[std::size_t(p)].w, dvec3(vec3(Nodes[node])), Nodes[node].w);
  };
  auto store = [](const ConeStump& k)
  {
    return StoredStump{ vec3(k.base), vec3(k.axis), float(k.slope), k.valid ? float(k.cosine) : 0.0f,
      float(k.radius1), float(k.u1), float(k.u2) };
  };
  const bool precomputed = Layout.transforms == TubeLayout::Transforms::Precomputed;
  for (std::uint32_t k = 0; k < Nodes.size(); ++k)
  {
    const ConeStump stump = computeStump(k);
    if (Layout.primitives == TubeLayout::Primitives::Separate)
    {
      if (!stump.valid)
        continue;
      StumpEnds.push_back(k);
      if (precomputed)
        Stumps.push_back(store(stump));
    }
    else if (precomputed)
      Stumps.push_back(store(stump));
  }
  // Vectors grown by push_back hold up to twice their size: give the slack back, since
  // bytes per link is what large assemblies are limited by.
  // Only a set that dropped points needs its constructor indices (picking maps through them).
  if (dropped > 0)
    SourceIndex = std::move(sourceIndex);
  SourceIndex.shrink_to_fit();
  Nodes.shrink_to_fit();
  StumpEnds.shrink_to_fit();
  Stumps.shrink_to_fit();
  Colors.shrink_to_fit();
  for (unsigned i = 0; i < size(); ++i)
    AllBounds.extend(bounds(i));
}

TubeSet::TubeSet(const dvec3& origin, const std::vector<vec3>& points, const std::vector<float>& radii,
  const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors,
  TubeLayout layout)
  : TubeSet(points, radii, predecessors, colors, layout)
{
  if (!(std::isfinite(origin.x) && std::isfinite(origin.y) && std::isfinite(origin.z)))
    throw std::invalid_argument("sightline::TubeSet: the origin must be finite");
  Origin = origin;
  AllBounds = Box3{};
  for (unsigned i = 0; i < size(); ++i)
    AllBounds.extend(bounds(i));
}

std::uint32_t TubeSet::nodeOf(unsigned primitive) const
{
  return primitive < Nodes.size() ? primitive : StumpEnds[primitive - Nodes.size()];
}

ConeStump TubeSet::stumpOf(std::uint32_t node) const
{
  if (Layout.transforms == TubeLayout::Transforms::Precomputed)
  {
    // Combined layouts store one per node, separate ones one per stump primitive; parts name
    // nodes, so a separate layout finds its stump's slot by search (only for normals).
    std::size_t slot = node;
    if (Layout.primitives == TubeLayout::Primitives::Separate)
      slot = std::size_t(std::lower_bound(StumpEnds.begin(), StumpEnds.end(), node) - StumpEnds.begin());
    if (slot >= Stumps.size() || (Layout.primitives == TubeLayout::Primitives::Separate &&
                                    StumpEnds[slot] != node))
      return ConeStump{};
    const StoredStump& s = Stumps[slot];
    ConeStump k;
    k.valid = s.cosine > 0.0f;
    k.base = dvec3(s.base);
    k.axis = dvec3(s.axis);
    k.slope = s.slope;
    k.cosine = s.cosine;
    k.radius1 = s.radius1;
    k.u1 = s.u1;
    k.u2 = s.u2;
    return k;
  }
  const std::int32_t p = Predecessors[node];
  if (p < 0)
    return ConeStump{};
  const vec4& a = Nodes[std::size_t(p)];
  const vec4& b = Nodes[node];
  return makeConeStump(dvec3(vec3(a)), a.w, dvec3(vec3(b)), b.w);
}

Box3 TubeSet::bounds(unsigned primitive) const
{
  const std::uint32_t node = nodeOf(primitive);
  Box3 box;
  if (primitive < Nodes.size())
    box = sphereBox(Nodes[node]);
  // A stump lies in the convex hull of its two spheres, hence in the union of their boxes.
  const bool withStump = primitive >= Nodes.size() || Layout.primitives == TubeLayout::Primitives::Combined;
  if (withStump && Predecessors[node] >= 0)
  {
    box.extend(sphereBox(Nodes[node]));
    box.extend(sphereBox(Nodes[std::size_t(Predecessors[node])]));
  }
  const vec3 pad = 1e-6f * (glm::abs(box.lower) + glm::abs(box.upper) + vec3(1e-30f));
  box.lower -= pad;
  box.upper += pad;
  return Box3{ vec3(Origin + dvec3(box.lower)), vec3(Origin + dvec3(box.upper)) };
}

bool TubeSet::intersect(unsigned primitive, const DoubleRay& ray, SurfaceHit& hit) const
{
  // The nearest surface of the primitive's sphere and stump in (tnear, tfar): an interval's
  // entry, or its exit when the ray starts inside. In the set's frame (t is the same there).
  const std::uint32_t node = nodeOf(primitive);
  const dvec3 o = ray.origin - Origin, d = ray.direction;
  const double tmin = ray.tnear, tmax = std::min(ray.tfar, 1e300);
  double best = tmax;
  dvec3 normal(0.0);
  bool found = false;
  auto consider = [&](double t0, double t1, auto normalAt)
  {
    const double t = t0 > tmin ? t0 : t1;
    if (t > tmin && t < best)
    {
      best = t;
      normal = normalAt(o + t * d);
      found = true;
    }
  };
  double t0, t1;
  if (primitive < Nodes.size())
  {
    const dvec3 center = dvec3(vec3(Nodes[node]));
    if (sphereInterval(center, Nodes[node].w, o, d, -1e300, 1e300, t0, t1))
      consider(t0, t1, [&](const dvec3& p) { return p - center; });
  }
  if (primitive >= Nodes.size() || Layout.primitives == TubeLayout::Primitives::Combined)
  {
    const ConeStump stump = stumpOf(node);
    if (coneStumpInterval(stump, o, d, -1e300, 1e300, t0, t1))
      consider(t0, t1, [&](const dvec3& p) { return coneStumpNormal(stump, p); });
  }
  if (!found || !(best < tmax))
    return false;
  hit.t = best;
  hit.normal = vec3(normal);
  return true;
}

void TubeSet::insideIntervals(unsigned primitive, const DoubleRay& ray, std::vector<InsideInterval>& out) const
{
  // The whole line (t_r0 = -inf, Section 4.3.1), so a ray starting inside a tube knows it.
  const std::uint32_t node = nodeOf(primitive);
  const dvec3 o = ray.origin - Origin, d = ray.direction;
  double t0, t1;
  if (primitive < Nodes.size() &&
    sphereInterval(dvec3(vec3(Nodes[node])), Nodes[node].w, o, d, -1e300, 1e300, t0, t1))
    out.push_back({ t0, t1, primitive, 2 * node });
  if (primitive >= Nodes.size() || Layout.primitives == TubeLayout::Primitives::Combined)
  {
    const ConeStump stump = stumpOf(node);
    if (coneStumpInterval(stump, o, d, -1e300, 1e300, t0, t1))
      out.push_back({ t0, t1, primitive, 2 * node + 1 });
  }
}

vec3 TubeSet::partNormal(std::uint32_t part, const dvec3& point) const
{
  const std::uint32_t node = part / 2;
  const dvec3 local = point - Origin;
  if (part % 2 == 0)
    return vec3(local - dvec3(vec3(Nodes[node])));
  return vec3(coneStumpNormal(stumpOf(node), local));
}

vec3 TubeSet::partColor(std::uint32_t part) const
{
  const std::uint32_t c = Colors[part / 2];
  return vec3(float(c & 0xffu), float((c >> 8) & 0xffu), float((c >> 16) & 0xffu)) / 255.0f;
}

vec3 TubeSet::primitiveColor(unsigned primitive) const
{
  return partColor(2 * nodeOf(primitive));
}

std::size_t TubeSet::memoryBytes() const
{
  return Nodes.capacity() * sizeof(vec4) + Predecessors.capacity() * sizeof(std::int32_t) +
    StumpEnds.capacity() * sizeof(std::uint32_t) + Stumps.capacity() * sizeof(StoredStump) +
    Colors.capacity() * sizeof(std::uint32_t) + SourceIndex.capacity() * sizeof(std::uint32_t);
}
} // namespace sightline
