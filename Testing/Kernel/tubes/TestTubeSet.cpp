// SPDX-License-Identifier: BSD-3-Clause
// Tube links (TubeLink.h, TubeSet.h) against an independent reference: a link is the union of
// the spheres centred on the segment with linearly varying radius, so a point q is inside iff
// min over s in [0, 1] of |q - P(s)| - r(s) <= 0 (convex in s: golden-section search, long
// double). That function is convex along a ray too, so its minimum and first root give the
// reference hit; the cone stump's formulas are never used by the reference.
#include "sightline/core/EmbreeScene.h"
#include "sightline/tubes/TubeLink.h"
#include "sightline/tubes/TubeSet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>

using namespace sightline;

namespace
{
struct Link
{
  dvec3 p1, p2;
  double r1, r2;
};

/// min over s of |q - P(s)| - r(s): negative inside the link (golden section: convex in s).
long double linkDistance(const Link& l, const dvec3& q)
{
  auto f = [&](long double s)
  {
    const long double x = q.x - (l.p1.x + s * (l.p2.x - l.p1.x));
    const long double y = q.y - (l.p1.y + s * (l.p2.y - l.p1.y));
    const long double z = q.z - (l.p1.z + s * (l.p2.z - l.p1.z));
    return std::sqrt(x * x + y * y + z * z) - (l.r1 + s * (l.r2 - l.r1));
  };
  long double a = 0.0L, b = 1.0L;
  const long double g = (std::sqrt(5.0L) - 1.0L) / 2.0L;
  for (int i = 0; i < 64; ++i)
  {
    const long double c = b - g * (b - a), d = a + g * (b - a);
    (f(c) < f(d) ? b : a) = (f(c) < f(d) ? d : c);
  }
  return std::min({ f(0.0L), f(1.0L), f(0.5L * (a + b)) });
}

/// First t in [0, tmax] where the ray enters the link, or -1. The link is convex and so is
/// linkDistance (a partial minimum of a jointly convex function), also along the ray: a
/// golden-section search finds its minimum, bisection the first root before it.
double referenceHit(const Link& l, const dvec3& o, const dvec3& d, double tmax)
{
  auto g = [&](double t) { return linkDistance(l, o + t * d); };
  if (g(0.0) <= 0)
    return 0.0;
  double a = 0.0, b = tmax;
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int i = 0; i < 70; ++i)
  {
    const double c = b - ratio * (b - a), e = a + ratio * (b - a);
    if (g(c) < g(e))
      b = e;
    else
      a = c;
  }
  const double lowest = 0.5 * (a + b);
  if (g(lowest) > 0)
    return -1.0;
  double lo = 0.0, hi = lowest;
  for (int k = 0; k < 60; ++k)
  {
    const double m = 0.5 * (lo + hi);
    (g(m) <= 0 ? hi : lo) = m;
  }
  return hi;
}

/// The link's first hit from its pieces: both spheres and the stump.
double linkHit(const Link& l, const dvec3& o, const dvec3& d)
{
  double best = std::numeric_limits<double>::infinity(), t0, t1;
  if (sphereInterval(l.p1, l.r1, o, d, 0.0, 1e300, t0, t1))
    best = std::min(best, t0);
  if (sphereInterval(l.p2, l.r2, o, d, 0.0, 1e300, t0, t1))
    best = std::min(best, t0);
  const ConeStump stump = makeConeStump(l.p1, l.r1, l.p2, l.r2);
  if (coneStumpInterval(stump, o, d, 0.0, 1e300, t0, t1))
    best = std::min(best, t0);
  return std::isfinite(best) ? best : -1.0;
}

Link randomLink(std::mt19937& rng, int kind)
{
  std::uniform_real_distribution<double> u(-1.0, 1.0), r(0.1, 0.8);
  Link l{ dvec3(u(rng), u(rng), u(rng)), dvec3(u(rng), u(rng), u(rng)) * 2.0, r(rng), r(rng) };
  if (kind == 1)
    l.r2 = l.r1; // cylinder
  if (kind == 2)
    l.r2 = l.r1 * (1.0 + 1e-9); // nearly a cylinder: the apex is far away
  if (kind == 3)
  {
    l.r2 = 0.02; // a sharp cone
    l.r1 = 0.9;
  }
  if (kind == 4)
    l.p2 = l.p1 + 0.3 * glm::normalize(l.p2 - l.p1), l.r1 = 0.6, l.r2 = 0.1; // one holds the other
  return l;
}
} // namespace

