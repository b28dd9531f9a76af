// SPDX-License-Identifier: BSD-3-Clause
// The chunked tube layout (TubeLayout::Primitives::Chunked) against the combined on-the-fly one
// it must reproduce: the same union of spheres and stumps pixel by pixel (coverage, depth within
// 1e-6 of the radius), the same translucent union, picks that name a link whose own parts give
// the hit, and less memory per link (geometry and BVH).
#include "sightline/core/Camera.h"
#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Renderer.h"
#include "sightline/math/Half.h"
#include "sightline/tubes/TubeBatchBuilder.h"
#include "sightline/tubes/TubeSet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

using namespace sightline;

namespace
{
struct Tubes
{
  std::vector<vec3> points;
  std::vector<float> radii;
  std::vector<std::int64_t> predecessors;
};

/// Streamline-like runs with the cases chunks must handle: constant and varying radii, branches
/// from earlier nodes (predecessor not the node before), zero-length links, a sphere that holds
/// the next one, single-point tubes and runs longer than a chunk.
Tubes randomTubes(unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), r(0.1f, 0.35f);
  Tubes t;
  auto add = [&](const vec3& p, float radius, std::int64_t predecessor)
  {
    t.points.push_back(p);
    t.radii.push_back(radius);
    t.predecessors.push_back(predecessor);
  };
  for (int run = 0; run < 12; ++run)
  {
    const bool constant = run % 2 == 0;
    const float radius = r(rng);
    const int length = 1 + int(rng() % 45u);
    vec3 p(3.0f * u(rng), 3.0f * u(rng), 3.0f * u(rng));
    add(p, radius, -1);
    vec3 step = 0.3f * vec3(u(rng), u(rng), u(rng));
    for (int k = 1; k < length; ++k)
    {
      const std::int64_t last = std::int64_t(t.points.size()) - 1;
      const unsigned kind = rng() % 16u;
      step = 0.8f * step + 0.12f * vec3(u(rng), u(rng), u(rng));
      if (kind == 0) // zero-length link: the same point again
        add(t.points.back(), t.radii.back(), last);
      else if (kind == 1 && !constant) // a sphere inside the next one
        add(t.points.back() + 0.05f * step, t.radii.back() + 0.3f, last);
      else if (kind == 2 && k > 3) // a branch from an earlier node of this run
        add(t.points[std::size_t(last - 2)] + 2.0f * vec3(step.z, step.x, step.y),
          constant ? radius : r(rng), last - 2);
      else
      {
        p = t.points.back() + step;
        add(p, constant ? radius : r(rng), last);
      }
    }
  }
  return t;
}

TubeLayout chunked(unsigned size = TubeLayout::kDefaultChunkSize)
{
  TubeLayout layout;
  layout.primitives = TubeLayout::Primitives::Chunked;
  layout.chunkSize = size;
  return layout;
}

struct View
{
  Camera camera;
  Lighting lighting;
};

/// A camera framing the box; `distance` times farther away with a view angle as much narrower.
View viewOf(const Box3& box, int size, double distance = 1.0)
{
  CameraParameters parameters;
  const dvec3 center = 0.5 * (dvec3(box.lower) + dvec3(box.upper));
  const double extent = glm::length(dvec3(box.upper) - dvec3(box.lower));
  parameters.focalPoint = center;
  parameters.position = center + distance * extent * dvec3(0.3, 0.4, 1.1);
  parameters.viewAngle = 40.0 / distance;
  parameters.farClip = 10.0 * distance * extent;
  const Camera camera = Camera::fromParameters(parameters, size, size);
  return { camera, Lighting::headlight(vec3(glm::normalize(parameters.focalPoint - parameters.position))) };
}

/// Whether combined primitive `node` alone (its sphere and stump) is hit at t.
bool nodeHitAt(const TubeSet& combined, std::uint32_t node, const DoubleRay& ray, double t, double tolerance)
{
  SurfaceHit hit;
  return combined.intersect(node, ray, hit) && std::abs(hit.t - t) <= tolerance;
}

