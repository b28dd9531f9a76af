// SPDX-License-Identifier: BSD-3-Clause
// Hidden-link culling (TubeInterior.h): voxels marked covered lie inside a link's solid, and a
// dense set's outer links draw, seen from outside its bounds, exactly what all its links draw:
// colour, depth and picks, pixel by pixel.
#include "sightline/core/Camera.h"
#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Renderer.h"
#include "sightline/tubes/TubeInterior.h"
#include "sightline/tubes/TubeSet.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <thread>
#include <vector>

using namespace sightline;

namespace
{
/// Distance from p to the segment from a to b.
double segmentDistance(const dvec3& p, const dvec3& a, const dvec3& b)
{
  const dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? glm::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

/// Smooth runs of 0.5-unit links inside a ball of radius 5 about `center`, filling it about
/// `fill` times over with tubes of radius 0.3 (every fifth run's radii vary from 0.25 to 0.35),
/// each point coloured by its index.
struct DenseBall
{
  std::vector<vec3> points;
  std::vector<float> radii;
  std::vector<std::int64_t> predecessors;
  std::vector<std::uint32_t> colors;
};

DenseBall denseBall(double fill, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), r(0.25f, 0.35f);
  const double ballVolume = 4.0 / 3.0 * kPi * 125.0, linkVolume = kPi * 0.09 * 0.5;
  const std::size_t links = std::size_t(fill * ballVolume / linkVolume);
  DenseBall ball;
  for (int run = 0; ball.points.size() < links; ++run)
  {
    vec3 p;
    do
      p = 5.0f * vec3(u(rng), u(rng), u(rng));
    while (glm::length(p) > 5.0f);
    vec3 d = glm::normalize(vec3(u(rng), u(rng), u(rng)) + vec3(1e-3f));
    const bool varying = run % 5 == 0;
    for (int k = 0; k < 40 && glm::length(p) <= 5.0f; ++k)
    {
      ball.predecessors.push_back(k == 0 ? -1 : std::int64_t(ball.points.size()) - 1);
      ball.points.push_back(p);
      ball.radii.push_back(varying ? r(rng) : 0.3f);
      ball.colors.push_back(std::uint32_t(ball.points.size() * 2654435761u) | 0xff000000u);
      d = glm::normalize(d + 0.3f * vec3(u(rng), u(rng), u(rng)));
      p += 0.5f * d;
    }
  }
  return ball;
}

std::shared_ptr<TubeSet> chunkedSet(const DenseBall& ball, const dvec3& origin, unsigned chunkSize)
{
  TubeLayout layout;
  layout.primitives = TubeLayout::Primitives::Chunked;
  layout.chunkSize = chunkSize;
  return std::make_shared<TubeSet>(origin, ball.points, ball.radii, ball.predecessors, ball.colors, layout);
}

/// A camera outside the box, looking at its centre from direction `from`.
Camera cameraOutside(const Box3& box, const dvec3& from, int size)
{
  CameraParameters parameters;
  const dvec3 center = 0.5 * (dvec3(box.lower) + dvec3(box.upper));
  const double extent = glm::length(dvec3(box.upper) - dvec3(box.lower));
  parameters.focalPoint = center;
  parameters.position = center + 1.5 * extent * glm::normalize(from);
  parameters.viewUp = std::abs(from.z) > 0.9 * glm::length(from) ? dvec3(0, 1, 0) : dvec3(0, 0, 1);
  parameters.viewAngle = 32.0;
  parameters.nearClip = 0.5 * extent;
  parameters.farClip = 3.0 * extent;
  return Camera::fromParameters(parameters, size, size);
}
} // namespace