TEST(TubeLink, FirstHitsMatchTheSweptSphereReference)
{
  std::mt19937 rng(41);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0, misses = 0;
  double worst = 0.0;
  for (int kind = 0; kind < 5; ++kind)
    for (int i = 0; i < 12; ++i)
    {
      const Link l = randomLink(rng, kind);
      for (int r = 0; r < 60; ++r)
      {
        const dvec3 d = glm::normalize(dvec3(normal(rng), normal(rng), normal(rng)));
        const dvec3 target = 0.5 * (l.p1 + l.p2) + 1.5 * dvec3(u(rng), u(rng), u(rng));
        const dvec3 o = target - 8.0 * d;
        const double reference = referenceHit(l, o, d, 16.0);
        const double ours = linkHit(l, o, d);
        if (reference < 0.0)
        {
          ++misses;
          if (ours >= 0.0) // only a grazing ray may disagree, and then by a hair
          {
            EXPECT_LT(std::abs(double(linkDistance(l, o + ours * d))), 1e-6) << "kind " << kind;
          }
          continue;
        }
        ++hits;
        ASSERT_GE(ours, 0.0) << "kind " << kind << " link " << i << " ray " << r;
        worst = std::max(worst, std::abs(ours - reference));
        EXPECT_NEAR(ours, reference, 1e-6) << "kind " << kind << " link " << i << " ray " << r;
      }
    }
  std::printf("tube links: %d hits, %d misses, worst |t - reference| %.2e\n", hits, misses, worst);
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 300);
}

TEST(TubeLink, TangentCirclesAndNormals)
{
  // The stump meets each sphere tangentially: on the tangent circle the stump's radius is the
  // sphere's section there, and the stump's normal is the sphere's normal.
  std::mt19937 rng(42);
  for (int i = 0; i < 50; ++i)
  {
    Link l = randomLink(rng, i % 4);
    const ConeStump k = makeConeStump(l.p1, l.r1, l.p2, l.r2);
    ASSERT_TRUE(k.valid);
    const dvec3 side = glm::normalize(glm::cross(k.axis, dvec3(0.3, 0.7, -0.2)));
    const double radius1 = (k.radius1 + k.slope * k.u1) / k.cosine;
    const dvec3 x1 = k.base + k.u1 * k.axis + radius1 * side; // on the first tangent circle
    EXPECT_NEAR(glm::length(x1 - l.p1), l.r1, 1e-9);
    EXPECT_GT(glm::dot(glm::normalize(coneStumpNormal(k, x1)), glm::normalize(x1 - l.p1)), 1.0 - 1e-9);
    const double radius2 = (k.radius1 + k.slope * k.u2) / k.cosine;
    const dvec3 x2 = k.base + k.u2 * k.axis + radius2 * side;
    EXPECT_NEAR(glm::length(x2 - l.p2), l.r2, 1e-9);
    // Normals are the reference distance's gradient (central differences) anywhere on the side.
    const double um = 0.5 * (k.u1 + k.u2);
    const dvec3 x = k.base + um * k.axis + (k.radius1 + k.slope * um) / k.cosine * side;
    dvec3 gradient;
    for (int a = 0; a < 3; ++a)
    {
      dvec3 h(0.0);
      h[a] = 1e-6;
      gradient[a] = double(linkDistance(l, x + h) - linkDistance(l, x - h)) / 2e-6;
    }
    EXPECT_GT(glm::dot(glm::normalize(coneStumpNormal(k, x)), glm::normalize(gradient)), 1.0 - 1e-6);
  }
  // One sphere inside the other, and coincident points: no stump.
  EXPECT_FALSE(makeConeStump(dvec3(0), 1.0, dvec3(0.5, 0, 0), 0.2).valid);
  EXPECT_FALSE(makeConeStump(dvec3(1), 1.0, dvec3(1), 1.0).valid);
}

const TubeLayout kLayouts[] = {
  { TubeLayout::Primitives::Combined, TubeLayout::Transforms::OnTheFly },
  { TubeLayout::Primitives::Combined, TubeLayout::Transforms::Precomputed },
  { TubeLayout::Primitives::Separate, TubeLayout::Transforms::OnTheFly },
  { TubeLayout::Primitives::Separate, TubeLayout::Transforms::Precomputed },
};

class TubeLayouts : public ::testing::TestWithParam<int>
{
protected:
  TubeLayout layout() const { return kLayouts[GetParam()]; }
};
INSTANTIATE_TEST_SUITE_P(AllFour, TubeLayouts, ::testing::Range(0, 4),
  [](const ::testing::TestParamInfo<int>& info)
  {
    std::string name = kLayouts[info.param].name();
    std::string out;
    for (char c : name)
      if (std::isalnum(static_cast<unsigned char>(c)))
        out += c;
    return out;
  });

// A Y: a trunk and two branches from point 1, radii shrinking.
const std::vector<vec3> kY = { vec3(0, 0, 0), vec3(0, 2, 0), vec3(-1.5, 4, 0), vec3(1.5, 4, 0) };
const std::vector<float> kYRadii = { 0.6f, 0.5f, 0.25f, 0.3f };
const std::vector<std::int64_t> kYPredecessors = { -1, 0, 1, 1 };