/// Renders both layouts and compares them pixel by pixel; returns the pixels hit.
int compareLayouts(const Tubes& tubes, const dvec3& origin, unsigned chunkSize, double cameraDistance = 1.0)
{
  auto combined = std::make_shared<TubeSet>(origin, tubes.points, tubes.radii, tubes.predecessors);
  auto chunks = std::make_shared<TubeSet>(origin, tubes.points, tubes.radii, tubes.predecessors,
    std::vector<std::uint32_t>{}, chunked(chunkSize));
  EXPECT_EQ(chunks->pointCount(), combined->pointCount());
  EXPECT_EQ(chunks->linkCount(), combined->linkCount());
  EXPECT_LT(chunks->size(), combined->size());
  for (std::uint32_t node = 0; node < combined->pointCount(); ++node)
    EXPECT_EQ(chunks->predecessorOf(node), combined->predecessorOf(node)) << "node " << node;
  EmbreeScene a, b;
  a.add(combined);
  b.add(chunks);
  a.commit();
  b.commit();
  const double tolerance = 1e-6 * 0.1; // the smallest radius of randomTubes
  const View view = viewOf(combined->bounds(), 128, cameraDistance);
  RenderOptions options;
  options.primitiveIds = true;
  Framebuffer fa, fb;
  Renderer().render(a, view.camera, view.lighting, fa, options);
  Renderer().render(b, view.camera, view.lighting, fb, options);
  int hits = 0, samePick = 0;
  for (int py = 0; py < 128; ++py)
    for (int px = 0; px < 128; ++px)
    {
      const std::size_t i = fa.index(px, py);
      const DoubleRay ray = view.camera.doublePrimaryRay(px + 0.5, py + 0.5); // as the renderer's
      SceneHit ha, hb;
      const bool hitA = a.intersect(ray, ha), hitB = b.intersect(ray, hb);
      EXPECT_EQ(hitA, hitB) << "pixel " << px << ", " << py;
      EXPECT_EQ(fa.Color[i].a > 0.0f, fb.Color[i].a > 0.0f) << "pixel " << px << ", " << py;
      if (!hitA || !hitB)
        continue;
      ++hits;
      EXPECT_NEAR(ha.t, hb.t, tolerance) << "pixel " << px << ", " << py;
      EXPECT_EQ(fa.Depth[i], fb.Depth[i]) << "pixel " << px << ", " << py;
      // The pick names a link (node) whose own sphere and stump give this hit.
      const std::uint32_t node = fb.Primitives[i].primitive;
      // So does the link of a single ray's hit (it may be the other one of a tie: a packet
      // visits chunks in another order).
      EXPECT_TRUE(nodeHitAt(*combined, chunks->selectionIndex(hb.primID, hb.part), ray, hb.t, tolerance));
      EXPECT_LT(node, combined->pointCount());
      if (node < combined->pointCount())
      {
        EXPECT_TRUE(nodeHitAt(*combined, node, ray, hb.t, tolerance)) << "pixel " << px << ", " << py;
      }
      EXPECT_EQ(chunks->nodeOfSelection(node), node);
      samePick += fa.Primitives[i].primitive == node;
    }
  // Ties (a duplicated point, a joint) may pick either link; nearly all picks agree.
  EXPECT_GT(samePick, hits * 95 / 100);
  return hits;
}
} // namespace

TEST(TubeChunks, ChunkBoundariesFollowRuns)
{
  // 0-1-2-3-4 a run, 5 branches from 2, 6 continues 5, 7 starts a tube, 8-9 continue it.
  std::vector<vec3> p;
  for (int i = 0; i < 10; ++i)
    p.push_back(vec3(float(i), 0, 0));
  const std::vector<float> radii(10, 0.2f);
  const std::vector<std::int64_t> predecessors{ -1, 0, 1, 2, 3, 2, 5, -1, 7, 8 };
  const TubeSet two(p, radii, predecessors, {}, chunked(2));
  // Chunks of two: [0 1] [2 3] [4] [5 6] [7 8] [9].
  EXPECT_EQ(two.size(), 6u);
  EXPECT_EQ(two.nodeOfPrimitive(3), 5u);
  EXPECT_EQ(two.predecessorOf(5), 2);
  EXPECT_EQ(two.predecessorOf(6), 5);
  EXPECT_EQ(two.predecessorOf(7), -1);
  EXPECT_EQ(two.predecessorOf(9), 8);
  const TubeSet wide(p, radii, predecessors, {}, chunked(8));
  EXPECT_EQ(wide.size(), 3u); // [0..4] [5 6] [7 8 9]
  EXPECT_EQ(wide.layout().name(), "chunked (8 links), on-the-fly");
  EXPECT_THROW(TubeSet(p, radii, predecessors, {}, chunked(0)), std::invalid_argument);
}

