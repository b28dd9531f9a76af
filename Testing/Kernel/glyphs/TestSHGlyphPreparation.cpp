// SPDX-License-Identifier: BSD-3-Clause
// SHGlyphPreparation: one conversion to the canonical basis whatever the input basis, rotation,
// normalisations, dropped glyphs, the per-point box cache, and ellipsoids from second-order
// tensors without SH boxes.
#include "sightline/glyphs/SHGlyphPreparation.h"

#include "sightline/glyphs/SHGlyph.h"
#include "sightline/glyphs/SHGlyphSet.h"
#include "sightline/math/SHRotation.h"
#include "sightline/math/SymmetricTensor.h"

#include "glyphs/SHGlyphTestSupport.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace
{
using sightline::GlyphNormalization;
using sightline::GlyphRequest;
using sightline::GlyphSource;
using sightline::SHGlyphPreparation;

/// A source over a table of per-point tuples (what a mapper's array reader does).
GlyphSource TableSource(const std::vector<std::vector<double>>& table, int order,
  sightline::SHConvention convention = { sightline::SHBasis::Canonical, false })
{
  GlyphSource source;
  source.pointCount = table.size();
  source.order = order;
  source.convention = convention;
  source.identity = &table;
  source.read = [&table](std::size_t point, double* out)
  { std::copy(table[point].begin(), table[point].end(), out); };
  return source;
}

std::vector<std::size_t> AllPoints(std::size_t n)
{
  std::vector<std::size_t> points(n);
  for (std::size_t i = 0; i < n; ++i)
    points[i] = i;
  return points;
}

std::vector<double> TwoFibres(int order)
{
  return sightline_test::glyph::fibreLobeCoefficients(
    order, { { 1.0, 0.2, 0.1 }, { -0.1, 0.3, 1.0 } }, 0.05, 40.0);
}
} // namespace

TEST(SHGlyphPreparation, DIPYInputGivesTheCanonicalGlyphOnce)
{
  const int order = 8;
  const std::vector<double> canonical = TwoFibres(order);
  // The same function in DIPY's legacy basis: invert the conversion on a basis vector each.
  const sightline::SHConvention dipy{ sightline::SHBasis::Descoteaux07, true };
  const auto conversion = sightline::SHConversion::toCanonical(dipy, order);
  std::vector<double> legacy(canonical.size(), 0.0);
  for (std::size_t j = 0; j < conversion.target.size(); ++j)
    legacy[j] = canonical[conversion.target[j]] / conversion.factor[j];
  const std::vector<std::vector<double>> a{ canonical }, b{ legacy };

  GlyphRequest request;
  request.points = { 0 };
  request.normalization = GlyphNormalization::None;
  SHGlyphPreparation first, second;
  const auto fromCanonical = first.prepare(TableSource(a, order), request);
  const auto fromDIPY = second.prepare(TableSource(b, order, dipy), request);
  ASSERT_EQ(fromCanonical.size(), 1u);
  ASSERT_EQ(fromDIPY.size(), 1u);
  ASSERT_EQ(fromDIPY.coefficients.size(), fromCanonical.coefficients.size());
  for (std::size_t j = 0; j < canonical.size(); ++j)
    EXPECT_NEAR(fromDIPY.coefficients[j], canonical[j], 1e-12);
  const glm::dvec3 box = sightline::shGlyphHalfExtents(order, canonical.data());
  EXPECT_NEAR(fromDIPY.halfExtents[0].x, box.x, 1e-6);
}

TEST(SHGlyphPreparation, RotatesNormalisesAndTrims)
{
  const int order = 8;
  std::vector<double> lowBands = TwoFibres(4);
  lowBands.resize(sightline::shCoefficientCount(order), 0.0); // bands 6 and 8 zero
  const std::vector<std::vector<double>> table{ TwoFibres(order), lowBands };
  const double angle = 0.7;
  const sightline::dmat3 rotation(glm::dvec3(std::cos(angle), std::sin(angle), 0.0),
    glm::dvec3(-std::sin(angle), std::cos(angle), 0.0), glm::dvec3(0.0, 0.0, 1.0));

  GlyphRequest request;
  request.points = AllPoints(2);
  request.rotation = rotation;
  request.worldScale = 2.0;
  request.maxAmplitudes = true;
  SHGlyphPreparation preparation;
  const auto glyphs = preparation.prepare(TableSource(table, order), request);
  ASSERT_EQ(glyphs.size(), 2u);
  EXPECT_EQ(glyphs.orders[0], 8);
  EXPECT_EQ(glyphs.orders[1], 4) << "trailing zero bands are dropped";

  std::vector<double> turned(table[0].size());
  sightline::SHRotation(order, rotation).apply(table[0].data(), turned.data());
  for (std::size_t j = 0; j < turned.size(); ++j)
    EXPECT_NEAR(glyphs.coefficients[glyphs.offsets[0] + j], turned[j], 1e-12);
  const double amplitude = sightline::shGlyphMaxRadius(order, table[0].data());
  EXPECT_NEAR(glyphs.maxAmplitudes[0], amplitude, 1e-5 * amplitude);
  EXPECT_NEAR(glyphs.scales[0], 2.0 / amplitude, 1e-5 * (2.0 / amplitude));

  request.normalization = GlyphNormalization::CoefficientNorm;
  const auto byNorm = preparation.prepare(TableSource(table, order), request);
  double norm = 0.0;
  for (double c : table[1])
    norm += c * c;
  EXPECT_NEAR(byNorm.scales[1], 2.0 / std::sqrt(norm), 1e-6);
}

