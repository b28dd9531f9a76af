// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/tubes/TubeSet.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace sightline
{
std::string TubeLayout::name() const
{
  if (primitives == Primitives::Chunked)
    return "chunked (" + std::to_string(chunkSize) + " links), on-the-fly";
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

/// A box in the set's frame widened against rounding, moved to the world frame.
Box3 padAndPlace(Box3 box, const dvec3& origin)
{
  const vec3 pad = 1e-6f * (glm::abs(box.lower) + glm::abs(box.upper) + vec3(1e-30f));
  box.lower -= pad;
  box.upper += pad;
  return Box3{ vec3(origin + dvec3(box.lower)), vec3(origin + dvec3(box.upper)) };
}

/// The nearest surface among a primitive's parts in (tmin, tmax): an interval's entry, or its
/// exit when the ray starts inside. Every layout tests its parts through this, so they agree.
struct NearestPart
{
  dvec3 o, d;
  double tmin, best;
  dvec3 normal{ 0.0 };
  std::uint32_t part = SurfaceHit::kNoPart;

  void sphere(const vec4& node, std::uint32_t p)
  {
    const dvec3 center = dvec3(vec3(node));
    double t0, t1;
    if (sphereInterval(center, node.w, o, d, -1e300, 1e300, t0, t1))
      consider(t0, t1, p, [&](const dvec3& x) { return x - center; });
  }
  void stump(const ConeStump& k, std::uint32_t p)
  {
    double t0, t1;
    if (coneStumpInterval(k, o, d, -1e300, 1e300, t0, t1))
      consider(t0, t1, p, [&](const dvec3& x) { return coneStumpNormal(k, x); });
  }
  template <class NormalAt>
  void consider(double t0, double t1, std::uint32_t p, NormalAt normalAt)
  {
    const double t = t0 > tmin ? t0 : t1;
    if (t > tmin && t < best)
    {
      best = t;
      normal = normalAt(o + t * d);
      part = p;
    }
  }
  bool report(double tmax, SurfaceHit& hit) const
  {
    if (part == SurfaceHit::kNoPart || !(best < tmax))
      return false;
    hit.t = best;
    hit.normal = vec3(normal);
    hit.part = part;
    return true;
  }
};

/// Whether the ray's line misses a link's bounding sphere (the link lies in the hull of its
/// two spheres), or meets it only outside [tmin, tmax]: a cheap test that spares a chunk's
/// links the exact sphere and stump tests, so it is free of square roots (the hot loop of
/// chunked tubes): the sphere about the link's middle of radius |h| + r is enlarged to radius
/// sqrt(2 (|h|^2 + r^2)), which holds it, and padded well beyond double rounding: it only culls.
/// `inverseDD` is 1 / (d . d).
inline bool linkMissed(const dvec3& o, const dvec3& d, double inverseDD, double tmin, double tmax,
  const vec4& a, const vec4& b)
{
  const dvec3 pa = dvec3(vec3(a)), pb = dvec3(vec3(b));
  const dvec3 h = 0.5 * (pb - pa);
  const dvec3 f = pa + h - o;
  const double r = std::max(double(a.w), double(b.w));
  const double ff = glm::dot(f, f);
  const double reach2 = 2.0 * (glm::dot(h, h) + r * r) * (1.0 + 1e-8) + 1e-17 * ff + 1e-300;
  const double tc = glm::dot(f, d) * inverseDD;
  const dvec3 off = f - tc * d;
  if (glm::dot(off, off) > reach2)
    return true;
  // Along the ray the sphere spans tc +- reach / |d|.
  const double before = tmin - tc, after = tc - tmax;
  return (after > 0.0 && after * after > reach2 * inverseDD) ||
    (before > 0.0 && before * before > reach2 * inverseDD);
}

/// Whether the ray's line passes farther than `reach` from the segment [p0, p1]: a chunk's
/// capsule (closeChunk), which spares its links the culling tests of linkMissed.
inline bool capsuleMissed(const dvec3& o, const dvec3& d, double inverseDD, const vec3& p0,
  const vec3& p1, float reach)
{
  // Distances across the ray: the components perpendicular to d.
  const dvec3 a = dvec3(p0), u = dvec3(p1) - a;
  const dvec3 w = a - o;
  const dvec3 wp = w - (glm::dot(w, d) * inverseDD) * d, up = u - (glm::dot(u, d) * inverseDD) * d;
  const double uu = glm::dot(up, up);
  const double s = uu > 0.0 ? std::clamp(-glm::dot(wp, up) / uu, 0.0, 1.0) : 0.0;
  const dvec3 off = wp + s * up;
  const double r = double(reach);
  return glm::dot(off, off) > r * r * (1.0 + 1e-9);
}

ConeStump linkStump(const vec4& a, const vec4& b)
{
  return makeConeStump(dvec3(vec3(a)), a.w, dvec3(vec3(b)), b.w);
}
} // namespace

TubeSet::TubeSet(const std::vector<vec3>& points, const std::vector<float>& radii,
  const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors,
  TubeLayout layout)
  : Layout(layout)
{
  construct(points, radii, predecessors, colors);
}

TubeSet::TubeSet(const dvec3& origin, const std::vector<vec3>& points, const std::vector<float>& radii,
  const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors,
  TubeLayout layout)
  : Layout(layout)
{
  // Before the chunks are built: a compact chunk may anchor at the world origin (-Origin).
  if (!(std::isfinite(origin.x) && std::isfinite(origin.y) && std::isfinite(origin.z)))
    throw std::invalid_argument("sightline::TubeSet: the origin must be finite");
  Origin = origin;
  construct(points, radii, predecessors, colors);
}

void TubeSet::construct(const std::vector<vec3>& points, const std::vector<float>& radii,
  const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors)
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
  if (Layout.primitives == TubeLayout::Primitives::Chunked)
  {
    if (Layout.chunkSize < 1)
      throw std::invalid_argument("sightline::TubeSet: a chunk holds at least one link");
    Layout.transforms = TubeLayout::Transforms::OnTheFly; // chunks derive their stumps
  }
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
  NodeCount = Nodes.size();
  if (Layout.primitives == TubeLayout::Primitives::Chunked)
    buildChunks(); // (AllBounds grows chunk by chunk)
  else
    AllBounds = primitiveBoundsUnion();
}

