// SPDX-License-Identifier: BSD-3-Clause
// SHRotation: the turned glyph G(w) = F(R^T w) is checked pointwise with the kernel's SH
// evaluation (itself verified against MRtrix3 and DIPY), for proper and improper rotations of
// random functions up to order 16; rotations compose; non-orthogonal matrices are refused.
#include "sightline/math/SHRotation.h"
#include "sightline/math/SphericalHarmonics.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace
{
using sightline::dvec3;

glm::dmat3 randomRotation(std::mt19937& random)
{
  std::normal_distribution<double> normal;
  const dvec3 axis = glm::normalize(dvec3(normal(random), normal(random), normal(random)));
  const double angle = std::uniform_real_distribution<double>(0.1, 3.0)(random);
  return glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, axis));
}

std::vector<double> randomFunction(int order, std::mt19937& random)
{
  std::normal_distribution<double> normal;
  std::vector<double> c(sightline::shCoefficientCount(order));
  for (double& v : c)
    v = normal(random);
  return c;
}

double evaluate(int order, const std::vector<double>& c, const dvec3& w)
{
  const dvec3 u = glm::normalize(w);
  return sightline::evaluateSHSum<double>(order, c.data(), u.x, u.y, u.z);
}
} // namespace

TEST(SHRotation, TurnedFunctionMatchesPointwise)
{
  std::mt19937 random(31);
  std::normal_distribution<double> normal;
  for (int order = 0; order <= 16; order += 2)
  {
    for (bool reflect : { false, true })
    {
      glm::dmat3 R = randomRotation(random);
      if (reflect)
        R = R * glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1));
      const std::vector<double> f = randomFunction(order, random);
      std::vector<double> g(f.size());
      sightline::SHRotation(order, R).apply(f.data(), g.data());
      double scale = 0.0;
      for (double v : f)
        scale += v * v;
      scale = std::sqrt(scale);
      for (int s = 0; s < 50; ++s)
      {
        const dvec3 w = glm::normalize(dvec3(normal(random), normal(random), normal(random)));
        EXPECT_NEAR(evaluate(order, g, R * w), evaluate(order, f, w), 1e-9 * scale)
          << "order " << order << (reflect ? " with reflection" : "");
      }
    }
  }
}

TEST(SHRotation, RotationsComposeAndTheIdentityChangesNothing)
{
  std::mt19937 random(5);
  const int order = 8;
  const glm::dmat3 A = randomRotation(random), B = randomRotation(random);
  const std::vector<double> f = randomFunction(order, random);
  std::vector<double> a(f.size()), ba(f.size()), direct(f.size()), same(f.size());
  sightline::SHRotation(order, A).apply(f.data(), a.data());
  sightline::SHRotation(order, B).apply(a.data(), ba.data());
  sightline::SHRotation(order, B * A).apply(f.data(), direct.data());
  sightline::SHRotation(order, glm::dmat3(1.0)).apply(f.data(), same.data());
  for (std::size_t i = 0; i < f.size(); ++i)
  {
    EXPECT_NEAR(ba[i], direct[i], 1e-10);
    EXPECT_NEAR(same[i], f[i], 1e-12);
  }
}

TEST(SHRotation, RefusesBadInput)
{
  EXPECT_THROW(sightline::SHRotation(8, glm::dmat3(2.0)), std::invalid_argument);
  EXPECT_THROW(sightline::SHRotation(3, glm::dmat3(1.0)), std::invalid_argument);
  EXPECT_THROW(sightline::SHRotation(18, glm::dmat3(1.0)), std::invalid_argument);
}
