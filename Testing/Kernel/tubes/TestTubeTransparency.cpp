// SPDX-License-Identifier: BSD-3-Clause
// Translucent generalized tubes (Han et al. 2019, Section 4.3): the surfaces a ray crosses must
// be exactly those of the union of the links, found independently here by sampling the union's
// distance function (the minimum over links of the swept-sphere distance) along the ray. At a
// bifurcation and along a chain the links overlap, so the raw sphere and stump intervals have
// many interior endpoints that must not show.
#include "sightline/core/Camera.h"
#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Renderer.h"
#include "sightline/spheres/SphereSet.h"
#include "sightline/tubes/TubeSet.h"

#include "RegionBlend.h"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <random>

using namespace sightline;

namespace
{
struct Tree
{
  std::vector<vec3> points;
  std::vector<float> radii;
  std::vector<std::int64_t> predecessors;
};

/// A Y bifurcation.
Tree bifurcation()
{
  return { { vec3(0, 0, 0), vec3(0, 2, 0), vec3(-1.5, 4, 0), vec3(1.5, 4, 0) },
    { 0.6f, 0.5f, 0.25f, 0.3f }, { -1, 0, 1, 1 } };
}

/// A random branching tree with short, thick, overlapping links (a dendrite-like worst case),
/// plus a childless root (a sphere only).
Tree randomTree(unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), r(0.15f, 0.45f);
  Tree t;
  t.points.push_back(vec3(0));
  t.radii.push_back(0.5f);
  t.predecessors.push_back(-1);
  for (int i = 1; i < 40; ++i)
  {
    // Mostly extend the newest point, sometimes branch from an older one.
    const int parent = (i % 7 == 0) ? int(rng() % unsigned(i)) : i - 1;
    t.points.push_back(t.points[parent] + 0.6f * vec3(u(rng), u(rng), u(rng)));
    t.radii.push_back(r(rng));
    t.predecessors.push_back(parent);
  }
  t.points.push_back(vec3(3, 3, 3));
  t.radii.push_back(0.4f);
  t.predecessors.push_back(-1);
  return t;
}

/// Signed distance-like function of the union: negative inside some link or sphere.
double unionDistance(const Tree& t, const dvec3& q)
{
  double best = 1e300;
  for (std::size_t i = 0; i < t.points.size(); ++i)
  {
    const dvec3 p2(t.points[i]);
    const double r2 = t.radii[i];
    best = std::min(best, glm::length(q - p2) - r2);
    if (t.predecessors[i] < 0)
      continue;
    const std::size_t j = std::size_t(t.predecessors[i]);
    // Swept sphere: min over s of |q - P(s)| - r(s), convex in s (golden section).
    const dvec3 p1(t.points[j]);
    const double r1 = t.radii[j];
    // Skip links that cannot beat the current best (a bound from their bounding sphere).
    if (glm::length(q - 0.5 * (p1 + p2)) - 0.5 * glm::length(p2 - p1) - std::max(r1, r2) >= best)
      continue;
    auto f = [&](double s) { return glm::length(q - (p1 + s * (p2 - p1))) - (r1 + s * (r2 - r1)); };
    double a = 0.0, b = 1.0;
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    for (int k = 0; k < 45; ++k)
    {
      const double c = b - g * (b - a), d = a + g * (b - a);
      (f(c) < f(d) ? b : a) = (f(c) < f(d) ? d : c);
    }
    best = std::min({ best, f(0.0), f(1.0), f(0.5 * (a + b)) });
    if (best < -0.05) // the sign is all that matters this deep inside
      return best;
  }
  return best;
}

struct ReferenceCrossings
{
  std::vector<double> t;
  bool grazing = false; ///< the ray comes too close to the surface to classify by sampling
};

ReferenceCrossings referenceCrossings(const Tree& tree, const dvec3& o, const dvec3& d, double tmax)
{
  ReferenceCrossings out;
  const int samples = 1500;
  double previousT = 0.0, previous = unionDistance(tree, o);
  for (int k = 1; k <= samples; ++k)
  {
    const double t = tmax * k / samples;
    const double value = unionDistance(tree, o + t * d);
    if ((value <= 0.0) != (previous <= 0.0))
    {
      double lo = previousT, hi = t;
      for (int b = 0; b < 50; ++b)
      {
        const double m = 0.5 * (lo + hi);
        ((unionDistance(tree, o + m * d) <= 0.0) == (previous <= 0.0) ? lo : hi) = m;
      }
      out.t.push_back(0.5 * (lo + hi));
    }
    else if (std::abs(value) < 3e-3)
      out.grazing = true;
    previous = value;
    previousT = t;
  }
  return out;
}

struct CrossingCounts
{
  int rays = 0, unionSurfaces = 0, rawEndpoints = 0, startInside = 0;
};