Box3 TubeSet::primitiveBoundsUnion() const
{
  // A box per primitive (10^8 chunks and more for a whole brain): on every core, not one.
  return tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, size(), 4096), Box3{},
    [this](const tbb::blocked_range<std::size_t>& range, Box3 box)
    {
      for (std::size_t i = range.begin(); i < range.end(); ++i)
        box.extend(bounds(unsigned(i)));
      return box;
    },
    [](Box3 a, const Box3& b)
    {
      a.extend(b);
      return a;
    });
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
  const std::int32_t p = predecessorOf(node);
  if (p < 0)
    return ConeStump{};
  return linkStump(nodeAt(std::uint32_t(p)), nodeAt(node));
}

Box3 TubeSet::bounds(unsigned primitive) const
{
  if (Chunked)
    return chunkBounds(primitive);
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
  return padAndPlace(box, Origin);
}

bool TubeSet::intersect(unsigned primitive, const DoubleRay& ray, SurfaceHit& hit) const
{
  if (Chunked)
    return intersectChunk(primitive, ray, hit);
  // The nearest surface of the primitive's sphere and stump in (tnear, tfar), in the set's
  // frame (t is the same there).
  const std::uint32_t node = nodeOf(primitive);
  const double tmax = std::min(ray.tfar, 1e300);
  NearestPart nearest{ ray.origin - Origin, ray.direction, ray.tnear, tmax };
  if (primitive < Nodes.size())
    nearest.sphere(Nodes[node], 2 * node);
  if (primitive >= Nodes.size() || Layout.primitives == TubeLayout::Primitives::Combined)
    nearest.stump(stumpOf(node), 2 * node + 1);
  return nearest.report(tmax, hit);
}

void TubeSet::insideIntervals(unsigned primitive, const DoubleRay& ray, std::vector<InsideInterval>& out) const
{
  // The whole line (t_r0 = -inf, Section 4.3.1), so a ray starting inside a tube knows it.
  if (Chunked)
    return chunkIntervals(primitive, ray, out);
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
    return vec3(local - dvec3(vec3(nodeAt(node))));
  return vec3(coneStumpNormal(stumpOf(node), local));
}

vec3 TubeSet::partColor(std::uint32_t part) const
{
  const std::uint32_t c = Colors[part / 2];
  return vec3(float(c & 0xffu), float((c >> 8) & 0xffu), float((c >> 16) & 0xffu)) / 255.0f;
}

vec3 TubeSet::primitiveColor(unsigned primitive) const
{
  return partColor(2 * nodeOfPrimitive(primitive));
}

std::uint32_t TubeSet::selectionIndex(unsigned primitive, std::uint32_t part) const
{
  if (!Chunked)
    return primitive;
  const std::uint32_t node = part != SurfaceHit::kNoPart ? part / 2 : Chunks[primitive].firstNode;
  return SelectedNode.empty() ? node : SelectedNode[node];
}

std::int32_t TubeSet::predecessorOf(std::uint32_t node) const
{
  if (!Chunked)
    return Predecessors[node];
  const std::uint32_t chunk = chunkOf(node);
  return node == Chunks[chunk].firstNode ? Chunks[chunk].predecessor : std::int32_t(node) - 1;
}