TEST(TubeInterior, CoveredVoxelsLieInsideTheLinks)
{
  // A bundle of parallel links along x, axes 0.05 apart (half a voxel) over |y|, |z| <= 0.5,
  // radius 0.8 (the second end 0.7): axis samples cover every voxel about the bundle's core.
  std::vector<std::pair<vec4, vec4>> links;
  for (int j = -10; j <= 10; ++j)
    for (int k = -10; k <= 10; ++k)
      links.emplace_back(vec4(0.0f, 0.05f * j, 0.05f * k, 0.8f), vec4(5.0f, 0.05f * j, 0.05f * k, 0.7f));
  TubeInteriorGrid grid(Box3{ vec3(-2.0f), vec3(7.0f, 2.0f, 2.0f) }, 0.1);
  for (const auto& link : links)
    EXPECT_TRUE(grid.coverLink(link.first, link.second));
  EXPECT_GT(grid.fullBrickCount(), 40u); // 2 x 2 x 12 bricks lie in the core
  // Soundness: a covered box lies in the solids (here: each corner within the smaller radius
  // of some axis).
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> x(-2.0f, 7.0f), yz(-2.0f, 2.0f), size(0.0f, 0.5f);
  int covered = 0;
  for (int i = 0; i < 20000; ++i)
  {
    const vec3 lower(x(rng), yz(rng), yz(rng));
    const Box3 box{ lower, lower + vec3(size(rng)) };
    if (!grid.covers(box))
      continue;
    ++covered;
    for (int corner = 0; corner < 8; ++corner)
    {
      const dvec3 p(corner & 1 ? box.upper.x : box.lower.x, corner & 2 ? box.upper.y : box.lower.y,
        corner & 4 ? box.upper.z : box.lower.z);
      double nearest = 1e30;
      for (const auto& link : links)
        nearest = std::min(nearest, segmentDistance(p, dvec3(vec3(link.first)), dvec3(vec3(link.second))));
      EXPECT_LT(nearest, 0.7) << "corner of box " << i;
    }
  }
  EXPECT_GT(covered, 10);
  // Boxes in the core, away from the ends, are covered; boxes reaching past it are not.
  EXPECT_TRUE(grid.covers(Box3{ vec3(2.4f, -0.2f, -0.1f), vec3(2.6f, 0.2f, 0.1f) }));
  EXPECT_FALSE(grid.covers(Box3{ vec3(2.4f, 0.0f, -0.1f), vec3(2.6f, 0.2f, 1.2f) }));
  EXPECT_FALSE(grid.covers(Box3{ vec3(-3.0f), vec3(-2.5f) })); // outside the grid
  // The summaries (blocks, a bit per brick) answer as the bricks' words do.
  std::vector<Box3> boxes;
  std::vector<bool> answers;
  for (int i = 0; i < 20000; ++i)
  {
    const vec3 lower(x(rng), yz(rng), yz(rng));
    boxes.push_back(Box3{ lower, lower + vec3(2.0f * size(rng)) });
    answers.push_back(grid.covers(boxes.back()));
  }
  grid.summarize();
  int agreed = 0, coveredBoxes = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i)
  {
    agreed += grid.covers(boxes[i]) == answers[i];
    coveredBoxes += answers[i];
  }
  EXPECT_EQ(agreed, int(boxes.size()));
  EXPECT_GT(coveredBoxes, 10);
  // A link thinner than a voxel's diagonal marks nothing.
  TubeInteriorGrid thin(Box3{ vec3(-2.0f), vec3(7.0f, 3.0f, 2.0f) }, 0.1);
  EXPECT_FALSE(thin.coverLink(vec4(0.0f, 0.0f, 0.0f, 0.17f), vec4(5.0f, 0.0f, 0.0f, 0.5f)));
  EXPECT_EQ(thin.fullBrickCount(), 0u);
  EXPECT_THROW(TubeInteriorGrid(Box3{}, 0.1), std::invalid_argument);
  EXPECT_THROW(TubeInteriorGrid(Box3{ vec3(0.0f), vec3(1.0f) }, 0.0), std::invalid_argument);
}