TEST(TubeChunks, DrawWhatCombinedLinksDraw)
{
  for (unsigned seed : { 1u, 2u, 3u })
    for (unsigned size : { 4u, TubeLayout::kDefaultChunkSize, 16u })
      EXPECT_GT(compareLayouts(randomTubes(seed), dvec3(0.0), size), 1000) << "seed " << seed;
}

TEST(TubeChunks, DrawWhatCombinedLinksDrawFarFromTheOrigin)
{
  // Points relative to a distant origin, as the mapper gives them: double rays in the set's frame.
  EXPECT_GT(compareLayouts(randomTubes(7), dvec3(4.0e6, -2.5e6, 1.0e6), 8), 1000);
}

namespace
{
/// Tubes whose world positions are float16 values, as a float16 TRX file gives them, placed in
/// a set's frame (relative to `origin`) as the mapper places them.
Tubes float16Tubes(unsigned seed, const dvec3& origin)
{
  Tubes tubes = randomTubes(seed);
  for (vec3& p : tubes.points)
  {
    // World coordinates of a brain (tens of mm, some near 0), rounded to float16.
    dvec3 world;
    for (int axis = 0; axis < 3; ++axis)
      world[axis] = halfToFloat(floatToHalf(12.0f * p[axis] + (axis == 0 ? 0.0f : 31.0f * float(axis))));
    p = vec3(world - origin);
  }
  for (float& r : tubes.radii)
    r *= 12.0f;
  return tubes;
}

/// The chunks of more than two nodes: those a compact store may hold.
std::size_t longChunks(const TubeSet& set)
{
  std::size_t count = 0;
  for (unsigned c = 0; c < set.size(); ++c)
    count += (c + 1 < set.size() ? set.nodeOfPrimitive(c + 1) : set.pointCount()) - set.nodeOfPrimitive(c) > 2;
  return count;
}
} // namespace

TEST(TubeChunks, Float16PositionsAreStoredCompactlyAndDrawTheSame)
{
  // float16 world positions with a float origin: every chunk of three nodes or more is compact
  // (anchored at the world origin if nowhere else), and draws what combined links draw, depth
  // for depth. The same tubes nudged off the float16 grid are stored wide.
  for (unsigned seed : { 3u, 5u })
  {
    const dvec3 origin(6.0, 30.5, 61.25);
    Tubes tubes = float16Tubes(seed, origin);
    EXPECT_GT(compareLayouts(tubes, origin, 8), 1000) << "seed " << seed;
    const TubeSet compact(origin, tubes.points, tubes.radii, tubes.predecessors, {}, chunked(8));
    EXPECT_GT(longChunks(compact), 10u);
    EXPECT_EQ(compact.compactChunkCount(), longChunks(compact)) << "seed " << seed;
    // Every other point a float step off: no offset within a chunk is a float16 any more.
    for (std::size_t i = 0; i < tubes.points.size(); i += 2)
      for (int axis = 0; axis < 3; ++axis)
        tubes.points[i][axis] = std::nextafter(tubes.points[i][axis], kInfinity);
    const TubeSet wide(origin, tubes.points, tubes.radii, tubes.predecessors, {}, chunked(8));
    EXPECT_EQ(wide.compactChunkCount(), 0u) << "seed " << seed;
    EXPECT_GT(wide.memoryBytes(), compact.memoryBytes() + 2 * tubes.points.size());
    EXPECT_GT(compareLayouts(tubes, origin, 8), 1000) << "seed " << seed;
  }
  // An origin that is no float: anchors at a chunk's first point where that is exact, wide
  // where not; the same image either way.
  const dvec3 odd(6.1, 30.3, 61.7);
  EXPECT_GT(compareLayouts(float16Tubes(4, odd), odd, 8), 1000);
}

TEST(TubeChunks, DrawWhatCombinedLinksDrawSeenFromFarAway)
{
  // Rays starting 10^4 extents away (a narrow view): the chunks' capsule and link culls lose
  // nothing to the rounding of distances that large. (From 10^5 extents on, both layouts'
  // hits differ by more than this test's 1e-7: Embree's float ray and the quadratics' rounding
  // at t ~ 10^6, not the culls.)
  EXPECT_GT(compareLayouts(randomTubes(8), dvec3(0.0), 16, 1e4), 1000);
}