void TubeSet::buildChunks()
{
  // A chunk ends before a node that does not link to the node before it (a tube's start, a
  // branch, a point whose predecessor was dropped) and after chunkSize nodes: its members'
  // links are implicit. Its first node keeps its link to wherever it starts from.
  const std::vector<vec4> nodes = std::move(Nodes);
  const std::vector<std::int32_t> predecessors = std::move(Predecessors);
  Nodes = {};
  Predecessors = {};
  Chunked = true;
  NodeCount = 0;
  // The exact chunk count first (appendChunkNode's rule), so that the tables and positions are
  // reserved once at their size: a grown vector's trim would copy it at the peak.
  std::size_t chunks = 0;
  for (std::size_t i = 0, run = 0; i < nodes.size(); ++i)
  {
    run = predecessors[i] == std::int32_t(i) - 1 && run > 0 && run < Layout.chunkSize ? run + 1 : 1;
    chunks += run == 1;
  }
  Chunks.reserve(chunks + 1);
  ReserveHint = nodes.size();
  ChunkHint = chunks;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    appendChunkNode(vec3(nodes[i]), nodes[i].w, predecessors[i]);
  finishChunks();
}

void TubeSet::appendChunkNode(const vec3& position, float radius, std::int32_t predecessor)
{
  // While building, the chunk tables hold one entry per chunk; the last chunk is open.
  const std::uint32_t node = std::uint32_t(NodeCount);
  const bool joins = !Chunks.empty() && predecessor == std::int32_t(node) - 1 &&
    node - Chunks.back().firstNode < Layout.chunkSize;
  if (!joins)
  {
    closeChunk();
    Chunks.push_back(ChunkEntry{ node, predecessor, std::uint32_t(Radii.size()), 0, 0.0f });
  }
  OpenPositions.push_back(position);
  Radii.push_back(radius);
  ++NodeCount;
}

void TubeSet::appendLinkedNodes(const vec3* points, const float* radii, std::size_t count)
{
  // appendChunkNode's chunks for the same nodes, each stored as soon as it is complete: no
  // copy through the open chunk, and one pass per chunk (the streamed build's hot path).
  closeChunk();
  const std::size_t size = Layout.chunkSize;
  for (std::size_t k = 0; k < count; k += size)
  {
    const std::size_t m = std::min(size, count - k);
    const std::uint32_t node = std::uint32_t(NodeCount + k);
    Chunks.push_back(ChunkEntry{ node, k > 0 ? std::int32_t(node) - 1 : -1, std::uint32_t(Radii.size()), 0, 0.0f });
    if (std::all_of(radii + k + 1, radii + k + m, [&](float v) { return v == radii[k]; }))
      Radii.push_back(radii[k]);
    else
      Radii.insert(Radii.end(), radii + k, radii + k + m);
    const vec4 start = k > 0 ? vec4(points[k - 1], radii[k - 1]) : vec4(0.0f);
    storeChunk(points + k, radii + k, m, k > 0 ? &start : nullptr);
  }
  NodeCount += count;
}