TEST(TubeInterior, BlockSummariesAnswerAsTheirBricksDo)
{
  // A thick bundle along x (axes 0.05 apart over |y|, |z| <= 2, radius 0.8): blocks of 4x4x4
  // bricks (1.6 a side) lie wholly in its covered core.
  TubeInteriorGrid grid(Box3{ vec3(-1.0f, -3.0f, -3.0f), vec3(9.0f, 3.0f, 3.0f) }, 0.1);
  for (int j = -40; j <= 40; ++j)
    for (int k = -40; k <= 40; ++k)
      grid.coverLink(vec4(-0.5f, 0.05f * j, 0.05f * k, 0.8f), vec4(8.5f, 0.05f * j, 0.05f * k, 0.8f));
  // Before summarize(): no block answers, and the bricks' words decide covers(). Each box's
  // truth is covers() of the box grown to whole blocks (edges 1.6 from the grid's corner).
  const double block = 16 * grid.voxel();
  const vec3 corner(-1.0f, -3.0f, -3.0f);
  auto grown = [&](const Box3& box)
  {
    Box3 whole;
    for (int axis = 0; axis < 3; ++axis)
    {
      const double lo = std::floor((double(box.lower[axis]) - corner[axis]) / block);
      const double hi = std::floor((double(box.upper[axis]) - corner[axis]) / block) + 1.0;
      whole.lower[axis] = float(corner[axis] + lo * block + 0.01 * grid.voxel());
      whole.upper[axis] = float(corner[axis] + hi * block - 0.01 * grid.voxel());
    }
    return whole;
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> x(-1.0f, 9.0f), yz(-3.0f, 3.0f), size(0.0f, 4.0f);
  std::vector<Box3> boxes;
  std::vector<bool> truth;
  for (int i = 0; i < 4000; ++i)
  {
    const vec3 lower(x(rng), yz(rng), yz(rng));
    boxes.push_back(Box3{ lower, lower + vec3(size(rng), 0.5f * size(rng), 0.5f * size(rng)) });
    truth.push_back(grid.covers(grown(boxes.back())));
    EXPECT_FALSE(grid.blocksCover(boxes.back()));
  }
  grid.summarize();
  int full = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i)
  {
    EXPECT_EQ(grid.blocksCover(boxes[i]), bool(truth[i])) << "box " << i;
    EXPECT_TRUE(!truth[i] || grid.covers(boxes[i])) << "box " << i;
    full += truth[i];
  }
  EXPECT_GT(full, 40);
  // Boxes spanning several blocks: the whole core, and the core with a sliver past it.
  EXPECT_TRUE(grid.blocksCover(Box3{ vec3(0.7f, -1.3f, -1.3f), vec3(7.0f, 1.3f, 1.3f) }));
  EXPECT_FALSE(grid.blocksCover(Box3{ vec3(0.7f, -1.3f, -1.3f), vec3(7.0f, 1.3f, 2.5f) }));
}