TEST(SHGlyphPreparation, DropsInvalidAndZeroGlyphsAndCachesBoxes)
{
  const int order = 4;
  std::vector<double> nan = TwoFibres(order);
  nan[3] = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::vector<double>> table{ TwoFibres(order),
    std::vector<double>(TwoFibres(order).size(), 0.0), nan, TwoFibres(order) };
  GlyphRequest request;
  request.points = AllPoints(4);
  int progressCalls = 0;
  double lastProgress = 0.0;
  request.progress = [&](double p)
  {
    ++progressCalls;
    lastProgress = p;
  };
  SHGlyphPreparation preparation;
  const GlyphSource source = TableSource(table, order);
  const auto glyphs = preparation.prepare(source, request);
  EXPECT_EQ(glyphs.points, (std::vector<std::size_t>{ 0, 3 }));
  EXPECT_EQ(glyphs.drops.nonFinite, 1u);
  EXPECT_EQ(glyphs.drops.firstNonFinite, 2u);
  EXPECT_EQ(glyphs.drops.empty, 1u);
  EXPECT_EQ(glyphs.computedBoxes, 2u);
  EXPECT_GT(progressCalls, 0);
  EXPECT_EQ(lastProgress, 1.0);

  // A different scale reuses every box; a new version of the data recomputes them.
  request.worldScale = 3.0;
  const auto again = preparation.prepare(source, request);
  EXPECT_EQ(again.computedBoxes, 0u);
  EXPECT_NEAR(again.halfExtents[0].x, 3.0 * glyphs.halfExtents[0].x, 1e-5);
  GlyphSource changed = source;
  changed.version = 1;
  EXPECT_EQ(preparation.prepare(changed, request).computedBoxes, 2u);
  EXPECT_GT(preparation.memoryBytes(), 0u);

  request.points = { 7 };
  EXPECT_THROW(preparation.prepare(source, request), std::invalid_argument);
}