void TubeSet::storeChunk(const vec3* positions, const float* radii, std::size_t count, const vec4* start)
{
  // The capsule about the segment from the chunk's first to last node that holds all its
  // spheres (its first link's start too) holds its links (each in the hull of its spheres).
  // The boxes of the same spheres hold the chunk (chunkBounds): their union is the set's, kept
  // here rather than in a pass over 10^8 chunks after the build.
  const dvec3 p0 = dvec3(positions[0]), axis = dvec3(positions[count - 1]) - p0;
  const double length2 = glm::dot(axis, axis);
  const double inverse = length2 > 0.0 ? 1.0 / length2 : 0.0;
  auto distance2 = [&](const vec3& center)
  {
    const dvec3 w = dvec3(center) - p0;
    const dvec3 d = w - std::clamp(glm::dot(w, axis) * inverse, 0.0, 1.0) * axis;
    return glm::dot(d, d);
  };
  double reach = 0.0;
  Box3 box;
  if (start)
    box.extend(sphereBox(*start));
  if (std::all_of(radii + 1, radii + count, [&](float v) { return v == radii[0]; }) &&
    (!start || start->w == radii[0]))
  {
    // One radius: the farthest centre decides, one square root (the same value as below).
    double farthest = start ? distance2(vec3(*start)) : 0.0;
    vec3 lower = positions[0], upper = positions[0];
    for (std::size_t i = 0; i < count; ++i)
    {
      farthest = std::max(farthest, distance2(positions[i]));
      lower = glm::min(lower, positions[i]);
      upper = glm::max(upper, positions[i]);
    }
    reach = std::sqrt(farthest) + double(radii[0]);
    box.extend(Box3{ lower - vec3(radii[0]), upper + vec3(radii[0]) });
  }
  else
  {
    for (std::size_t i = 0; i < count; ++i)
    {
      reach = std::max(reach, std::sqrt(distance2(positions[i])) + double(radii[i]));
      box.extend(sphereBox(vec4(positions[i], radii[i])));
    }
    if (start)
      reach = std::max(reach, std::sqrt(distance2(vec3(*start))) + double(start->w));
  }
  // Rounded up, and padded against the rounding of the test (linkMissed's padding).
  reach += 1e-7 * (reach + std::sqrt(length2) + glm::length(p0)) + 1e-30;
  Chunks.back().reach = std::nextafter(float(reach), kInfinity);
  AllBounds.extend(padAndPlace(box, Origin));

  // Per axis, the first anchor from which every position comes back exactly as anchor + the
  // float16 nearest its offset: the chunk's first point (offsets within a chunk are small),
  // the world origin in the set's frame (then the offsets are the world positions: exact for
  // float16 files when Origin is a float, see SightlineKernelConversions::ToLocalFrame), zero.
  vec3 anchor(0.0f);
  // Compact costs 6 bytes a node and 12 for the anchor: less than 12 a node from 3 nodes on.
  bool compact = count > 2;
  // The first point on every axis is the anchor of nearly every chunk: tried in one pass over
  // all the offsets at once, encoded by the CPU's conversion where it has one.
  constexpr std::size_t kAtOnce = 32;
  std::uint16_t halves[3 * kAtOnce];
  bool encoded = false;
  if (compact && count <= kAtOnce)
  {
    float offsets[3 * kAtOnce];
    bool exact = true;
    for (std::size_t i = 0; i < count; ++i)
      for (int axis = 0; axis < 3; ++axis)
      {
        const float offset = positions[i][axis] - positions[0][axis];
        offsets[3 * i + std::size_t(axis)] = offset;
        exact &= positions[0][axis] + offset == positions[i][axis];
      }
    encoded = exact && halvesOfExact(offsets, 3 * count, halves);
    if (encoded)
      anchor = positions[0];
  }
  for (int axis = 0; axis < 3 && compact && !encoded; ++axis)
  {
    const float world = float(-Origin[axis]);
    const float candidates[3] = { positions[0][axis], double(world) == -Origin[axis] ? world : 0.0f, 0.0f };
    compact = false;
    for (float a : candidates)
    {
      compact = std::all_of(positions, positions + count,
        [&](const vec3& p)
        {
          const float offset = p[axis] - a;
          return halfHolds(offset) && a + offset == p[axis];
        });
      if (compact)
      {
        anchor[axis] = a;
        break;
      }
    }
  }
  // A size() past the top bit would be taken for a compact chunk's start.
  auto first = [](std::size_t index)
  {
    if (index >= kCompactChunk)
      throw std::length_error("sightline::TubeSet: more chunk positions than 2^31 entries");
    return std::uint32_t(index);
  };
  if (compact)
  {
    reservePositions(true);
    Chunks.back().positions = kCompactChunk | first(Compact.size());
    Half3 bits[2];
    static_assert(sizeof(bits) == sizeof(vec3), "an anchor is two entries");
    std::memcpy(bits, &anchor, sizeof(bits));
    Compact.push_back(bits[0]);
    Compact.push_back(bits[1]);
    for (std::size_t i = 0; i < count; ++i)
    {
      const vec3& p = positions[i];
      Compact.push_back(encoded ? Half3{ { halves[3 * i], halves[3 * i + 1], halves[3 * i + 2] } }
                                : Half3{ { halfOfExact(p.x - anchor.x), halfOfExact(p.y - anchor.y),
                                    halfOfExact(p.z - anchor.z) } });
    }
  }
  else
  {
    reservePositions(false);
    Chunks.back().positions = first(Wide.size());
    Wide.insert(Wide.end(), positions, positions + count);
  }
}

void TubeSet::reservePositions(bool compact)
{
  // Once, at the full size a builder expects (each compact chunk adds an anchor of 2 entries).
  if (ReserveHint == 0)
    return;
  if (compact && Compact.empty())
    Compact.reserve(ReserveHint + 2 * ChunkHint);
  if (!compact && Wide.empty())
    Wide.reserve(ReserveHint);
}