TEST(TubeInterior, OuterLinksDrawWhatAllLinksDraw)
{
  const DenseBall ball = denseBall(160.0, 11);
  for (const dvec3& origin : { dvec3(0.0), dvec3(1000.0, -250.0, 40.0) })
  {
    const auto whole = chunkedSet(ball, origin, 8);
    OuterLinkOptions options;
    options.maximumKept = 1.0; // a ball this small keeps most links; draw it culled anyway
    OuterLinkReport report;
    const auto outer = outerLinks(*whole, options, &report);
    ASSERT_TRUE(outer);
    EXPECT_GT(report.fill, 60.0); // of the bounding box: about half of it is ball
    EXPECT_EQ(report.links, whole->linkCount());
    // The interior of the ball (radius ~3.5 of 5) is hidden: a third of the links or more.
    EXPECT_GT(report.hiddenLinks, whole->pointCount() / 3) << "of " << whole->pointCount();
    EXPECT_LT(outer->linkCount(), whole->linkCount() - report.hiddenLinks / 2);
    EXPECT_EQ(outer->selectionCount(), whole->selectionCount());

    EmbreeScene all, part;
    all.add(whole);
    part.add(outer);
    all.commit();
    part.commit();
    RenderOptions render;
    render.primitiveIds = true;
    for (const dvec3& from : { dvec3(1, 0.3, 0.2), dvec3(-0.2, -1, 0.5), dvec3(0.1, 0.2, -1) })
    {
      const Camera camera = cameraOutside(whole->bounds(), from, 96);
      const Lighting lighting = Lighting::headlight(vec3(-glm::normalize(from)));
      Framebuffer fa, fb;
      Renderer().render(all, camera, lighting, fa, render);
      Renderer().render(part, camera, lighting, fb, render);
      int hits = 0, samePick = 0;
      for (int py = 0; py < 96; ++py)
        for (int px = 0; px < 96; ++px)
        {
          const std::size_t i = fa.index(px, py);
          EXPECT_EQ(fa.Depth[i], fb.Depth[i]) << "pixel " << px << ", " << py;
          EXPECT_EQ(fa.Color[i], fb.Color[i]) << "pixel " << px << ", " << py;
          if (fa.Color[i].a == 0.0f)
            continue;
          ++hits;
          samePick += fa.Primitives[i].primitive == fb.Primitives[i].primitive;
        }
      EXPECT_GT(hits, 96 * 96 / 4);
      // Picks name the whole set's links; ties (a joint) may name either of two.
      EXPECT_GT(samePick, hits * 99 / 100);
    }
  }
}

TEST(TubeInterior, SparseAndUnchunkedSetsAreNotCulled)
{
  const DenseBall sparse = denseBall(5.0, 2);
  OuterLinkReport report;
  EXPECT_FALSE(outerLinks(*chunkedSet(sparse, dvec3(0.0), 8), {}, &report));
  EXPECT_LT(report.fill, 10.0);
  EXPECT_GT(report.fill, 1.0); // the ball is about half its bounding box
  EXPECT_EQ(report.voxel, 0.0);

  const DenseBall dense = denseBall(160.0, 5);
  const auto combined =
    std::make_shared<TubeSet>(dense.points, dense.radii, dense.predecessors, dense.colors);
  EXPECT_FALSE(outerLinks(*combined));
  // Dense, but asked to keep at most 5 % of the links: not worth a second set.
  OuterLinkOptions options;
  options.maximumKept = 0.05;
  EXPECT_FALSE(outerLinks(*chunkedSet(dense, dvec3(0.0), 8), options, &report));
  EXPECT_GT(report.voxel, 0.0);
  EXPECT_GT(report.hiddenLinks, 0u);
}

TEST(TubeInterior, OuterLinksReportProgressOnTheCallingThread)
{
  const DenseBall ball = denseBall(160.0, 11);
  const auto whole = chunkedSet(ball, dvec3(0.0), 8);
  OuterLinkOptions options;
  options.maximumKept = 1.0;
  std::vector<double> fractions;
  bool sameThread = true;
  const auto caller = std::this_thread::get_id();
  options.progress = [&](double fraction)
  {
    sameThread = sameThread && std::this_thread::get_id() == caller;
    fractions.push_back(fraction);
  };
  OuterLinkReport withProgress, without;
  const auto reported = outerLinks(*whole, options, &withProgress);
  options.progress = {};
  const auto quiet = outerLinks(*whole, options, &without);
  ASSERT_TRUE(reported && quiet);
  EXPECT_TRUE(sameThread);
  ASSERT_GE(fractions.size(), 3u);
  EXPECT_EQ(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  // Marking order between threads may differ; what it finds hidden hardly does.
  EXPECT_NEAR(double(withProgress.hiddenLinks), double(without.hiddenLinks), 0.01 * double(without.links));
  EXPECT_GT(withProgress.hiddenLinks, whole->pointCount() / 3);
}