// Frustum culling: glyphs the request says cannot be seen get the loose cube of their
// coefficient bound instead of the box search, are not cached, get their near-exact box once a
// later request sees them, and are drawn the same either way (the box only bounds the search).
TEST(SHGlyphPreparation, CulledGlyphsGetLooseBoxesAndTheSameHits)
{
  const int order = 6;
  std::vector<std::vector<double>> table;
  for (int i = 0; i < 6; ++i)
  {
    const double a = 0.5 * i;
    table.push_back(sightline_test::glyph::fibreLobeCoefficients(order,
      { { std::cos(a), std::sin(a), 0.3 }, { -0.2, 0.4 * i, 1.0 } }, 0.05, 30.0));
  }
  const GlyphSource source = TableSource(table, order);
  GlyphRequest request;
  request.points = AllPoints(table.size());
  request.worldScale = 0.7;
  std::vector<double> radii(table.size(), -1.0);
  request.mayBeVisible = [&](std::size_t point, double radius)
  {
    radii.at(point) = radius;
    return point % 2 == 0;
  };
  SHGlyphPreparation culling;
  const auto culled = culling.prepare(source, request);
  ASSERT_EQ(culled.size(), table.size());
  EXPECT_EQ(culled.computedBoxes, 3u);
  EXPECT_EQ(culled.looseBoxCount, 3u);
  ASSERT_EQ(culled.looseBoxes.size(), table.size());

  GlyphRequest plain = request;
  plain.mayBeVisible = nullptr;
  SHGlyphPreparation fresh;
  const auto tight = fresh.prepare(source, plain);
  EXPECT_TRUE(tight.looseBoxes.empty());
  EXPECT_EQ(tight.looseBoxCount, 0u);
  for (std::size_t g = 0; g < table.size(); ++g)
  {
    SCOPED_TRACE("glyph " + std::to_string(g));
    const double* b = culled.coefficients.data() + culled.offsets[g];
    const double bound = sightline::shGlyphBoundingRadius(culled.orders[g], b);
    EXPECT_NEAR(radii[g], bound * culled.scales[g], 1e-12 * bound);
    EXPECT_EQ(culled.looseBoxes[g], g % 2 == 0 ? 0 : 1);
    for (int axis = 0; axis < 3; ++axis)
      if (g % 2 == 0)
        EXPECT_EQ(culled.halfExtents[g][axis], tight.halfExtents[g][axis]);
      else
      {
        EXPECT_GE(culled.halfExtents[g][axis], float(bound * culled.scales[g]));
        EXPECT_LE(culled.halfExtents[g][axis], float(1.00001 * bound * culled.scales[g]));
        EXPECT_GT(culled.halfExtents[g][axis], tight.halfExtents[g][axis]);
      }
  }

  // Seen now: exactly the loose boxes are computed, equal to a fresh preparation's.
  const auto seen = culling.prepare(source, plain);
  EXPECT_EQ(seen.computedBoxes, 3u);
  EXPECT_TRUE(seen.looseBoxes.empty());
  for (std::size_t g = 0; g < table.size(); ++g)
    for (int axis = 0; axis < 3; ++axis)
      EXPECT_EQ(seen.halfExtents[g][axis], tight.halfExtents[g][axis]);

  // The same hits through the loose and the tight boxes: rays down through a grid over each
  // glyph's loose box, from outside and from the glyph's centre.
  std::vector<sightline::vec3> centers;
  for (std::size_t g = 0; g < table.size(); ++g)
    centers.emplace_back(float(3 * g), 1.0f, -2.0f);
  const sightline::SHGlyphSet looseSet(centers, culled), tightSet(centers, tight);
  int hits = 0;
  for (unsigned g = 0; g < centers.size(); ++g)
  {
    const sightline::vec3 h = looseSet.halfExtents(g);
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 40; ++j)
        for (const double z : { 3.0, 0.0 })
        {
          const sightline::dvec3 origin = sightline::dvec3(centers[g]) +
            sightline::dvec3(h.x * (i / 20.0 - 1.0), h.y * (j / 20.0 - 1.0), z);
          const sightline::DoubleRay ray(origin, sightline::dvec3(0.1, -0.05, -1.0), 0.0, 1e30);
          sightline::SurfaceHit a, b;
          const bool hitLoose = looseSet.intersect(g, ray, a), hitTight = tightSet.intersect(g, ray, b);
          ASSERT_EQ(hitLoose, hitTight) << "glyph " << g << " ray " << i << ", " << j << ", z " << z;
          if (hitLoose)
          {
            ++hits;
            EXPECT_NEAR(a.t, b.t, 1e-6 * double(h.x));
          }
        }
  }
  EXPECT_GT(hits, 1000);
}

TEST(SHGlyphPreparation, PreparedGlyphSetMatchesTheConvertingConstructor)
{
  const int order = 6;
  const std::vector<std::vector<double>> table{ TwoFibres(order) };
  GlyphRequest request;
  request.points = { 0 };
  request.worldScale = 0.5;
  SHGlyphPreparation preparation;
  const auto glyphs = preparation.prepare(TableSource(table, order), request);
  const sightline::SHGlyphSet prepared({ sightline::vec3(1.0f, 2.0f, 3.0f) }, glyphs);

  std::vector<float> values(table[0].begin(), table[0].end());
  sightline::SHGlyphOptions options;
  options.convention = { sightline::SHBasis::Canonical, false };
  const sightline::SHGlyphSet converted(
    { sightline::vec3(1.0f, 2.0f, 3.0f) }, values, order, options, glyphs.scales);
  ASSERT_EQ(prepared.size(), 1u);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(prepared.halfExtents(0)[axis], converted.halfExtents(0)[axis], 1e-5);
  for (int j = 0; j < sightline::shCoefficientCount(order); ++j)
    EXPECT_NEAR(prepared.coefficients(0)[j], converted.coefficients(0)[j], 1e-6);
}

TEST(SHGlyphPreparation, EllipsoidsFollowTheEigenvectors)
{
  // diag(3, 1, 0.5) turned by 90 degrees about z: the long axis along y.
  const std::vector<std::vector<double>> table{ { 1.0, 0.0, 0.0, 3.0, 0.0, 0.5 },
    { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 } };
  GlyphRequest request;
  request.points = AllPoints(2);
  request.worldScale = 2.0;
  const auto ellipsoids = SHGlyphPreparation::prepareEllipsoids(TableSource(table, 2), request);
  ASSERT_EQ(ellipsoids.size(), 1u);
  EXPECT_EQ(ellipsoids.drops.empty, 1u);
  double longest = 0.0;
  for (int c = 0; c < 3; ++c)
    longest = std::max(longest, glm::length(ellipsoids.axes[0][c]));
  EXPECT_NEAR(longest, 2.0, 1e-12) << "normalisation makes the longest semi-axis the scale";
  EXPECT_EQ(ellipsoids.directionColors[0], sightline::packRGBA8(0, 255, 0));
}