void TubeSet::appendChunks(const TubeSet& part)
{
  closeChunk();
  const std::uint32_t nodes = std::uint32_t(NodeCount), radii = std::uint32_t(Radii.size());
  const std::size_t compact = Compact.size(), wide = Wide.size();
  if (compact + part.Compact.size() >= kCompactChunk || wide + part.Wide.size() >= kCompactChunk)
    throw std::length_error("sightline::TubeSet: more chunk positions than 2^31 entries");
  for (ChunkEntry entry : part.Chunks)
  {
    entry.firstNode += nodes;
    if (entry.predecessor >= 0)
      entry.predecessor += std::int32_t(nodes);
    entry.firstRadius += radii;
    entry.positions = entry.positions & kCompactChunk
      ? kCompactChunk | (std::uint32_t(compact) + (entry.positions & ~kCompactChunk))
      : std::uint32_t(wide) + entry.positions;
    Chunks.push_back(entry);
  }
  if (!part.Compact.empty())
    reservePositions(true);
  if (!part.Wide.empty())
    reservePositions(false);
  Compact.insert(Compact.end(), part.Compact.begin(), part.Compact.end());
  Wide.insert(Wide.end(), part.Wide.begin(), part.Wide.end());
  Radii.insert(Radii.end(), part.Radii.begin(), part.Radii.end());
  NodeCount += part.NodeCount;
  Links += part.Links;
  AllBounds.extend(part.AllBounds);
}

void TubeSet::clearChunks()
{
  Chunks.clear();
  Compact.clear();
  Wide.clear();
  Radii.clear();
  OpenPositions.clear();
  NodeCount = 0;
  Links = 0;
  AllBounds = Box3{};
}

void TubeSet::closeChunk()
{
  if (OpenPositions.empty())
    return;
  const std::size_t r = Chunks.back().firstRadius;
  const bool constant = std::all_of(Radii.begin() + std::ptrdiff_t(r), Radii.end(), [&](float v) { return v == Radii[r]; });
  // The open chunk holds a radius per node: one is kept where they are all equal.
  vec4 start;
  const bool linked = chunkStart(unsigned(Chunks.size() - 1), start);
  storeChunk(OpenPositions.data(), Radii.data() + r, OpenPositions.size(), linked ? &start : nullptr);
  OpenPositions.clear();
  if (constant)
    Radii.resize(r + 1);
}

void TubeSet::finishChunks()
{
  closeChunk();
  Chunks.push_back(ChunkEntry{ std::uint32_t(NodeCount), -1, std::uint32_t(Radii.size()), 0, 0.0f });
  OpenPositions = {};
  ReserveHint = ChunkHint = 0;
  // Vectors grown by push_back hold up to twice their size: give the slack back. The large
  // ones (6 GB of positions and 1.4 GB of chunk entries at 10^9 links) would be copied at the
  // peak: those only where the slack is large (a builder reserves them; the chunk count is a
  // guess there).
  auto trim = [](auto& v, std::size_t slackDivisor)
  {
    if (v.capacity() > v.size() + v.size() / slackDivisor)
      v.shrink_to_fit();
  };
  trim(Compact, 8);
  trim(Wide, 8);
  trim(Colors, 8);
  trim(SourceIndex, 8);
  trim(Chunks, 4);
  Radii.shrink_to_fit();
}

std::size_t TubeSet::compactChunkCount() const
{
  return std::size_t(std::count_if(Chunks.begin(), Chunks.end() - (Chunks.empty() ? 0 : 1),
    [](const ChunkEntry& c) { return (c.positions & kCompactChunk) != 0; }));
}

TubeSet::ChunkPoints TubeSet::pointsOf(unsigned chunk) const
{
  ChunkPoints points;
  const std::uint32_t start = Chunks[chunk].positions;
  if (start & kCompactChunk)
  {
    const Half3* entries = Compact.data() + (start & ~kCompactChunk);
    std::memcpy(&points.anchor, entries, sizeof(vec3));
    points.offsets = entries + 2;
  }
  else
    points.wide = Wide.data() + start;
  return points;
}

void TubeSet::prefetchChunk(unsigned chunk) const
{
  for (unsigned c = chunk > 0 ? chunk - 1 : 0; c <= chunk; ++c)
  {
    const std::uint32_t start = Chunks[c].positions;
    __builtin_prefetch(start & kCompactChunk ? static_cast<const void*>(Compact.data() + (start & ~kCompactChunk))
                                             : static_cast<const void*>(Wide.data() + start));
    __builtin_prefetch(Radii.data() + Chunks[c].firstRadius);
  }
}

