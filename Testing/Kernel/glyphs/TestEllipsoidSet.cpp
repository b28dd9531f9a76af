// SPDX-License-Identifier: BSD-3-Clause
// EllipsoidSet (vtkTensorGlyph's second-order shape, exact) against an independent reference:
// the implicit quadric (x - c)^T A (x - c) = 1 with A = (M M^T)^-1, solved in long double by
// bisection on the ray, and its gradient for normals.
#include "sightline/glyphs/EllipsoidSet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

using namespace sightline;

namespace
{
dmat3 randomAxes(std::mt19937& rng)
{
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> length(0.2, 2.0);
  // Orthonormal eigenvectors from Gram-Schmidt, scaled by three lengths.
  dvec3 a(normal(rng), normal(rng), normal(rng)), b(normal(rng), normal(rng), normal(rng));
  a = glm::normalize(a);
  b = glm::normalize(b - glm::dot(a, b) * a);
  const dvec3 c = glm::cross(a, b);
  return dmat3(a * length(rng), b * length(rng), c * length(rng));
}

/// q(x) = (x - c)^T A (x - c) - 1 in long double.
long double quadric(const dmat3& m, const dvec3& c, const dvec3& x)
{
  const dmat3 a = glm::inverse(m * glm::transpose(m));
  const dvec3 d = x - c;
  long double sum = 0.0L;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      sum += (long double)d[i] * a[j][i] * d[j];
  return sum - 1.0L;
}

/// First root of q on the ray by dense sampling plus bisection, or -1.
double referenceHit(const dmat3& m, const dvec3& c, const dvec3& o, const dvec3& d, double tmax)
{
  const int samples = 20000;
  double previous = 0.0;
  long double qPrevious = quadric(m, c, o);
  for (int i = 1; i <= samples; ++i)
  {
    const double t = tmax * i / samples;
    const long double q = quadric(m, c, o + t * d);
    if ((q < 0) != (qPrevious < 0))
    {
      double lo = previous, hi = t;
      for (int k = 0; k < 80; ++k)
      {
        const double mid = 0.5 * (lo + hi);
        ((quadric(m, c, o + mid * d) < 0) == (qPrevious < 0) ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    }
    previous = t;
    qPrevious = q;
  }
  return -1.0;
}

Ray makeRay(const dvec3& o, const dvec3& d)
{
  Ray ray;
  ray.origin = vec3(o);
  ray.direction = vec3(d);
  ray.tnear = 0.0f;
  ray.tfar = std::numeric_limits<float>::infinity();
  return ray;
}
} // namespace

TEST(EllipsoidSet, HitsAndNormalsMatchTheImplicitQuadric)
{
  std::mt19937 rng(21);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  int hits = 0;
  for (int e = 0; e < 20; ++e)
  {
    const dmat3 m = randomAxes(rng);
    const vec3 centre(uniform(rng), uniform(rng), uniform(rng));
    const EllipsoidSet set({ centre }, { m });
    ASSERT_EQ(set.size(), 1u);
    for (int r = 0; r < 100; ++r)
    {
      const dvec3 d = glm::normalize(dvec3(normal(rng), normal(rng), normal(rng)));
      const dvec3 target = dvec3(centre) + 1.5 * dvec3(uniform(rng), uniform(rng), uniform(rng));
      const dvec3 o = target - 6.0 * d;
      const double reference = referenceHit(m, dvec3(centre), dvec3(vec3(o)), dvec3(vec3(d)), 12.0);
      SurfaceHit hit;
      const bool found = set.intersect(0, makeRay(o, d), hit);
      if (reference < 0.0)
      {
        // Only grazing rays may disagree, and then by a hair.
        if (found)
        {
          EXPECT_LT(std::abs(quadric(m, dvec3(centre), dvec3(vec3(o)) + double(hit.t) * dvec3(vec3(d)))), 1e-4);
        }
        continue;
      }
      ASSERT_TRUE(found) << "ellipsoid " << e << " ray " << r;
      ++hits;
      EXPECT_NEAR(hit.t, reference, 2e-5 * (1.0 + reference));
      // Normal parallel to the quadric's gradient A (x - c).
      const dvec3 x = dvec3(vec3(o)) + reference * dvec3(vec3(d));
      const dvec3 gradient = glm::inverse(m * glm::transpose(m)) * (x - dvec3(centre));
      EXPECT_GT(glm::dot(glm::normalize(dvec3(hit.normal)), glm::normalize(gradient)), 1.0 - 1e-5);
      // The box holds the hit point.
      const Box3 box = set.bounds(0);
      for (int axis = 0; axis < 3; ++axis)
      {
        EXPECT_GE(float(x[axis]), box.lower[axis] - 1e-5f);
        EXPECT_LE(float(x[axis]), box.upper[axis] + 1e-5f);
      }
    }
  }
  EXPECT_GT(hits, 600);
}

TEST(EllipsoidSet, InsideFarAwayAndTightBox)
{
  const dmat3 m(dvec3(2, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 0.5));
  const EllipsoidSet set({ vec3(1, 2, 3) }, { m });
  SurfaceHit hit;
  // From the centre: the far side along each axis, at the semi-axis length.
  ASSERT_TRUE(set.intersect(0, makeRay(dvec3(1, 2, 3), dvec3(1, 0, 0)), hit));
  EXPECT_NEAR(hit.t, 2.0f, 1e-6f);
  ASSERT_TRUE(set.intersect(0, makeRay(dvec3(1, 2, 3), dvec3(0, 0, -1)), hit));
  EXPECT_NEAR(hit.t, 0.5f, 1e-6f);
  // From 1e4 away along y: the near side at distance 1e4 - 1.
  ASSERT_TRUE(set.intersect(0, makeRay(dvec3(1, 2 - 1e4, 3), dvec3(0, 1, 0)), hit));
  EXPECT_NEAR(hit.t, 1e4f - 1.0f, 2e-3f);
  // Tangent line at x = 1 + 2 (touches), slightly outside (misses).
  EXPECT_FALSE(set.intersect(0, makeRay(dvec3(3.001, -10, 3), dvec3(0, 1, 0)), hit));
  // The box of an axis-aligned ellipsoid is its semi-axes.
  const Box3 box = set.bounds(0);
  EXPECT_NEAR(box.upper.x, 3.0f, 1e-4f);
  EXPECT_NEAR(box.lower.z, 2.5f, 1e-4f);
}

TEST(EllipsoidSet, BadInputIsDroppedOrThrown)
{
  const dmat3 good(1.0), singular(dvec3(1, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 0));
  dmat3 nan(1.0);
  nan[1][1] = std::numeric_limits<double>::quiet_NaN();
  const EllipsoidSet set({ vec3(0), vec3(1), vec3(2), vec3(std::numeric_limits<float>::infinity()) },
    { good, singular, nan, good });
  EXPECT_EQ(set.size(), 1u);
  EXPECT_EQ(set.report().rejected, 3u);
  EXPECT_EQ(set.report().reasons.size(), 2u);
  EXPECT_EQ(set.sourceIndex()[0], 0u);
  EXPECT_THROW(EllipsoidSet({ vec3(0) }, {}), std::invalid_argument);
  EXPECT_THROW(EllipsoidSet({ vec3(0) }, { good }, { 1u, 2u }), std::invalid_argument);
}