TEST(TubeChunks, TranslucentUnionIsTheSame)
{
  const Tubes tubes = randomTubes(11);
  auto combined = std::make_shared<TubeSet>(tubes.points, tubes.radii, tubes.predecessors);
  combined->material.opacity = 0.35f;
  EmbreeScene a, empty;
  a.add(combined);
  a.commit();
  empty.commit();
  const View view = viewOf(combined->bounds(), 96);
  Framebuffer fa;
  RenderOptions options;
  options.translucent.scene = &a;
  Renderer().render(empty, view.camera, view.lighting, fa, options);
  std::shared_ptr<TubeSet> chunks;
  for (unsigned size : { 16u, TubeLayout::kDefaultChunkSize })
  {
    chunks = std::make_shared<TubeSet>(
      tubes.points, tubes.radii, tubes.predecessors, std::vector<std::uint32_t>{}, chunked(size));
    chunks->material.opacity = 0.35f;
    EmbreeScene b;
    b.add(chunks);
    b.commit();
    Framebuffer fb;
    options.translucent.scene = &b;
    Renderer().render(empty, view.camera, view.lighting, fb, options);
    int covered = 0;
    for (std::size_t i = 0; i < fa.pixelCount(); ++i)
    {
      covered += fa.Color[i].a > 0.0f;
      EXPECT_NEAR(fa.Color[i].a, fb.Color[i].a, 1e-6f) << "pixel " << i << ", chunk size " << size;
      EXPECT_NEAR(glm::length(vec3(fa.Color[i]) - vec3(fb.Color[i])), 0.0f, 1e-5f) << "pixel " << i;
    }
    EXPECT_GT(covered, 1000);
  }
  // The intervals of a chunk are those of its links, each naming the link's parts.
  const Ray ray = view.camera.primaryRay(48.5, 48.5);
  std::vector<InsideInterval> ia, ib;
  for (unsigned p = 0; p < combined->size(); ++p)
    combined->insideIntervals(p, ray, ia);
  for (unsigned p = 0; p < chunks->size(); ++p)
    chunks->insideIntervals(p, ray, ib);
  ASSERT_EQ(ia.size(), ib.size());
  for (std::size_t k = 0; k < ia.size(); ++k)
  {
    EXPECT_EQ(ia[k].part, ib[k].part);
    EXPECT_EQ(ia[k].t0, ib[k].t0);
    EXPECT_EQ(ia[k].t1, ib[k].t1);
  }
}

TEST(TubeChunks, ColoursFollowTheLinkHit)
{
  // Two runs in one chunk size: each node's colour shows where its link is hit.
  std::vector<vec3> p;
  std::vector<float> radii;
  std::vector<std::int64_t> predecessors;
  std::vector<std::uint32_t> colors;
  for (int i = 0; i < 8; ++i)
  {
    p.push_back(vec3(float(i) - 3.5f, 0, 0));
    radii.push_back(0.3f);
    predecessors.push_back(i - 1);
    colors.push_back(i % 2 ? packRGBA8(255, 0, 0) : packRGBA8(0, 0, 255));
  }
  auto combined = std::make_shared<TubeSet>(p, radii, predecessors, colors);
  auto chunks = std::make_shared<TubeSet>(p, radii, predecessors, colors, chunked());
  ASSERT_EQ(chunks->size(), 1u);
  EmbreeScene a, b;
  a.add(combined);
  b.add(chunks);
  a.commit();
  b.commit();
  const View view = viewOf(combined->bounds(), 64);
  Framebuffer fa, fb;
  Renderer().render(a, view.camera, view.lighting, fa);
  Renderer().render(b, view.camera, view.lighting, fb);
  int red = 0, blue = 0;
  for (std::size_t i = 0; i < fa.pixelCount(); ++i)
  {
    EXPECT_NEAR(glm::length(vec3(fa.Color[i]) - vec3(fb.Color[i])), 0.0f, 1e-5f) << "pixel " << i;
    red += fb.Color[i].r > 2.0f * fb.Color[i].b;
    blue += fb.Color[i].b > 2.0f * fb.Color[i].r;
  }
  EXPECT_GT(red, 100);
  EXPECT_GT(blue, 100);
}