bool TubeSet::chunkStart(unsigned chunk, vec4& start) const
{
  const std::int32_t first = Chunks[chunk].predecessor;
  if (first < 0)
    return false;
  if (chunk > 0 && std::uint32_t(first) + 1 == Chunks[chunk].firstNode)
  {
    // The previous chunk's last node: a tube going on (the usual case, no search).
    const std::uint32_t begin = Chunks[chunk - 1].firstNode;
    const std::uint32_t r = Chunks[chunk - 1].firstRadius, count = Chunks[chunk].firstRadius - r;
    start = vec4(pointsOf(chunk - 1)[std::uint32_t(first) - begin],
      Radii[count == 1 ? r : r + std::uint32_t(first) - begin]);
  }
  else
    start = nodeAt(std::uint32_t(first));
  return true;
}

std::uint32_t TubeSet::chunkOf(std::uint32_t node) const
{
  const auto after = std::upper_bound(Chunks.begin(), Chunks.end(), node,
    [](std::uint32_t n, const ChunkEntry& c) { return n < c.firstNode; });
  return std::uint32_t(after - Chunks.begin()) - 1;
}

vec4 TubeSet::nodeAt(std::uint32_t node) const
{
  if (!Chunked)
    return Nodes[node];
  const std::uint32_t chunk = chunkOf(node);
  const std::uint32_t r = Chunks[chunk].firstRadius, count = Chunks[chunk + 1].firstRadius - r;
  return vec4(pointsOf(chunk)[node - Chunks[chunk].firstNode], Radii[count == 1 ? r : r + node - Chunks[chunk].firstNode]);
}

namespace
{
/// Calls visit(node, its point and radius, its predecessor's or null) for each link of a chunk.
template <class Points, class Radii, class Visit>
void forEachChunkLink(const Points& positions, const Radii& radii,
  std::uint32_t begin, std::uint32_t end, bool linked, std::uint32_t radiusStart,
  bool constant, const vec4& start, Visit&& visit)
{
  vec4 previous = start;
  for (std::uint32_t node = begin; node < end; ++node)
  {
    const vec4 point(positions[node - begin], radii[constant ? radiusStart : radiusStart + node - begin]);
    visit(node, point, node > begin || linked ? &previous : nullptr);
    previous = point;
  }
}
} // namespace

Box3 TubeSet::chunkBounds(unsigned chunk) const
{
  const std::uint32_t begin = Chunks[chunk].firstNode, end = Chunks[chunk + 1].firstNode;
  // A link's stump lies in the hull of its spheres: the boxes of the chunk's spheres and of
  // its first link's start hold all its links.
  Box3 box;
  vec4 start;
  if (chunkStart(chunk, start))
    box.extend(sphereBox(start));
  const std::uint32_t r = Chunks[chunk].firstRadius;
  const bool constant = Chunks[chunk + 1].firstRadius - r == 1;
  const ChunkPoints points = pointsOf(chunk);
  for (std::uint32_t node = begin; node < end; ++node)
    box.extend(sphereBox(vec4(points[node - begin], Radii[constant ? r : r + node - begin])));
  return padAndPlace(box, Origin);
}

bool TubeSet::intersectChunk(unsigned chunk, const DoubleRay& ray, SurfaceHit& hit) const
{
  // The nearest surface over the chunk's links, each tested as a combined primitive is.
  const double tmax = std::min(ray.tfar, 1e300);
  NearestPart nearest{ ray.origin - Origin, ray.direction, ray.tnear, tmax };
  const double inverseDD = 1.0 / glm::dot(ray.direction, ray.direction);
  const ChunkPoints points = pointsOf(chunk);
  const std::uint32_t count = Chunks[chunk + 1].firstNode - Chunks[chunk].firstNode;
  if (capsuleMissed(nearest.o, nearest.d, inverseDD, points[0], points[count - 1], Chunks[chunk].reach))
    return false;
  vec4 start(0.0f);
  const bool linked = chunkStart(chunk, start);
  const std::uint32_t r = Chunks[chunk].firstRadius;
  forEachChunkLink(points, Radii, Chunks[chunk].firstNode, Chunks[chunk + 1].firstNode, linked, r,
    Chunks[chunk + 1].firstRadius - r == 1, start,
    [&](std::uint32_t node, const vec4& point, const vec4* start)
    {
      if (linkMissed(nearest.o, nearest.d, inverseDD, nearest.tmin, nearest.best, start ? *start : point, point))
        return;
      nearest.sphere(point, 2 * node);
      if (start)
        nearest.stump(linkStump(*start, point), 2 * node + 1);
    });
  return nearest.report(tmax, hit);
}