TEST_P(TubeLayouts, BifurcationThroughEmbree)
{
  const std::vector<vec3>& points = kY;
  const std::vector<float>& radii = kYRadii;
  const std::vector<std::int64_t>& predecessors = kYPredecessors;
  auto tubes = std::make_shared<TubeSet>(points, radii, predecessors, std::vector<std::uint32_t>{}, layout());
  EXPECT_EQ(tubes->pointCount(), 4u);
  EXPECT_EQ(tubes->linkCount(), 3u);
  EXPECT_EQ(tubes->size(), layout().primitives == TubeLayout::Primitives::Combined ? 4u : 7u);
  EmbreeScene scene;
  scene.add(tubes);
  scene.commit();
  std::mt19937 rng(43);
  std::uniform_real_distribution<float> u(-2.5f, 2.5f), v(-1.0f, 5.0f);
  int hits = 0;
  for (int r = 0; r < 1000; ++r)
  {
    Ray ray;
    ray.origin = vec3(u(rng), v(rng), 10.0f);
    ray.direction = vec3(0, 0, -1);
    RTCRayHit rh = makeRayHit(ray);
    const bool hit = scene.intersect(rh);
    // Reference: the first entry of any of the three links (the union).
    double best = -1.0;
    for (int i = 1; i < 4; ++i)
    {
      const Link l{ dvec3(points[predecessors[i]]), dvec3(points[i]), radii[predecessors[i]], radii[i] };
      const double t = referenceHit(l, dvec3(ray.origin), dvec3(ray.direction), 20.0);
      if (t >= 0.0 && (best < 0.0 || t < best))
        best = t;
    }
    if (best < 0.0)
    {
      EXPECT_FALSE(hit && rh.ray.tfar < 9.0f) << "ray " << r;
      continue;
    }
    ++hits;
    ASSERT_TRUE(hit) << "ray " << r;
    // Precomputed stumps are stored in single precision.
    EXPECT_NEAR(rh.ray.tfar, best, 2e-5) << "ray " << r;
  }
  EXPECT_GT(hits, 100);
}

TEST(TubeSet, BadInput)
{
  const std::vector<vec3>& points = kY;
  const std::vector<float>& radii = kYRadii;
  const std::vector<std::int64_t>& predecessors = kYPredecessors;

  // Bad input: cycles, predecessors out of range, sizes; bad radii are dropped and reported.
  EXPECT_THROW(TubeSet(points, radii, { 1, 2, 3, 1 }), std::invalid_argument);
  EXPECT_THROW(TubeSet(points, radii, { 0, 0, 1, 1 }), std::invalid_argument); // self link
  EXPECT_THROW(TubeSet(points, radii, { -1, 0, 1, 4 }), std::invalid_argument);
  EXPECT_THROW(TubeSet(points, { 1.0f }, predecessors), std::invalid_argument);
  const TubeSet partial(points, { 0.6f, -0.5f, std::nanf(""), 0.3f }, predecessors);
  EXPECT_EQ(partial.size(), 2u);
  EXPECT_EQ(partial.report().rejected, 2u);
  // Picking maps kept control points back to the points given: 0 and 3 are kept, and 3 lost
  // its predecessor (point 1) with it.
  EXPECT_EQ(partial.sourceIndexOf(0), 0u);
  EXPECT_EQ(partial.sourceIndexOf(1), 3u);
  EXPECT_EQ(partial.nodeOfPrimitive(1), 1u);
  EXPECT_EQ(partial.predecessorOf(1), -1);
  // Separate spheres and stumps: stump primitives follow the spheres and name their end point.
  const TubeSet separate(points, radii, predecessors, {},
    { TubeLayout::Primitives::Separate, TubeLayout::Transforms::OnTheFly });
  ASSERT_EQ(separate.size(), 7u);
  for (unsigned p = 0; p < 4; ++p)
  {
    EXPECT_EQ(separate.nodeOfPrimitive(p), p);
    EXPECT_EQ(separate.sourceIndexOf(p), p);
    EXPECT_EQ(separate.predecessorOf(p), predecessors[p]);
  }
  for (unsigned p = 4; p < 7; ++p)
    EXPECT_EQ(separate.nodeOfPrimitive(p), p - 3);
  // Duplicate points (a zero-length link) draw the sphere only.
  const TubeSet duplicate({ vec3(0), vec3(0) }, { 0.5f, 0.5f }, { -1, 0 });
  Ray down;
  down.origin = vec3(0, 0, 5);
  down.direction = vec3(0, 0, -1);
  SurfaceHit hit;
  ASSERT_TRUE(duplicate.intersect(1, down, hit));
  EXPECT_NEAR(hit.t, 4.5f, 1e-6f);
}