CrossingCounts checkCrossings(const Tree& tree, TubeLayout layout, unsigned seed, double span)
{
  auto tubes = std::make_shared<TubeSet>(tree.points, tree.radii, tree.predecessors,
    std::vector<std::uint32_t>{}, layout);
  EmbreeScene scene;
  scene.add(tubes);
  scene.commit();
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> u(-span, span);
  const dvec3 center = 0.5 * dvec3(scene.bounds().lower + scene.bounds().upper);
  CrossingCounts counts;
  std::vector<InsideInterval> intervals;
  std::vector<UnionSurface> surfaces;
  for (int r = 0; r < 240; ++r)
  {
    const dvec3 d = glm::normalize(dvec3(normal(rng), normal(rng), normal(rng)));
    const dvec3 target = center + dvec3(u(rng), u(rng), u(rng));
    // Every fourth ray starts inside the union: at a control point.
    const bool inside = r % 4 == 0;
    const dvec3 o = inside ? dvec3(tree.points[rng() % (tree.points.size() - 1)]) : target - 12.0 * d;
    const double tmax = 24.0;
    const ReferenceCrossings reference = referenceCrossings(tree, o, d, tmax);
    if (reference.grazing)
      continue;
    Ray ray;
    ray.origin = vec3(o);
    ray.direction = vec3(d);
    ray.tnear = 0.0f;
    ray.tfar = float(tmax);
    intervals.clear();
    scene.insideIntervals(ray, intervals);
    counts.rawEndpoints += 2 * int(intervals.size());
    unionSurfaces(intervals, 0.0, tmax, 1e-7, surfaces);
    ++counts.rays;
    counts.unionSurfaces += int(surfaces.size());
    EXPECT_EQ(surfaces.size(), reference.t.size()) << layout.name() << ", ray " << r;
    if (surfaces.size() != reference.t.size())
      continue;
    for (std::size_t k = 0; k < surfaces.size(); ++k)
    {
      // Surfaces alternate: entering, leaving, ... except that a ray starting inside leaves first.
      const bool expectEntering = (k % 2 == 0) != inside;
      EXPECT_EQ(surfaces[k].entering, expectEntering) << layout.name() << ", ray " << r << ", surface " << k;
      EXPECT_NEAR(surfaces[k].t, reference.t[k], 2e-5) << layout.name() << ", ray " << r << ", surface " << k;
    }
    counts.startInside += inside;
  }
  return counts;
}
} // namespace

TEST(UnionSurfaces, CountsEntriesAndExitsAndIgnoresDuplicates)
{
  // Two overlapping solids, one reported twice, one touching the next, one far away.
  std::vector<InsideInterval> intervals = { { 1.0, 3.0, 0, 10 }, { 2.0, 4.0, 1, 11 },
    { 2.0, 4.0, 1, 11 }, { 4.0, 5.0, 2, 12 }, { 7.0, 8.0, 3, 13 } };
  std::vector<UnionSurface> out;
  unionSurfaces(intervals, 0.0, 100.0, 1e-9, out);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].t, 1.0);
  EXPECT_TRUE(out[0].entering);
  EXPECT_EQ(out[0].part, 10u);
  EXPECT_EQ(out[1].t, 5.0);
  EXPECT_FALSE(out[1].entering);
  EXPECT_EQ(out[1].part, 12u);
  EXPECT_EQ(out[2].t, 7.0);
  EXPECT_EQ(out[3].t, 8.0);
  // A ray starting inside (tnear = 2.5) sees the exit only, and tfar clips the rest.
  unionSurfaces(intervals, 2.5, 7.5, 1e-9, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].t, 5.0);
  EXPECT_FALSE(out[0].entering);
  EXPECT_EQ(out[1].t, 7.0);
  EXPECT_TRUE(out[1].entering);
  // Nothing: no surfaces.
  intervals.clear();
  unionSurfaces(intervals, 0.0, 1.0, 0.0, out);
  EXPECT_TRUE(out.empty());
}

TEST(TubeTransparency, OnlyUnionSurfacesAtABifurcationAndInATree)
{
  const TubeLayout layouts[] = { { TubeLayout::Primitives::Combined, TubeLayout::Transforms::OnTheFly },
    { TubeLayout::Primitives::Separate, TubeLayout::Transforms::Precomputed } };
  for (const TubeLayout& layout : layouts)
  {
    const CrossingCounts y = checkCrossings(bifurcation(), layout, 51, 1.5);
    const CrossingCounts tree = checkCrossings(randomTree(52), layout, 53, 1.5);
    std::printf("%s: Y %d rays (%d from inside), %d union surfaces of %d raw interval ends; "
                "tree %d rays (%d from inside), %d of %d\n",
      layout.name().c_str(), y.rays, y.startInside, y.unionSurfaces, y.rawEndpoints, tree.rays,
      tree.startInside, tree.unionSurfaces, tree.rawEndpoints);
    // Enough rays classified, from inside too, and plenty of interior surfaces removed.
    EXPECT_GT(y.rays, 150);
    EXPECT_GT(y.startInside, 40);
    EXPECT_GT(y.unionSurfaces, 100);
    EXPECT_GT(y.rawEndpoints, 3 * y.unionSurfaces);
    EXPECT_GT(tree.rays, 150);
    EXPECT_GT(tree.rawEndpoints, 3 * tree.unionSurfaces);
  }
}