void TubeSet::chunkIntervals(unsigned chunk, const DoubleRay& ray, std::vector<InsideInterval>& out) const
{
  const dvec3 o = ray.origin - Origin, d = ray.direction;
  const double inverseDD = 1.0 / glm::dot(d, d);
  const ChunkPoints points = pointsOf(chunk);
  const std::uint32_t count = Chunks[chunk + 1].firstNode - Chunks[chunk].firstNode;
  if (capsuleMissed(o, d, inverseDD, points[0], points[count - 1], Chunks[chunk].reach))
    return;
  vec4 start(0.0f);
  const bool linked = chunkStart(chunk, start);
  const std::uint32_t r = Chunks[chunk].firstRadius;
  forEachChunkLink(points, Radii, Chunks[chunk].firstNode, Chunks[chunk + 1].firstNode, linked, r,
    Chunks[chunk + 1].firstRadius - r == 1, start,
    [&](std::uint32_t node, const vec4& point, const vec4* start)
    {
      if (linkMissed(o, d, inverseDD, -1e300, 1e300, start ? *start : point, point))
        return;
      double t0, t1;
      if (sphereInterval(dvec3(vec3(point)), point.w, o, d, -1e300, 1e300, t0, t1))
        out.push_back({ t0, t1, chunk, 2 * node });
      if (start && coneStumpInterval(linkStump(*start, point), o, d, -1e300, 1e300, t0, t1))
        out.push_back({ t0, t1, chunk, 2 * node + 1 });
    });
}

std::size_t TubeSet::memoryBytes() const
{
  return Nodes.capacity() * sizeof(vec4) + Predecessors.capacity() * sizeof(std::int32_t) +
    StumpEnds.capacity() * sizeof(std::uint32_t) + Stumps.capacity() * sizeof(StoredStump) +
    Colors.capacity() * sizeof(std::uint32_t) + SourceIndex.capacity() * sizeof(std::uint32_t) +
    SelectedNode.capacity() * sizeof(std::uint32_t) +
    Compact.capacity() * sizeof(Half3) + Wide.capacity() * sizeof(vec3) +
    Chunks.capacity() * sizeof(ChunkEntry) + Radii.capacity() * sizeof(float);
}
} // namespace sightline

