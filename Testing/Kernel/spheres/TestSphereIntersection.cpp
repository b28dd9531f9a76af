// SPDX-License-Identifier: BSD-3-Clause
// intersectSphere against the textbook quadratic solved in long double. Every reference is
// computed from the exact float inputs the kernel receives, so the tolerances measure the kernel's
// own float arithmetic only.
#include "KernelTestSupport.h"

#include "sightline/spheres/SphereSet.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <random>

namespace
{
using namespace sightline_test;
using sightline::intersectSphere;
using sightline::Ray;
using sightline::SurfaceHit;
using sightline::vec3;

/// Distance from the sphere's centre to the ray's line, in long double.
long double lineDistance(const Ray& ray, const vec3& center)
{
  const dvec3 f = dvec3(ray.origin) - dvec3(center);
  const dvec3 d = dvec3(ray.direction);
  const long double along = (long double)glm::dot(f, d) / glm::dot(d, d);
  const long double x = f.x - along * d.x, y = f.y - along * d.y, z = f.z - along * d.z;
  return std::sqrt(x * x + y * y + z * z);
}

std::optional<long double> reference(const Ray& ray, const vec3& center, float radius)
{
  return referenceSphereHit(dvec3(ray.origin), dvec3(ray.direction), dvec3(center), radius,
                            ray.tnear, ray.tfar);
}

/// The outward unit normal at o + t d, in long double.
dvec3 referenceNormal(const Ray& ray, long double t, const vec3& center, float radius)
{
  const long double x = ray.origin.x + t * ray.direction.x - center.x;
  const long double y = ray.origin.y + t * ray.direction.y - center.y;
  const long double z = ray.origin.z + t * ray.direction.z - center.z;
  return dvec3(double(x / radius), double(y / radius), double(z / radius));
}

vec3 randomUnitVector(std::mt19937& random)
{
  std::normal_distribution<float> gaussian;
  vec3 v;
  do
    v = vec3(gaussian(random), gaussian(random), gaussian(random));
  while (glm::length(v) < 1e-3f);
  return glm::normalize(v);
}

/// A unit vector perpendicular to `direction`.
vec3 perpendicularTo(const vec3& direction, std::mt19937& random)
{
  const vec3 v = randomUnitVector(random);
  return glm::normalize(v - glm::dot(v, direction) * direction);
}

struct RandomCase
{
  vec3 center;
  float radius;
  Ray ray;
};

/// Random spheres and rays aimed near them (so that about half hit), with directions that are
/// deliberately not always unit length.
RandomCase randomCase(std::mt19937& random)
{
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_real_distribution<float> logRadius(std::log(0.5f), std::log(5.0f));
  std::uniform_real_distribution<float> directionLength(0.2f, 5.0f);
  RandomCase c;
  c.center = 10.0f * vec3(unit(random), unit(random), unit(random));
  c.radius = std::exp(logRadius(random));
  c.ray.origin = 20.0f * vec3(unit(random), unit(random), unit(random));
  const vec3 target = c.center + 1.5f * c.radius * vec3(unit(random), unit(random), unit(random));
  c.ray.direction = glm::normalize(target - c.ray.origin);
  if (random() % 2)
    c.ray.direction *= directionLength(random);
  return c;
}

TEST(IntersectSphere, RandomRaysMatchTheLongDoubleQuadratic)
{
  std::mt19937 random(12345);
  int hits = 0, misses = 0;
  for (int i = 0; i < 20000; ++i)
  {
    const RandomCase c = randomCase(random);
    const long double distance = lineDistance(c.ray, c.center);
    const long double directionLength = glm::length(dvec3(c.ray.direction));
    // t is in units of the direction's length; errors scale with the radius and with t.
    const long double scale = c.radius / directionLength;
    SurfaceHit hit;
    const bool kernelHit = intersectSphere(c.center, c.radius, c.ray, hit);

    // The long double discriminant a (r^2 - distance^2) is clearly negative.
    if (distance > c.radius * (1 + 1e-4L))
    {
      EXPECT_FALSE(kernelHit) << "case " << i << ": the line misses the sphere";
      ++misses;
      continue;
    }
    // Nearly tangent rays are ill-conditioned (tested separately); keep those with a chord
    // of at least a tenth of the radius.
    if (distance > c.radius * std::sqrt(1 - 0.0025L))
      continue;
    const auto expected = reference(c.ray, c.center, c.radius);
    // An origin within rounding of the surface may legitimately count as inside or outside.
    const auto nearRoot = referenceSphereHit(dvec3(c.ray.origin), dvec3(c.ray.direction),
                                             dvec3(c.center), c.radius, -INFINITY);
    const auto farRoot = referenceSphereHit(dvec3(c.ray.origin), dvec3(c.ray.direction),
                                            dvec3(c.center), c.radius, *nearRoot);
    if (std::fabs(*nearRoot) < 1e-5L * scale || (farRoot && std::fabs(*farRoot) < 1e-5L * scale))
      continue;
    if (!expected)
    {
      EXPECT_FALSE(kernelHit) << "case " << i << ": the sphere is behind the ray";
      ++misses;
      continue;
    }
    ++hits;
    ASSERT_TRUE(kernelHit) << "case " << i;
    EXPECT_NEAR(double(hit.t), double(*expected), double(1e-5L * std::max(*expected, scale)))
      << "case " << i;
    const dvec3 normal(hit.normal);
    EXPECT_NEAR(glm::length(normal), 1.0, 1e-5) << "case " << i;
    EXPECT_LT(glm::length(normal - referenceNormal(c.ray, *expected, c.center, c.radius)), 1e-4)
      << "case " << i << ": the normal must be the outward one at the hit";
  }
  // Guard against a generator that silently stopped producing one of the two outcomes.
  EXPECT_GT(hits, 5000);
  EXPECT_GT(misses, 5000);
}

TEST(IntersectSphere, RayFromInsideHitsTheFarSideWithAnOutwardNormal)
{
  std::mt19937 random(777);
  std::uniform_real_distribution<float> fraction(0.0f, 0.9f);
  for (int i = 0; i < 2000; ++i)
  {
    const vec3 center = 5.0f * randomUnitVector(random);
    const float radius = 0.5f + 3.0f * fraction(random);
    Ray ray;
    ray.origin = center + fraction(random) * radius * randomUnitVector(random);
    ray.direction = randomUnitVector(random);
    const auto expected = reference(ray, center, radius);
    ASSERT_TRUE(expected.has_value());
    SurfaceHit hit;
    ASSERT_TRUE(intersectSphere(center, radius, ray, hit)) << "case " << i;
    EXPECT_NEAR(hit.t, double(*expected), 1e-5 * radius) << "case " << i;
    // On the far side the outward normal points along the ray.
    EXPECT_GT(glm::dot(hit.normal, ray.direction), 0.0f) << "case " << i;
    EXPECT_LT(glm::length(dvec3(hit.normal) - referenceNormal(ray, *expected, center, radius)),
              1e-4);
  }
}

TEST(IntersectSphere, OriginAtTheCentreHitsAtTheRadius)
{
  Ray ray;
  ray.origin = vec3(1, 2, 3);
  ray.direction = vec3(0, 0.6f, 0.8f);
  SurfaceHit hit;
  ASSERT_TRUE(intersectSphere(ray.origin, 2.5f, ray, hit));
  EXPECT_NEAR(hit.t, 2.5f, 1e-6f);
  EXPECT_NEAR(hit.normal.y, 0.6f, 1e-6f);
  EXPECT_NEAR(hit.normal.z, 0.8f, 1e-6f);
}

TEST(IntersectSphere, SphereBehindTheRayIsMissed)
{
  Ray ray;
  ray.origin = vec3(0, 0, 0);
  ray.direction = vec3(0, 0, 1);
  SurfaceHit hit;
  EXPECT_FALSE(intersectSphere(vec3(0, 0, -10), 2.0f, ray, hit));
}

// Sphere at distance 10 along -z with radius 2: the roots are t = 8 and t = 12.
TEST(IntersectSphere, HonoursTnearAndTfar)
{
  const vec3 center(0, 0, -10);
  const float radius = 2.0f;
  struct Limits
  {
    float tnear, tfar;
    std::optional<float> expected;
  };
  const std::vector<Limits> cases{
    { 0.0f, sightline::kInfinity, 8.0f },
    { 7.9f, sightline::kInfinity, 8.0f },
    { 8.1f, sightline::kInfinity, 12.0f }, // near root excluded: the far one
    { 11.9f, 12.5f, 12.0f },
    { 12.1f, sightline::kInfinity, std::nullopt },
    { 0.0f, 8.1f, 8.0f },
    { 0.0f, 7.9f, std::nullopt },
    { 8.1f, 11.9f, std::nullopt }, // between the roots
    { -20.0f, sightline::kInfinity, 8.0f },
  };
  Ray ray;
  ray.direction = vec3(0, 0, -1);
  for (const Limits& limits : cases)
  {
    ray.tnear = limits.tnear;
    ray.tfar = limits.tfar;
    SurfaceHit hit;
    const bool found = intersectSphere(center, radius, ray, hit);
    ASSERT_EQ(found, limits.expected.has_value())
      << "tnear " << limits.tnear << ", tfar " << limits.tfar;
    if (found)
    {
      EXPECT_NEAR(hit.t, *limits.expected, 1e-5f);
    }
  }
}

TEST(IntersectSphere, RandomLimitsSelectTheRightRoot)
{
  std::mt19937 random(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 5000; ++i)
  {
    RandomCase c = randomCase(random);
    if (lineDistance(c.ray, c.center) > c.radius * 0.99L)
      continue;
    // Both roots from the unlimited ray; then limits placed between and around them.
    const long double t0 = *referenceSphereHit(dvec3(c.ray.origin), dvec3(c.ray.direction),
                                               dvec3(c.center), c.radius, -INFINITY);
    const long double t1 = *referenceSphereHit(dvec3(c.ray.origin), dvec3(c.ray.direction),
                                               dvec3(c.center), c.radius, t0);
    c.ray.tnear = float(t0 + (t1 - t0) * (u(random) * 1.4 - 0.2));
    c.ray.tfar = float(c.ray.tnear + (t1 - t0) * u(random) * 1.4);
    // Keep the limits clear of the roots so that float rounding cannot decide the outcome.
    const long double margin = 1e-3L * (t1 - t0);
    bool ambiguous = false;
    for (long double root : { t0, t1 })
      for (float limit : { c.ray.tnear, c.ray.tfar })
        ambiguous |= std::fabs(root - limit) < margin;
    if (ambiguous)
      continue;
    const auto expected = reference(c.ray, c.center, c.radius);
    SurfaceHit hit;
    const bool found = intersectSphere(c.center, c.radius, c.ray, hit);
    ASSERT_EQ(found, expected.has_value()) << "case " << i;
    if (found)
    {
      EXPECT_NEAR(hit.t, double(*expected),
                  double(1e-5L * std::max(std::fabs(*expected), t1 - t0)));
      EXPECT_GT(hit.t, c.ray.tnear);
      EXPECT_LT(hit.t, c.ray.tfar);
    }
  }
}

// Lines passing at r (1 - 1e-3) hit, at r (1 + 1e-3) miss, at every scale.
TEST(IntersectSphere, GrazingRays)
{
  std::mt19937 random(4242);
  for (float radius : { 1e-3f, 1.0f, 1e3f })
    for (int i = 0; i < 500; ++i)
    {
      const vec3 center = radius * 3.0f * randomUnitVector(random);
      Ray ray;
      ray.direction = randomUnitVector(random);
      const vec3 sideways = perpendicularTo(ray.direction, random);
      for (double offset : { 1 - 1e-3, 1 + 1e-3 })
      {
        ray.origin = center + float(offset) * radius * sideways - 10.0f * radius * ray.direction;
        const long double distance = lineDistance(ray, center);
        SurfaceHit hit;
        const bool found = intersectSphere(center, radius, ray, hit);
        if (distance > radius)
        {
          EXPECT_FALSE(found) << "radius " << radius << ", case " << i;
          continue;
        }
        const auto expected = reference(ray, center, radius);
        ASSERT_TRUE(expected.has_value());
        ASSERT_TRUE(found) << "radius " << radius << ", case " << i;
        EXPECT_NEAR(hit.t, double(*expected), 1e-5 * double(*expected))
          << "radius " << radius << ", case " << i;
      }
    }
}

// With the origin 1e4 radii away, b^2 - ac cancels away all float digits (the textbook form errs
// by several radii and misses a quarter of the hits). The distance-to-line form must be accurate
// to float precision of t itself: one ulp of t = 1e4 r is already about 1e-3 r, and rounding
// o - c, the dot products and the quotient leaves a few ulps (at most 3.3 FLT_EPSILON t measured
// over 9e5 rays), so the bound is 6 FLT_EPSILON t, about 7e-3 r.
TEST(IntersectSphere, FarAwayOriginKeepsAccuracyRelativeToTheRadius)
{
  std::mt19937 random(31337);
  std::uniform_real_distribution<float> impact(0.0f, 0.95f);
  int checked = 0;
  for (float radius : { 0.01f, 1.0f, 250.0f })
    for (int i = 0; i < 1000; ++i)
    {
      const vec3 center = radius * 2.0f * randomUnitVector(random);
      Ray ray;
      ray.direction = randomUnitVector(random);
      const vec3 sideways = perpendicularTo(ray.direction, random);
      ray.origin = center + impact(random) * radius * sideways - 1e4f * radius * ray.direction;
      const auto expected = reference(ray, center, radius);
      if (!expected || lineDistance(ray, center) > 0.95L * radius)
        continue;
      ++checked;
      SurfaceHit hit;
      ASSERT_TRUE(intersectSphere(center, radius, ray, hit))
        << "radius " << radius << ", case " << i;
      EXPECT_LT(std::fabs(hit.t - *expected), 6 * FLT_EPSILON * *expected)
        << "radius " << radius << ", case " << i;
    }
  EXPECT_GT(checked, 2500);
}
} // namespace