TEST(TubeChunks, LessMemoryPerLink)
{
  // A tractogram-like set: runs of 100 points of one radius each.
  std::vector<vec3> p;
  std::vector<float> radii;
  std::vector<std::int64_t> predecessors;
  for (int run = 0; run < 100; ++run)
    for (int k = 0; k < 100; ++k)
    {
      p.push_back(vec3(float(k) * 0.1f, float(run % 10), float(run / 10)) + vec3(0, 0.01f * float(k % 3), 0));
      radii.push_back(0.05f);
      predecessors.push_back(k == 0 ? -1 : std::int64_t(p.size()) - 2);
    }
  auto combined = std::make_shared<TubeSet>(p, radii, predecessors);
  auto chunks = std::make_shared<TubeSet>(p, radii, predecessors, std::vector<std::uint32_t>{}, chunked(16));
  // 12 bytes of position per point (tenths are no float16 offsets: wide chunks); per chunk a
  // start, a predecessor, a radius start, a position start, a capsule reach and one radius
  // (constant radius), and the end marker. 100 runs of 100 points: 7 chunks each.
  const std::size_t chunkCount = 100 * 7;
  ASSERT_EQ(chunks->size(), chunkCount);
  EXPECT_EQ(chunks->memoryBytes(), p.size() * 12 + chunkCount * 24 + 20);
  EXPECT_EQ(combined->memoryBytes(), p.size() * 20);
  EmbreeScene a, b;
  a.add(combined);
  b.add(chunks);
  a.commit();
  b.commit();
  EXPECT_LT(b.bvhBytes() * 4, a.bvhBytes());

  // Varying radii keep one per point.
  for (std::size_t i = 0; i < radii.size(); ++i)
    radii[i] = 0.05f + 0.001f * float(i % 7);
  const TubeSet varying(p, radii, predecessors, {}, chunked(16));
  EXPECT_EQ(varying.memoryBytes(), p.size() * 16 + chunkCount * 20 + 20);
}

namespace
{
/// Splits tubes into runs (each point's predecessor the point before, -1 at a run's start), as
/// a tractogram's streamlines are: the input the run builder takes.
Tubes runsOf(const Tubes& tubes)
{
  Tubes runs = tubes;
  for (std::size_t i = 0; i < runs.predecessors.size(); ++i)
    if (runs.predecessors[i] != std::int64_t(i) - 1)
      runs.predecessors[i] = -1;
  return runs;
}

std::shared_ptr<TubeSet> buildRuns(const Tubes& runs, const dvec3& origin, unsigned chunkSize,
  const std::vector<std::uint32_t>& colors = {}, bool reserve = false)
{
  TubeRunBuilder builder(origin, chunkSize, !colors.empty());
  if (reserve)
    builder.reserve(runs.points.size());
  for (std::size_t begin = 0; begin < runs.points.size();)
  {
    std::size_t end = begin + 1;
    while (end < runs.points.size() && runs.predecessors[end] == std::int64_t(end) - 1)
      ++end;
    builder.addRun(runs.points.data() + begin, runs.radii.data() + begin,
      colors.empty() ? nullptr : colors.data() + begin, end - begin);
    EXPECT_EQ(builder.pointsGiven(), end);
    begin = end;
  }
  return builder.finish();
}
/// The same chunks, nodes, links, colours and bounds in `built` as in `reference`.
void expectSameSet(const TubeSet& built, const TubeSet& reference)
{
  ASSERT_EQ(built.size(), reference.size()) << "chunk size " << reference.layout().chunkSize;
  EXPECT_EQ(built.pointCount(), reference.pointCount());
  EXPECT_EQ(built.linkCount(), reference.linkCount());
  EXPECT_EQ(built.report().reasons, reference.report().reasons);
  // The same tables; grown or reserved per-node vectors keep at most an eighth of slack.
  EXPECT_GE(built.memoryBytes(), reference.memoryBytes() * 7 / 8);
  EXPECT_LE(built.memoryBytes(), reference.memoryBytes() * 9 / 8);
  EXPECT_EQ(built.layout().name(), reference.layout().name());
  for (unsigned c = 0; c < built.size(); ++c)
  {
    EXPECT_EQ(built.nodeOfPrimitive(c), reference.nodeOfPrimitive(c));
    EXPECT_EQ(built.bounds(c).lower, reference.bounds(c).lower);
    EXPECT_EQ(built.bounds(c).upper, reference.bounds(c).upper);
  }
  for (std::uint32_t node = 0; node < built.pointCount(); ++node)
  {
    EXPECT_EQ(built.predecessorOf(node), reference.predecessorOf(node)) << "node " << node;
    EXPECT_EQ(built.sourceIndexOf(node), reference.sourceIndexOf(node)) << "node " << node;
    if (reference.hasPrimitiveColors())
    {
      EXPECT_EQ(built.partColor(2 * node), reference.partColor(2 * node));
    }
  }
  EXPECT_EQ(built.hasPrimitiveColors(), reference.hasPrimitiveColors());
  EXPECT_EQ(built.bounds().lower, reference.bounds().lower);
  EXPECT_EQ(built.bounds().upper, reference.bounds().upper);
  // Both grow their bounds chunk by chunk while building: exactly the union of the chunks' boxes.
  Box3 chunks;
  for (unsigned c = 0; c < built.size(); ++c)
    chunks.extend(built.bounds(c));
  EXPECT_EQ(built.bounds().lower, chunks.lower);
  EXPECT_EQ(built.bounds().upper, chunks.upper);
}
} // namespace