namespace sightline
{
TubeRunBuilder::TubeRunBuilder(const dvec3& origin, unsigned chunkSize, bool withColors)
  : Set(new TubeSet())
  , WithColors(withColors)
{
  if (!(std::isfinite(origin.x) && std::isfinite(origin.y) && std::isfinite(origin.z)))
    throw std::invalid_argument("sightline::TubeRunBuilder: the origin must be finite");
  if (chunkSize < 1)
    throw std::invalid_argument("sightline::TubeRunBuilder: a chunk holds at least one link");
  Set->Origin = origin;
  Set->Layout.primitives = TubeLayout::Primitives::Chunked;
  Set->Layout.transforms = TubeLayout::Transforms::OnTheFly;
  Set->Layout.chunkSize = chunkSize;
  Set->Chunked = true;
}

void TubeRunBuilder::reserve(std::size_t points, std::size_t runs)
{
  // The positions reserve when their first chunk is stored; tubes end a chunk early: where the
  // runs are not known, allow for one end in 48 points (streamlines of 20-200 mm at 0.5-1 mm
  // steps have 40-400).
  Set->ReserveHint = points;
  Set->ChunkHint = points / Set->Layout.chunkSize + (runs > 0 ? runs : points / 48) + 1;
  Set->Chunks.reserve(Set->ChunkHint + 1);
  if (WithColors)
    Set->Colors.reserve(points);
}

void TubeRunBuilder::checkRuns(const std::uint32_t* colors, std::size_t count) const
{
  if (!Set)
    throw std::logic_error("sightline::TubeRunBuilder: runs added after finish()");
  if (count > 0 && (colors != nullptr) != WithColors)
    throw std::invalid_argument(std::string("sightline::TubeRunBuilder: a run ") +
      (WithColors ? "without colours for a builder made with them" : "with colours for a builder made without"));
  if (Given + count >= std::size_t(INT32_MAX))
    throw std::invalid_argument("sightline::TubeRunBuilder: " + std::to_string(Given + count) +
      " points exceed the 2^31 - 1 a tube set indexes");
}

void TubeRunBuilder::addRuns(const vec3* points, const float* radii, const std::uint32_t* colors,
  const std::size_t* runEnds, std::size_t runs, std::size_t slicePoints)
{
  for (std::size_t k = 0; k < runs; ++k)
    if (k > 0 && runEnds[k] < runEnds[k - 1])
      throw std::invalid_argument("sightline::TubeRunBuilder: run end " + std::to_string(k) + " (" +
        std::to_string(runEnds[k]) + ") is before the one before it (" + std::to_string(runEnds[k - 1]) + ")");
  const std::size_t count = runs > 0 ? runEnds[runs - 1] : 0;
  checkRuns(colors, count);
  auto oneByOne = [&]
  {
    for (std::size_t k = 0, begin = 0; k < runs; begin = runEnds[k++])
      addRun(points + begin, radii + begin, colors ? colors + begin : nullptr, runEnds[k] - begin);
  };
  // Storing chunks (their capsules, float16 offsets) is most of a streamed build's time, on
  // one thread while the caller reads the next piece: slices of runs are stored into sets of
  // their own at once, then appended in order. Sets with dropped points keep to one thread
  // (their source indices and reasons go point by point).
  const std::size_t sliceCount = std::min<std::size_t>(runs, count / std::max<std::size_t>(slicePoints, 1));
  if (sliceCount < 2 || Set->Report.rejected > 0)
    return oneByOne();
  // Slice s holds runs firstRun[s] .. firstRun[s + 1] - 1: about as many points each.
  std::vector<std::size_t> firstRun(sliceCount + 1, runs);
  firstRun[0] = 0;
  for (std::size_t s = 1; s < sliceCount; ++s)
    firstRun[s] = std::size_t(std::upper_bound(runEnds, runEnds + runs, count * s / sliceCount) - runEnds);
  while (Slices.size() < sliceCount)
  {
    Slices.push_back(std::unique_ptr<TubeSet>(new TubeSet()));
    Slices.back()->Layout = Set->Layout;
    Slices.back()->Origin = Set->Origin;
    Slices.back()->Chunked = true;
  }
  std::atomic<bool> dropped{ false };
  tbb::parallel_for(std::size_t(0), sliceCount, [&](std::size_t s)
    {
      TubeSet& part = *Slices[s];
      part.clearChunks();
      const std::size_t begin = firstRun[s] > 0 ? runEnds[firstRun[s] - 1] : 0;
      const std::size_t end = firstRun[s + 1] > 0 ? runEnds[firstRun[s + 1] - 1] : 0;
      for (std::size_t i = begin; i < end; ++i)
        if (!(isFinite(points[i]) && std::isfinite(radii[i]) && radii[i] >= 0.0f))
        {
          dropped = true;
          return;
        }
      part.ReserveHint = end - begin;
      part.ChunkHint = (end - begin) / part.Layout.chunkSize + (firstRun[s + 1] - firstRun[s]) + 1;
      part.Chunks.reserve(part.ChunkHint);
      for (std::size_t k = firstRun[s], from = begin; k < firstRun[s + 1]; from = runEnds[k++])
        if (runEnds[k] > from)
        {
          part.appendLinkedNodes(points + from, radii + from, runEnds[k] - from);
          part.Links += runEnds[k] - from - 1;
        }
    });
  if (dropped)
    return oneByOne();
  for (std::size_t s = 0; s < sliceCount; ++s)
    Set->appendChunks(*Slices[s]);
  if (colors)
    Set->Colors.insert(Set->Colors.end(), colors, colors + count);
  Given += count;
}

void TubeRunBuilder::addRun(
  const vec3* points, const float* radii, const std::uint32_t* colors, std::size_t count)
{
  checkRuns(colors, count);
  TubeSet& set = *Set;
  const std::size_t given = Given;
  Given += count;
  // Stretches of good points, each a tube of its own: a bad point ends the tube before it.
  for (std::size_t i = 0; i < count;)
  {
    std::size_t end = i;
    while (end < count && isFinite(points[end]) && std::isfinite(radii[end]) && radii[end] >= 0.0f)
      ++end;
    if (end > i)
    {
      set.appendLinkedNodes(points + i, radii + i, end - i);
      set.Links += end - i - 1;
      if (colors)
        set.Colors.insert(set.Colors.end(), colors + i, colors + end);
      if (set.Report.rejected > 0)
        for (std::size_t k = i; k < end; ++k)
          SourceIndex.push_back(std::uint32_t(given + k));
    }
    if (end == count)
      break;
    // The same reason, worded the same, as the constructor's.
    if (set.Report.rejected++ == 0)
    {
      set.Report.reasons.push_back("point " + std::to_string(given + end) +
        " has a non-finite position or a negative or non-finite radius (first of the points "
        "dropped for this reason, with their links)");
      // Kept nodes so far are the points given so far, in order.
      SourceIndex.resize(set.NodeCount);
      for (std::size_t k = 0; k < SourceIndex.size(); ++k)
        SourceIndex[k] = std::uint32_t(k);
    }
    i = end + 1;
  }
}

std::shared_ptr<TubeSet> TubeRunBuilder::finish()
{
  if (!Set)
    throw std::logic_error("sightline::TubeRunBuilder: finish() called twice");
  std::shared_ptr<TubeSet> set = std::move(Set);
  Slices.clear(); // (their storage is only for building)
  Slices.shrink_to_fit();
  set->SourceIndex = std::move(SourceIndex);
  set->finishChunks(); // (AllBounds grew chunk by chunk)
  return set;
}
} // namespace sightline