TEST(TubeTransparency, RenderedLayersMatchTheUnionSurfaces)
{
  // A translucent render's alpha is 1 - (1 - opacity)^k, k the union surfaces along the pixel;
  // at opacity 1 the translucent path draws what the opaque path draws.
  const Tree y = bifurcation();
  auto tubes = std::make_shared<TubeSet>(y.points, y.radii, y.predecessors);
  EmbreeScene scene, empty;
  scene.add(tubes);
  scene.commit();
  empty.commit();
  CameraParameters parameters;
  parameters.position = dvec3(2.0, 3.0, 9.0);
  parameters.focalPoint = dvec3(0.0, 2.0, 0.0);
  parameters.viewAngle = 35.0;
  const Camera camera = Camera::fromParameters(parameters, 96, 96);
  const Lighting lighting = Lighting::headlight(vec3(glm::normalize(parameters.focalPoint - parameters.position)));

  Framebuffer opaque, translucent;
  Renderer().render(scene, camera, lighting, opaque);
  RenderOptions options;
  options.translucent.scene = &scene;
  tubes->material.opacity = 1.0f;
  Renderer().render(empty, camera, lighting, translucent, options);
  int compared = 0;
  for (std::size_t i = 0; i < opaque.pixelCount(); ++i)
  {
    ASSERT_EQ(opaque.Color[i].a > 0.0f, translucent.Color[i].a > 0.0f) << "pixel " << i;
    if (opaque.Color[i].a == 0.0f)
      continue;
    ++compared;
    EXPECT_NEAR(glm::length(vec3(opaque.Color[i]) - vec3(translucent.Color[i])), 0.0f, 2e-3f) << "pixel " << i;
    EXPECT_NEAR(opaque.Depth[i], translucent.Depth[i], 1e-5f) << "pixel " << i;
  }
  EXPECT_GT(compared, 1000);

  tubes->material.opacity = 0.4f;
  const RenderStatistics stats = Renderer().render(empty, camera, lighting, translucent, options);
  std::vector<InsideInterval> intervals;
  std::vector<UnionSurface> surfaces;
  std::size_t totalSurfaces = 0;
  int twoLayers = 0;
  for (int py = 0; py < camera.height(); ++py)
    for (int px = 0; px < camera.width(); ++px)
    {
      const Ray ray = camera.primaryRay(px + 0.5, py + 0.5);
      intervals.clear();
      scene.insideIntervals(ray, intervals);
      unionSurfaces(intervals, ray.tnear, ray.tfar, 1e-6, surfaces);
      totalSurfaces += surfaces.size();
      twoLayers += surfaces.size() == 2;
      const float expected = 1.0f - std::pow(0.6f, float(surfaces.size()));
      EXPECT_NEAR(translucent.Color[translucent.index(px, py)].a, expected, 1e-5f) << px << ", " << py;
    }
  EXPECT_EQ(stats.translucentSurfaces, totalSurfaces);
  EXPECT_GT(twoLayers, 1000); // front and back of the tube; never the insides of the joint
}

TEST(TubeTransparency, DepthLimitStopsRays)
{
  // Opaque geometry drawn elsewhere at window depth z: translucent layers behind it vanish.
  const Tree y = bifurcation();
  auto tubes = std::make_shared<TubeSet>(y.points, y.radii, y.predecessors);
  tubes->material.opacity = 0.5f;
  EmbreeScene scene, empty;
  scene.add(tubes);
  scene.commit();
  empty.commit();
  CameraParameters parameters;
  parameters.position = dvec3(0.0, 2.0, 10.0);
  parameters.focalPoint = dvec3(0.0, 2.0, 0.0);
  const Camera camera = Camera::fromParameters(parameters, 32, 32);
  const Lighting lighting = Lighting::headlight(vec3(0, 0, -1));
  RenderOptions options;
  options.translucent.scene = &scene;
  // A wall at z = 0 (through the tubes' axes): only the front layer is left.
  std::vector<float> wall(32 * 32);
  for (int py = 0; py < 32; ++py)
    for (int px = 0; px < 32; ++px)
    {
      const Ray ray = camera.primaryRay(px + 0.5, py + 0.5);
      const float t = -ray.origin.z / ray.direction.z;
      wall[std::size_t(py) * 32 + px] =
        float(camera.windowDepth(dvec3(ray.origin) + double(t) * dvec3(ray.direction)));
    }
  options.depthLimit = &wall;
  Framebuffer fb;
  Renderer().render(empty, camera, lighting, fb, options);
  const vec4 centre = fb.Color[fb.index(16, 16)]; // on the trunk
  EXPECT_NEAR(centre.a, 0.5f, 1e-5f);
  // Without the wall, front and back.
  options.depthLimit = nullptr;
  Renderer().render(empty, camera, lighting, fb, options);
  EXPECT_NEAR(fb.Color[fb.index(16, 16)].a, 0.75f, 1e-5f);
  // A wrongly sized limit is an error, not a read past the end.
  std::vector<float> wrong(10, 0.5f);
  options.depthLimit = &wrong;
  EXPECT_THROW(Renderer().render(empty, camera, lighting, fb, options), std::invalid_argument);
}