TEST(TubeChunks, RunBuilderBuildsWhatTheConstructorBuilds)
{
  // Bad points among the runs: dropped with their links, the run going on as a new tube.
  Tubes runs = runsOf(randomTubes(5));
  runs.points[17].x = NAN;
  runs.radii[40] = -1.0f;
  runs.radii[41] = INFINITY;
  std::vector<std::uint32_t> colors(runs.points.size());
  for (std::size_t i = 0; i < colors.size(); ++i)
    colors[i] = packRGBA8(std::uint8_t(i * 37), std::uint8_t(i * 11), std::uint8_t(i * 5));
  const dvec3 origin(120.0, -40.0, 7.0);
  for (unsigned size : { 1u, 3u, TubeLayout::kDefaultChunkSize })
  {
    const TubeSet reference(origin, runs.points, runs.radii, runs.predecessors, colors, chunked(size));
    const auto built = buildRuns(runs, origin, size, colors, size == 3u);
    EXPECT_EQ(built->report().rejected, 3u);
    expectSameSet(*built, reference);
  }
  // And the images: the built set against the combined layout, pixel by pixel.
  const Tubes clean = runsOf(randomTubes(9));
  const auto built = buildRuns(clean, dvec3(0.0), TubeLayout::kDefaultChunkSize);
  const TubeSet reference(clean.points, clean.radii, clean.predecessors, {}, chunked());
  EXPECT_EQ(built->report().rejected, 0u);
  EXPECT_EQ(built->sourceIndexOf(5), 5u);
  EXPECT_GT(compareLayouts(clean, dvec3(0.0), TubeLayout::kDefaultChunkSize), 1000);
  EmbreeScene a, b;
  a.add(built);
  b.add(std::make_shared<TubeSet>(reference));
  a.commit();
  b.commit();
  const View view = viewOf(reference.bounds(), 96);
  for (int py = 0; py < 96; ++py)
    for (int px = 0; px < 96; ++px)
    {
      const DoubleRay ray = view.camera.doublePrimaryRay(px + 0.5, py + 0.5);
      SceneHit ha, hb;
      ASSERT_EQ(a.intersect(ray, ha), b.intersect(ray, hb)) << "pixel " << px << ", " << py;
      EXPECT_EQ(ha.t, hb.t);
    }
}

TEST(TubeChunks, RunBuilderInSlicesBuildsWhatItBuildsRunByRun)
{
  // addRuns() stores slices of runs on TBB's threads and appends them in order: the same set
  // as addRun() run by run. Slices of a few points, so that each batch has many; runs rounded
  // to float16 in turn, so that both compact and wide chunks are appended.
  Tubes runs = runsOf(randomTubes(11));
  std::vector<std::size_t> ends;
  for (std::size_t i = 1; i <= runs.points.size(); ++i)
    if (i == runs.points.size() || runs.predecessors[i] != std::int64_t(i) - 1)
      ends.push_back(i);
  for (std::size_t k = 0, begin = 0; k < ends.size(); begin = ends[k++])
    if (k % 2 == 0)
      for (std::size_t i = begin; i < ends[k]; ++i)
        for (int axis = 0; axis < 3; ++axis)
          runs.points[i][axis] = halfToFloat(floatToHalf(runs.points[i][axis]));
  ASSERT_GE(ends.size(), 10u);
  std::vector<std::uint32_t> colors(runs.points.size());
  for (std::size_t i = 0; i < colors.size(); ++i)
    colors[i] = packRGBA8(std::uint8_t(i * 29), std::uint8_t(i * 3), std::uint8_t(i * 17));
  const dvec3 origin(8.0, -3.5, 12.25);
  // Two batches (the second's run ends count from its first point), an empty run in each.
  auto build = [&](const Tubes& input, unsigned size, bool colored, std::size_t slicePoints)
  {
    TubeRunBuilder builder(origin, size, colored);
    builder.reserve(input.points.size());
    const std::size_t split = ends.size() / 2, middle = ends[split - 1];
    std::vector<std::size_t> first(ends.begin(), ends.begin() + std::ptrdiff_t(split));
    std::vector<std::size_t> second;
    for (std::size_t k = split; k < ends.size(); ++k)
      second.push_back(ends[k] - middle);
    first.insert(first.begin() + 2, first[1]);
    second.insert(second.begin(), 0);
    builder.addRuns(input.points.data(), input.radii.data(), colored ? colors.data() : nullptr, first.data(),
      first.size(), slicePoints);
    EXPECT_EQ(builder.pointsGiven(), middle);
    builder.addRuns(input.points.data() + middle, input.radii.data() + middle,
      colored ? colors.data() + middle : nullptr, second.data(), second.size(), slicePoints);
    EXPECT_EQ(builder.pointsGiven(), input.points.size());
    return builder.finish();
  };
  for (bool colored : { false, true })
    for (unsigned size : { 1u, 3u, TubeLayout::kDefaultChunkSize })
    {
      const auto reference = buildRuns(runs, origin, size, colored ? colors : std::vector<std::uint32_t>{});
      if (size >= 3u) // (compact from 3 nodes on)
      {
        ASSERT_GT(reference->compactChunkCount(), 0u);
        ASSERT_LT(reference->compactChunkCount(), reference->size());
      }
      for (std::size_t slicePoints : { std::size_t(1), std::size_t(16), std::size_t(1) << 30 })
      {
        SCOPED_TRACE("chunk size " + std::to_string(size) + ", slices of " + std::to_string(slicePoints));
        const auto built = build(runs, size, colored, slicePoints);
        EXPECT_EQ(built->compactChunkCount(), reference->compactChunkCount());
        expectSameSet(*built, *reference);
      }
    }
  // Points to drop: the builder goes run by run, with the same reasons and source indices.
  Tubes bad = runs;
  bad.points[ends[3] + 1].z = NAN;
  bad.radii[ends[8] - 1] = -1.0f;
  const auto reference = buildRuns(bad, origin, 4u, colors);
  const auto built = build(bad, 4u, true, 8);
  EXPECT_EQ(built->report().rejected, 2u);
  expectSameSet(*built, *reference);
}

TEST(TubeChunks, RunBuilderNamesMisuse)
{
  const vec3 points[2] = { vec3(0.0f), vec3(1.0f, 0.0f, 0.0f) };
  const float radii[2] = { 0.1f, 0.1f };
  const std::uint32_t colors[2] = { 0u, 0u };
  EXPECT_THROW(TubeRunBuilder(dvec3(NAN, 0.0, 0.0)), std::invalid_argument);
  EXPECT_THROW(TubeRunBuilder(dvec3(0.0), 0u), std::invalid_argument);
  TubeRunBuilder plain;
  EXPECT_THROW(plain.addRun(points, radii, colors, 2), std::invalid_argument);
  TubeRunBuilder coloured(dvec3(0.0), 8u, true);
  EXPECT_THROW(coloured.addRun(points, radii, nullptr, 2), std::invalid_argument);
  const std::size_t decreasing[2] = { 2, 1 };
  EXPECT_THROW(plain.addRuns(points, radii, nullptr, decreasing, 2), std::invalid_argument);
  EXPECT_THROW(coloured.addRuns(points, radii, nullptr, decreasing + 0, 1), std::invalid_argument);
  EXPECT_EQ(plain.pointsGiven(), 0u);
  plain.addRun(points, radii, nullptr, 2);
  plain.addRun(points, radii, nullptr, 0); // an empty run adds nothing
  const auto set = plain.finish();
  EXPECT_EQ(set->pointCount(), 2u);
  EXPECT_EQ(set->linkCount(), 1u);
  EXPECT_THROW(plain.finish(), std::logic_error);
  EXPECT_THROW(plain.addRun(points, radii, nullptr, 2), std::logic_error);
  // An empty builder gives an empty set.
  EXPECT_EQ(TubeRunBuilder().finish()->size(), 0u);
}