TEST(TubeTransparency, RegionImagesBlendedInVisibilityOrderGiveTheWholeImage)
{
  // Sort-last compositing across MPI ranks: each rank draws its region of a kd-tree partition
  // (RenderOptions::regionLower/Upper) and the regions' images are blended front to back. Four
  // quadrants cut through a translucent tree and an opaque sphere; their blend must equal the
  // unclipped image, from several directions, one of them with a column of rays lying in a cut
  // plane (odd width, camera in the plane x = 0.2).
  const Tree tree = randomTree(7);
  auto tubes = std::make_shared<TubeSet>(tree.points, tree.radii, tree.predecessors);
  tubes->material.opacity = 0.4f;
  auto sphere = std::make_shared<SphereSet>(std::vector<vec3>{ vec3(0.3f, -0.2f, -0.4f) },
    std::vector<float>{ 0.7f });
  EmbreeScene translucent, opaque;
  translucent.add(tubes);
  translucent.commit();
  opaque.add(sphere);
  opaque.commit();
  const double cutX = 0.2, cutY = -0.3;
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<std::array<dvec3, 2>> regions;
  for (int i = 0; i < 4; ++i)
    regions.push_back({ dvec3(i & 1 ? cutX : -inf, i & 2 ? cutY : -inf, -inf),
      dvec3(i & 1 ? inf : cutX, i & 2 ? inf : cutY, inf) });

  const std::array<dvec3, 3> positions{ dvec3(2.0, 3.0, 9.0), dvec3(-7.0, -1.0, -4.0),
    dvec3(cutX, 0.5, 10.0) };
  for (const dvec3& position : positions)
  {
    CameraParameters parameters;
    parameters.position = position;
    parameters.focalPoint = dvec3(position.x == cutX ? cutX : 0.0, 0.5, 0.0);
    parameters.viewAngle = 40.0;
    const Camera camera = Camera::fromParameters(parameters, 65, 64);
    const Lighting lighting = Lighting::headlight(vec3(glm::normalize(parameters.focalPoint - position)));
    RenderOptions options;
    options.translucent.scene = &translucent;
    Framebuffer whole;
    Renderer().render(opaque, camera, lighting, whole, options);

    std::vector<Framebuffer> parts(regions.size());
    for (std::size_t r = 0; r < regions.size(); ++r)
    {
      options.regionLower = regions[r][0];
      options.regionUpper = regions[r][1];
      Renderer().render(opaque, camera, lighting, parts[r], options);
    }
    int covered = 0, split = 0;
    sightline_test::expectRegionBlendIsWhole(regions, parts, whole, camera, 1e-5f, 1e-4f, covered, split);
    EXPECT_GT(covered, 400);
    std::printf("camera at (%g, %g, %g): %d covered pixels, %d with layers in several regions\n",
      position.x, position.y, position.z, covered, split);
    EXPECT_GT(split, 10); // pixels whose layers lie in more than one region
  }
}

TEST(TubeSet, MemoryOfTheFourLayouts)
{
  // On the fly: a point, a radius and a predecessor index per link (20 bytes); precomputed
  // layouts add the stump; separate ones an index per stump primitive.
  const Tree tree = randomTree(54);
  std::size_t bytes[4];
  int k = 0;
  for (auto primitives : { TubeLayout::Primitives::Combined, TubeLayout::Primitives::Separate })
    for (auto transforms : { TubeLayout::Transforms::OnTheFly, TubeLayout::Transforms::Precomputed })
    {
      const TubeSet tubes(tree.points, tree.radii, tree.predecessors, {}, { primitives, transforms });
      bytes[k++] = tubes.memoryBytes();
    }
  EXPECT_EQ(bytes[0], tree.points.size() * 20);
  EXPECT_LT(bytes[0], bytes[1]);
  EXPECT_LT(bytes[0], bytes[2]);
  EXPECT_LT(bytes[2], bytes[3]);
}