TEST(TubeChunks, BatchBuilderBuildsWhatTheRunBuilderBuilds)
{
  // Bad points too; batches of a few runs each, an empty batch and empty runs among them.
  Tubes runs = runsOf(randomTubes(7));
  runs.points[23].y = NAN;
  runs.radii[60] = -2.0f;
  std::vector<std::uint32_t> colors(runs.points.size());
  for (std::size_t i = 0; i < colors.size(); ++i)
    colors[i] = packRGBA8(std::uint8_t(i * 13), std::uint8_t(i * 7), std::uint8_t(i * 3));
  const dvec3 origin(-30.0, 5.0, 900.0);
  for (bool colored : { false, true })
  {
    const std::vector<std::uint32_t> none;
    const auto reference = buildRuns(runs, origin, 4u, colored ? colors : none);
    TubeBatchBuilder builder(origin, 4u, colored);
    builder.reserve(runs.points.size());
    TubeBatchBuilder::Batch batch;
    std::size_t runsInBatch = 0, batches = 0;
    batch = builder.add(std::move(batch)); // nothing
    for (std::size_t begin = 0; begin < runs.points.size();)
    {
      std::size_t end = begin + 1;
      while (end < runs.points.size() && runs.predecessors[end] == std::int64_t(end) - 1)
        ++end;
      for (std::size_t i = begin; i < end; ++i)
      {
        batch.points.push_back(runs.points[i]);
        batch.radii.push_back(runs.radii[i]);
        if (colored)
          batch.colors.push_back(colors[i]);
      }
      batch.endRun();
      if (runsInBatch == 1)
        batch.endRun(); // an empty run
      begin = end;
      if (++runsInBatch == 1 + batches % 5 || begin == runs.points.size())
      {
        const std::size_t before = builder.pointsGiven();
        const std::size_t count = batch.points.size();
        batch = builder.add(std::move(batch));
        EXPECT_EQ(builder.pointsGiven(), before + count);
        EXPECT_TRUE(batch.points.empty() && batch.runEnds.empty());
        runsInBatch = 0;
        ++batches;
      }
    }
    EXPECT_GE(batches, 5u);
    EXPECT_EQ(builder.pointsGiven(), runs.points.size());
    const auto built = builder.finish();
    EXPECT_EQ(built->report().rejected, 2u);
    expectSameSet(*built, *reference);
  }
}

TEST(TubeChunks, BatchBuilderNamesMalformedBatches)
{
  TubeBatchBuilder builder;
  TubeBatchBuilder::Batch batch;
  batch.points = { vec3(0.0f), vec3(1.0f, 0.0f, 0.0f) };
  batch.radii = { 0.1f };
  batch.runEnds = { 2 };
  EXPECT_THROW(builder.add(TubeBatchBuilder::Batch(batch)), std::invalid_argument); // a radius short
  batch.radii = { 0.1f, 0.1f };
  batch.colors = { 0u, 0u };
  EXPECT_THROW(builder.add(TubeBatchBuilder::Batch(batch)), std::invalid_argument); // colours unasked
  batch.colors.clear();
  batch.runEnds = { 3 };
  EXPECT_THROW(builder.add(TubeBatchBuilder::Batch(batch)), std::invalid_argument); // past the points
  batch.runEnds = { 2, 1 };
  EXPECT_THROW(builder.add(TubeBatchBuilder::Batch(batch)), std::invalid_argument); // decreasing
  batch.runEnds = { 1 };
  EXPECT_THROW(builder.add(TubeBatchBuilder::Batch(batch)), std::invalid_argument); // a point in no run
  EXPECT_EQ(builder.pointsGiven(), 0u);
  batch.runEnds = { 2 };
  builder.add(std::move(batch));
  const auto set = builder.finish();
  EXPECT_EQ(set->linkCount(), 1u);
  // Errors of building (on the worker: here a batch after finish()) come back from the next call.
  TubeBatchBuilder coloured(dvec3(0.0), 4u, true);
  EXPECT_EQ(coloured.finish()->size(), 0u);
  TubeBatchBuilder::Batch late;
  late.points = { vec3(0.0f), vec3(1.0f, 0.0f, 0.0f) };
  late.radii = { 0.1f, 0.1f };
  late.colors = { 0u, 0u };
  late.endRun();
  coloured.add(std::move(late));
  EXPECT_THROW(coloured.add(TubeBatchBuilder::Batch{}), std::logic_error);
}
