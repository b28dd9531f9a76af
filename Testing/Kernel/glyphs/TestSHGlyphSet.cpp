// SPDX-License-Identifier: BSD-3-Clause
// SHGlyphSet: input validation (throw or drop and report), SH conventions, band trimming, boxes,
// the Embree user geometry (nearest hit against brute force, occlusion, hidden negative lobes),
// surface colours, the ray-marching baselines and the inside length that uncertainty volumes use.
//
// References are independent of the code under test where that is cheap: the conventions are
// built from DIPY's definitions written with std::sph_legendre and projected by quadrature, a
// sphere glyph is checked against the analytic chord, and a k = 4 glyph's inside length against
// a dense scan refined by bisection.
#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Renderer.h"
#include "sightline/glyphs/SHGlyphSet.h"
#include "sightline/spheres/SphereSet.h"

#include "glyphs/SHGlyphTestSupport.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using sightline::Box3;
using sightline::dvec3;
using sightline::EmbreeScene;
using sightline::kMaxGlyphHits;
using sightline::Ray;
using sightline::SHBasis;
using sightline::SHColoring;
using sightline::SHConvention;
using sightline::SHGlyphOptions;
using sightline::SHGlyphSet;
using sightline::SHIntersectionMethod;
using sightline::SHMarchingBound;
using sightline::SurfaceHit;
using sightline::vec3;

using sightline::kPi;
const double kY00 = 0.5 / std::sqrt(kPi); // the constant basis function
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

SHConvention canonicalConvention()
{
  return { SHBasis::Canonical, false };
}

SHGlyphOptions canonicalOptions()
{
  SHGlyphOptions options;
  options.convention = canonicalConvention();
  return options;
}

double glyphFunction(int order, const double* b, const dvec3& w)
{
  return sightline::evaluateSHSum<double>(order, b, w.x, w.y, w.z);
}

std::vector<dvec3> fibonacciSphere(int count)
{
  std::vector<dvec3> directions(count);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i)
  {
    const double z = 1.0 - (2.0 * i + 1.0) / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    directions[i] = { r * std::cos(golden * i), r * std::sin(golden * i), z };
  }
  return directions;
}

/// Scales canonical coefficients so that max |F| over many directions is `radius`.
void normalizeRadius(int order, std::vector<double>& b, double radius)
{
  double largest = 0.0;
  for (const dvec3& w : fibonacciSphere(4000))
    largest = std::max(largest, std::fabs(glyphFunction(order, b.data(), w)));
  for (double& c : b)
    c *= radius / largest;
}

/// A fibre-like ODF: an isotropic part plus band-limited, smoothed deltas along `fibres`
/// (canonical coefficients, max |F| = radius).
std::vector<double> fibreGlyph(int order, const std::vector<dvec3>& fibres, double isotropic,
                               double sharpness, double radius = 1.0)
{
  std::vector<double> b =
    sightline_test::glyph::fibreLobeCoefficients(order, fibres, isotropic, sharpness);
  normalizeRadius(order, b, radius);
  return b;
}

/// Uniformly random coefficients in [-1, 1] (as the paper's AABB validation) plus `offset` on
/// the constant term, normalised to max |F| = radius.
std::vector<double> randomGlyph(int order, std::mt19937& random, double offset, double radius = 1.0)
{
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> b(sightline::shCoefficientCount(order));
  for (double& c : b)
    c = uniform(random);
  b[0] += offset;
  normalizeRadius(order, b, radius);
  return b;
}

/// Rounds to float: the glyph set takes float input, so tests compare against what it received.
std::vector<float> toFloat(const std::vector<double>& values)
{
  return std::vector<float>(values.begin(), values.end());
}

/// The values rounded to float and kept in double: coefficients that the glyph set's float
/// input holds exactly, so conversions by +-1 compare bit for bit.
std::vector<double> floatRepresentable(const std::vector<double>& values)
{
  const std::vector<float> rounded = toFloat(values);
  return std::vector<double>(rounded.begin(), rounded.end());
}

dvec3 randomUnit(std::mt19937& random)
{
  std::normal_distribution<double> normal;
  dvec3 v;
  do
    v = { normal(random), normal(random), normal(random) };
  while (glm::length(v) < 1e-6);
  return glm::normalize(v);
}

/// A ray from `distance` away from `center` aimed at a random point within `spread` of it.
Ray rayTowards(const dvec3& center, double distance, double spread, std::mt19937& random)
{
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const dvec3 origin = center + distance * randomUnit(random);
  const dvec3 target = center + spread * std::cbrt(unit(random)) * randomUnit(random);
  Ray ray;
  ray.origin = vec3(origin);
  ray.direction = vec3(glm::normalize(target - origin));
  return ray;
}

/// The nearest intersection in (tnear, tfar) from the all-intersections query.
std::optional<double> firstRoot(const SHGlyphSet& set, unsigned primitive, const Ray& ray)
{
  double t[kMaxGlyphHits];
  const int count = set.allIntersections(primitive, ray, t);
  for (int i = 0; i < count; ++i)
    if (t[i] > double(ray.tnear) && t[i] < double(ray.tfar))
      return t[i];
  return std::nullopt;
}

dvec3 pointOnRay(const Ray& ray, double t)
{
  return dvec3(ray.origin) + t * dvec3(ray.direction);
}

std::shared_ptr<SHGlyphSet> singleGlyph(const std::vector<double>& b, int order,
                                        SHGlyphOptions options = canonicalOptions(),
                                        const vec3& center = vec3(0.0f))
{
  return std::make_shared<SHGlyphSet>(std::vector<vec3>{ center }, toFloat(b), order, options);
}

std::unique_ptr<EmbreeScene> sceneOf(std::shared_ptr<const sightline::Geometry> geometry)
{
  auto scene = std::make_unique<EmbreeScene>();
  scene->add(std::move(geometry));
  scene->commit();
  return scene;
}

/// A measured number for RecordProperty, with its significant digits.
std::string number(double value)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%.4g", value);
  return text;
}

/// Runs `construct` and returns the std::invalid_argument message it throws (fails otherwise).
std::string invalidArgumentMessage(const std::function<void()>& construct)
{
  try
  {
    construct();
  }
  catch (const std::invalid_argument& error)
  {
    return error.what();
  }
  catch (...)
  {
    ADD_FAILURE() << "threw something other than std::invalid_argument";
    return {};
  }
  ADD_FAILURE() << "did not throw";
  return {};
}

void expectMentions(const std::string& message, const std::vector<std::string>& parts)
{
  for (const std::string& part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << "'" << message << "' should name '" << part << "'";
}

// ---------------------------------------------------------------------------------------------
// Bad input

TEST(SHGlyphSetInput, WrongArraySizesThrowNamingTheSizes)
{
  const std::vector<vec3> centers(3, vec3(0.0f));
  const std::vector<float> good(45, 0.1f); // 3 glyphs x 15 coefficients of order 4

  // One coefficient short, and a whole order-6 glyph's worth per glyph (28 x 3 = 84).
  expectMentions(invalidArgumentMessage(
                   [&] { SHGlyphSet(centers, std::vector<float>(44, 0.1f), 4); }),
                 { "coefficient", "44", "45", "15 per glyph", "order 4" });
  expectMentions(invalidArgumentMessage(
                   [&] { SHGlyphSet(centers, std::vector<float>(84, 0.1f), 4); }),
                 { "coefficient", "84", "45" });
  expectMentions(invalidArgumentMessage([&] { SHGlyphSet(centers, {}, 2); }),
                 { "coefficient", "0 values", "18" });
  // Per-glyph arrays of the wrong length.
  expectMentions(invalidArgumentMessage(
                   [&] { SHGlyphSet(centers, good, 4, {}, std::vector<float>{ 1.0f, 2.0f }); }),
                 { "scale", "2 values", "3 glyphs" });
  expectMentions(invalidArgumentMessage(
                   [&] {
                     SHGlyphSet(centers, good, 4, {}, {}, std::vector<std::uint32_t>(4, 0xffffffffu));
                   }),
                 { "colo", "4 values", "3 glyphs" });
  // A baseline without steps.
  SHGlyphOptions marching;
  marching.method = SHIntersectionMethod::RayMarching;
  marching.marchingSteps = 0;
  EXPECT_THROW(SHGlyphSet(centers, good, 4, marching), std::invalid_argument);

  // The same arrays with matching sizes are accepted.
  EXPECT_NO_THROW(SHGlyphSet(centers, good, 4, {}, std::vector<float>(3, 1.0f),
                             std::vector<std::uint32_t>(3, 0xffffffffu)));
}

TEST(SHGlyphSetInput, OrdersMustBeEvenAndAtMostSixteen)
{
  const std::vector<vec3> center{ vec3(0.0f) };
  // The coefficient arrays have the length the formula gives, so only the order is wrong.
  for (int order : { 3, 7, 18, 20, -2 })
  {
    const int count = std::max(1, (order + 1) * (order + 2) / 2);
    const std::string message = invalidArgumentMessage(
      [&] { SHGlyphSet(center, std::vector<float>(count, 0.1f), order); });
    expectMentions(message, { std::to_string(order), "even", "16" });
  }
  // The largest supported order works end to end.
  std::vector<float> order16(sightline::shCoefficientCount(16), 0.0f);
  order16[0] = 1.0f;
  order16[sightline::shIndex(16, 3)] = 0.05f;
  const SHGlyphSet set(center, order16, 16, canonicalOptions());
  ASSERT_EQ(set.size(), 1u);
  EXPECT_EQ(set.order(0), 16);
  Ray ray;
  ray.origin = vec3(0.0f, 0.0f, 5.0f);
  SurfaceHit hit;
  EXPECT_TRUE(set.intersect(0, ray, hit));
}

TEST(SHGlyphSetInput, InvalidGlyphsAreDroppedReportedAndTheRestStillTrace)
{
  // Order 2 (6 coefficients): a sphere of radius 0.5 stretched a little along z.
  const int order = 2;
  std::vector<float> sphere(6, 0.0f);
  sphere[0] = float(0.5 / kY00);
  sphere[sightline::shIndex(2, 0)] = 0.1f;
  const std::vector<float> zero(6, 0.0f);
  std::vector<float> nanCoefficient = sphere, infCoefficient = sphere;
  nanCoefficient[3] = kNaN;
  infCoefficient[5] = -kInf;

  // 0, 2, 6, 9 are valid; 1, 3 have non-finite coefficients, 4 a NaN centre, 8 a NaN scale;
  // 5 has zero coefficients and 7 a zero scale (zero after scaling).
  // Every glyph has its own (x, y), so a ray along -z aims at one glyph only.
  const std::vector<vec3> centers{ { 0, 0, 0 },   { -3, 0, 0 },  { 3, 0, 0 }, { 0, -3, 0 },
                                   { kNaN, 0, 0 }, { 3, -3, 1 }, { 0, 3, 0 }, { 3, 3, 0 },
                                   { -3, -3, 0 },  { -3, 3, -1 } };
  const std::vector<const std::vector<float>*> inputs{
    &sphere, &nanCoefficient, &sphere, &infCoefficient, &sphere, &zero, &sphere, &sphere, &sphere, &sphere
  };
  std::vector<float> coefficients;
  for (const auto* input : inputs)
    coefficients.insert(coefficients.end(), input->begin(), input->end());
  std::vector<float> scales(10, 1.0f);
  scales[7] = 0.0f;
  scales[8] = kNaN;
  scales[9] = 2.0f;
  std::vector<std::uint32_t> colors;
  for (int i = 0; i < 10; ++i)
    colors.push_back(sightline::packRGBA8(std::uint8_t(20 * i), 7, 200));

  SHGlyphOptions options = canonicalOptions();
  options.coloring = SHColoring::PerGlyph;
  const auto set = std::make_shared<SHGlyphSet>(centers, coefficients, order, options, scales, colors);

  const sightline::ValidationReport& report = set->report();
  EXPECT_FALSE(report.clean());
  EXPECT_EQ(report.rejected, 6u);
  ASSERT_EQ(report.reasons.size(), 2u) << "one line per kind of problem";
  std::string all;
  for (const std::string& reason : report.reasons)
    all += reason + "\n";
  bool namedNonFinite = false, namedZero = false;
  for (const std::string& reason : report.reasons)
  {
    namedNonFinite |= reason.find("glyph 1 ") != std::string::npos && reason.find("non-finite") != std::string::npos;
    namedZero |= reason.find("glyph 5 ") != std::string::npos && reason.find("zero") != std::string::npos;
  }
  EXPECT_TRUE(namedNonFinite) << all;
  EXPECT_TRUE(namedZero) << all;

  const std::vector<std::uint32_t> kept{ 0, 2, 6, 9 };
  ASSERT_EQ(set->size(), kept.size());
  EXPECT_EQ(set->sourceIndex(), kept);
  for (unsigned p = 0; p < set->size(); ++p)
  {
    EXPECT_EQ(set->center(p), centers[kept[p]]);
    const double scale = scales[kept[p]];
    EXPECT_EQ(set->coefficients(p)[0], double(sphere[0]) * scale);
    const std::uint32_t c = colors[kept[p]];
    EXPECT_EQ(set->primitiveColor(p),
              vec3(float(c & 0xffu), float((c >> 8) & 0xffu), float((c >> 16) & 0xffu)) / 255.0f);
  }

  // Rays through the scene: each kept glyph is hit where it should be and maps back to its
  // input index; rays aimed where dropped glyphs would have been hit nothing.
  const auto scene = sceneOf(set);
  for (std::size_t i = 0; i < centers.size(); ++i)
  {
    if (!sightline::isFinite(centers[i]))
      continue;
    Ray ray;
    ray.origin = vec3(centers[i].x, centers[i].y, 20.0f);
    ray.direction = vec3(0.0f, 0.0f, -1.0f);
    RTCRayHit rh = sightline::makeRayHit(ray);
    const bool hit = scene->intersect(rh);
    const bool isKept = std::find(kept.begin(), kept.end(), std::uint32_t(i)) != kept.end();
    ASSERT_EQ(hit, isKept) << "glyph " << i;
    if (!hit)
      continue;
    EXPECT_EQ(set->sourceIndex()[rh.hit.primID], i);
    // The top of the glyph: F(z) = 0.5 + 0.1 Y_2^0(z) times the scale.
    const double top = scales[i] * (sphere[0] * kY00 + sphere[sightline::shIndex(2, 0)] *
                                                         std::sqrt(5.0 / (4.0 * kPi)));
    EXPECT_NEAR(rh.ray.tfar, 20.0 - centers[i].z - top, 1e-4) << "glyph " << i;
  }

  // Rendered from +z with an unlit material, each kept glyph's centre pixel shows its own
  // input colour (parallel view of [-5, 5]^2 on 100 x 100 pixels: 10 pixels per unit).
  set->material.ambient = 1.0f;
  set->material.diffuse = 0.0f;
  sightline::CameraParameters parameters;
  parameters.position = { 0, 0, 20 };
  parameters.parallelProjection = true;
  parameters.parallelScale = 5.0;
  parameters.nearClip = 1.0;
  parameters.farClip = 40.0;
  const sightline::Camera camera = sightline::Camera::fromParameters(parameters, 100, 100);
  sightline::Framebuffer framebuffer;
  const auto statistics = sightline::Renderer().render(
    *scene, camera, sightline::Lighting::headlight(vec3(0.0f, 0.0f, -1.0f)), framebuffer);
  EXPECT_GT(statistics.hits, 4u * 50u);
  for (std::size_t i = 0; i < centers.size(); ++i)
  {
    if (!sightline::isFinite(centers[i]))
      continue;
    const int px = int(std::lround((centers[i].x + 5.0f) * 10.0f));
    const int py = int(std::lround((centers[i].y + 5.0f) * 10.0f));
    const sightline::vec4 color = framebuffer.Color[framebuffer.index(px, py)];
    const bool isKept = std::find(kept.begin(), kept.end(), std::uint32_t(i)) != kept.end();
    ASSERT_EQ(color.a > 0.0f, isKept) << "glyph " << i;
    if (isKept)
    {
      const std::uint32_t c = colors[i];
      EXPECT_EQ(vec3(color), vec3(float(c & 0xffu), float((c >> 8) & 0xffu), float((c >> 16) & 0xffu)) / 255.0f)
        << "glyph " << i;
    }
  }

  // Everything dropped: an empty geometry that Embree accepts and nothing hits.
  const auto none = std::make_shared<SHGlyphSet>(std::vector<vec3>{ vec3(0.0f), vec3(kNaN) },
                                                 std::vector<float>(12, 0.0f), order);
  EXPECT_EQ(none->size(), 0u);
  EXPECT_EQ(none->report().rejected, 2u);
  EXPECT_TRUE(none->bounds().empty());
  const auto emptyScene = sceneOf(none);
  Ray ray;
  ray.origin = vec3(0.0f, 0.0f, 5.0f);
  RTCRayHit rh = sightline::makeRayHit(ray);
  EXPECT_FALSE(emptyScene->intersect(rh));
}

// ---------------------------------------------------------------------------------------------
// Conventions

/// Basis function (l, m) of a convention at polar angle theta and azimuth phi, written from
/// DIPY's definitions (real_sh_descoteaux_from_index, real_sh_tournier_from_index) with
/// scipy's Y_l^m = std::sph_legendre(l, m, theta) e^{i m phi} (both carry the Condon-Shortley
/// phase) and Y_l^{-m} = (-1)^m conj(Y_l^m). The canonical basis has no Condon-Shortley phase.
double conventionBasis(const SHConvention& convention, int l, int m, double theta, double phi)
{
  const int am = std::abs(m);
  const double s = std::sph_legendre(unsigned(l), unsigned(am), theta);
  const double sqrt2 = std::sqrt(2.0);
  const double csPhase = am % 2 == 1 ? -1.0 : 1.0;
  if (m == 0)
    return s;
  switch (convention.basis)
  {
    case SHBasis::Canonical:
      return sqrt2 * csPhase * s * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
    case SHBasis::Descoteaux07:
      // m > 0: sqrt2 Im Y_l^m; m < 0: sqrt2 Re Y_l^|m| (legacy) or sqrt2 Re Y_l^m.
      if (m > 0)
        return sqrt2 * s * std::sin(am * phi);
      return sqrt2 * s * std::cos(am * phi) * (convention.legacy ? 1.0 : csPhase);
    case SHBasis::Tournier07:
      // m > 0: Re Y_l^m; m < 0: Im Y_l^|m|; times sqrt2 unless legacy.
      return (convention.legacy ? 1.0 : sqrt2) * s * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
  }
  return 0.0;
}

/// Gauss-Legendre nodes and weights on [-1, 1].
void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w)
{
  x.resize(n);
  w.resize(n);
  for (int i = 0; i < n; ++i)
  {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration)
    {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k)
      {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (z * p1 - p0) / (z * z - 1.0);
      const double step = p1 / derivative;
      z -= step;
      if (std::fabs(step) < 1e-16)
        break;
    }
    x[i] = z;
    w[i] = 2.0 / ((1.0 - z * z) * derivative * derivative);
  }
}

/// Coefficients of the function with canonical coefficients `canonical` in another convention,
/// by projection onto that convention's (orthogonal) basis with a quadrature that is exact for
/// the products involved (degree <= 2 * order).
std::vector<double> toConvention(const std::vector<double>& canonical, int order,
                                 const SHConvention& convention)
{
  const int nTheta = order + 4, nPhi = 2 * order + 8;
  std::vector<double> z, weight;
  gaussLegendre(nTheta, z, weight);
  const int count = sightline::shCoefficientCount(order);
  std::vector<double> numerator(count, 0.0), denominator(count, 0.0);
  const SHConvention canonicalBasis = canonicalConvention();
  for (int i = 0; i < nTheta; ++i)
    for (int k = 0; k < nPhi; ++k)
    {
      const double theta = std::acos(z[i]), phi = 2.0 * kPi * k / nPhi;
      const double q = weight[i] * 2.0 * kPi / nPhi;
      double f = 0.0;
      for (int l = 0; l <= order; l += 2)
        for (int m = -l; m <= l; ++m)
          f += canonical[sightline::shIndex(l, m)] * conventionBasis(canonicalBasis, l, m, theta, phi);
      for (int l = 0; l <= order; l += 2)
        for (int m = -l; m <= l; ++m)
        {
          const double basis = conventionBasis(convention, l, m, theta, phi);
          numerator[sightline::shIndex(l, m)] += q * f * basis;
          denominator[sightline::shIndex(l, m)] += q * basis * basis;
        }
    }
  std::vector<double> result(count);
  for (int j = 0; j < count; ++j)
    result[j] = numerator[j] / denominator[j];
  return result;
}

// The same glyph in each convention DIPY and MRtrix3 write gives the same canonical coefficients
// and the same intersections. The conversions with factors +-1 must reproduce the float input
// bit for bit; MRtrix 0.2's legacy tournier07 carries sqrt(2), so its float input is rounded
// differently and agrees to float precision (coefficients within 1e-7 relative, hits within
// 1e-5 of a unit-size glyph).
TEST(SHGlyphSetConventions, EveryConventionGivesTheSameGlyph)
{
  const int order = 8;
  std::mt19937 random(20230);
  // Float-representable canonical coefficients, so that conversions by +-1 are exact.
  const std::vector<double> canonical = floatRepresentable(randomGlyph(order, random, 3.0));

  // My basis definitions agree with the kernel's canonical basis (otherwise this test would
  // compare against the wrong functions).
  std::vector<double> y(sightline::shCoefficientCount(order));
  for (const dvec3& w : fibonacciSphere(50))
  {
    sightline::evaluateSH<double>(order, w.x, w.y, w.z, y.data());
    const double theta = std::acos(std::clamp(w.z, -1.0, 1.0)), phi = std::atan2(w.y, w.x);
    for (int l = 0; l <= order; l += 2)
      for (int m = -l; m <= l; ++m)
        ASSERT_NEAR(conventionBasis(canonicalConvention(), l, m, theta, phi),
                    y[sightline::shIndex(l, m)], 1e-12)
          << "l " << l << " m " << m;
  }

  const std::vector<SHConvention> conventions{
    canonicalConvention(),
    { SHBasis::Descoteaux07, true },
    { SHBasis::Descoteaux07, false },
    { SHBasis::Tournier07, false },
    { SHBasis::Tournier07, true },
  };
  const std::vector<vec3> centers{ vec3(0.25f, -0.5f, 1.0f) };
  std::vector<std::unique_ptr<SHGlyphSet>> sets;
  for (const SHConvention& convention : conventions)
  {
    const std::vector<double> input = toConvention(canonical, order, convention);
    SHGlyphOptions options;
    options.convention = convention;
    sets.push_back(std::make_unique<SHGlyphSet>(centers, toFloat(input), order, options));
    ASSERT_EQ(sets.back()->size(), 1u);
    ASSERT_EQ(sets.back()->order(0), order);
  }
  // The conventions differ somewhere: a convention-blind implementation would fail below.
  const std::vector<double> legacyInput = toConvention(canonical, order, conventions[1]);
  int differing = 0;
  for (std::size_t j = 0; j < canonical.size(); ++j)
    differing += std::fabs(legacyInput[j] - canonical[j]) > 1e-3;
  EXPECT_GT(differing, 10);

  double largest = 0.0;
  for (double c : canonical)
    largest = std::max(largest, std::fabs(c));
  for (std::size_t s = 0; s < sets.size(); ++s)
  {
    const bool exact = !(conventions[s].basis == SHBasis::Tournier07 && conventions[s].legacy);
    for (std::size_t j = 0; j < canonical.size(); ++j)
    {
      if (exact)
        EXPECT_EQ(sets[s]->coefficients(0)[j], canonical[j]) << conventions[s].name() << " j " << j;
      else
        EXPECT_NEAR(sets[s]->coefficients(0)[j], canonical[j], 1e-7 * largest)
          << conventions[s].name() << " j " << j;
    }
  }

  int hits = 0;
  for (int r = 0; r < 300; ++r)
  {
    const Ray ray = rayTowards(dvec3(centers[0]), 3.0, 1.0, random);
    SurfaceHit reference;
    const bool referenceHit = sets[0]->intersect(0, ray, reference);
    hits += referenceHit;
    double referenceRoots[kMaxGlyphHits];
    const int referenceCount = sets[0]->allIntersections(0, ray, referenceRoots);
    for (std::size_t s = 1; s < sets.size(); ++s)
    {
      const bool exact = !(conventions[s].basis == SHBasis::Tournier07 && conventions[s].legacy);
      SurfaceHit hit;
      ASSERT_EQ(sets[s]->intersect(0, ray, hit), referenceHit) << conventions[s].name() << " ray " << r;
      double roots[kMaxGlyphHits];
      ASSERT_EQ(sets[s]->allIntersections(0, ray, roots), referenceCount) << conventions[s].name();
      for (int i = 0; i < referenceCount; ++i)
      {
        if (exact)
          EXPECT_EQ(roots[i], referenceRoots[i]) << conventions[s].name();
        else
          EXPECT_NEAR(roots[i], referenceRoots[i], 1e-5) << conventions[s].name();
      }
      if (!referenceHit)
        continue;
      if (exact)
      {
        EXPECT_EQ(hit.t, reference.t) << conventions[s].name();
        EXPECT_EQ(hit.normal, reference.normal) << conventions[s].name();
      }
      else
        EXPECT_NEAR(hit.t, reference.t, 1e-5) << conventions[s].name();
    }
  }
  EXPECT_GT(hits, 100);
}

// ---------------------------------------------------------------------------------------------
// Band trimming

TEST(SHGlyphSetBands, TrailingZeroBandsAreTrimmed)
{
  std::mt19937 random(44);
  const std::vector<double> low = randomGlyph(4, random, 2.0); // 15 coefficients
  std::vector<double> padded(sightline::shCoefficientCount(8), 0.0);
  std::copy(low.begin(), low.end(), padded.begin());
  // DIPY's default convention on input: zero bands stay zero through the conversion.
  SHGlyphOptions options;
  options.convention = { SHBasis::Descoteaux07, true };
  const auto trimmed = singleGlyph(padded, 8, options);
  const auto direct = singleGlyph(low, 4, options);
  options.trimZeroBands = false;
  const auto untrimmed = singleGlyph(padded, 8, options);

  EXPECT_EQ(trimmed->order(0), 4);
  EXPECT_EQ(direct->order(0), 4);
  EXPECT_EQ(untrimmed->order(0), 8);
  for (int j = 0; j < 15; ++j)
  {
    EXPECT_EQ(trimmed->coefficients(0)[j], direct->coefficients(0)[j]);
    EXPECT_EQ(untrimmed->coefficients(0)[j], direct->coefficients(0)[j]);
  }
  for (int j = 15; j < 45; ++j)
    EXPECT_EQ(untrimmed->coefficients(0)[j], 0.0);
  for (int axis = 0; axis < 3; ++axis)
  {
    EXPECT_EQ(trimmed->bounds(0).lower[axis], direct->bounds(0).lower[axis]);
    EXPECT_EQ(trimmed->bounds(0).upper[axis], direct->bounds(0).upper[axis]);
  }

  // Identical intersections for the trimmed input; the untrimmed degree-18 polynomial has the
  // same roots within the root tolerance (1e-6 of the glyph size; 1e-5 allowed).
  int hits = 0;
  for (int r = 0; r < 300; ++r)
  {
    const Ray ray = rayTowards(dvec3(0.0), 3.0, 1.0, random);
    double a[kMaxGlyphHits], b[kMaxGlyphHits], c[kMaxGlyphHits];
    const int na = trimmed->allIntersections(0, ray, a);
    ASSERT_EQ(direct->allIntersections(0, ray, b), na);
    for (int i = 0; i < na; ++i)
      EXPECT_EQ(a[i], b[i]);
    SurfaceHit ha, hb, hc;
    const bool hitA = trimmed->intersect(0, ray, ha);
    ASSERT_EQ(direct->intersect(0, ray, hb), hitA);
    hits += hitA;
    if (hitA)
    {
      EXPECT_EQ(ha.t, hb.t);
      EXPECT_EQ(ha.normal, hb.normal);
    }
    const int nc = untrimmed->allIntersections(0, ray, c);
    ASSERT_EQ(nc, na) << "ray " << r;
    for (int i = 0; i < nc; ++i)
      EXPECT_NEAR(c[i], a[i], 1e-5);
    ASSERT_EQ(untrimmed->intersect(0, ray, hc), hitA);
    if (hitA)
    {
      EXPECT_NEAR(hc.t, ha.t, 1e-5);
    }
  }
  EXPECT_GT(hits, 100);

  // Per glyph: a zero band below a non-zero one stays, and each glyph finds its own
  // coefficients (offsets into the shared array).
  std::vector<double> interior = randomGlyph(8, random, 2.0);
  for (int l : { 4, 8 })
    for (int m = -l; m <= l; ++m)
      interior[sightline::shIndex(l, m)] = 0.0;
  std::vector<double> sphere(45, 0.0);
  sphere[0] = 1.0 / kY00;
  const std::vector<double> full = randomGlyph(8, random, 2.0);
  const std::vector<const std::vector<double>*> glyphs{ &interior, &sphere, &full, &padded };
  std::vector<float> all;
  for (const auto* glyph : glyphs)
    for (double c : *glyph)
      all.push_back(float(c));
  const SHGlyphSet mixed({ vec3(0.0f), vec3(3.0f, 0.0f, 0.0f), vec3(6.0f, 0.0f, 0.0f), vec3(9.0f, 0.0f, 0.0f) },
                         all, 8, canonicalOptions());
  ASSERT_EQ(mixed.size(), 4u);
  EXPECT_EQ(mixed.order(0), 6);
  EXPECT_EQ(mixed.order(1), 0);
  EXPECT_EQ(mixed.order(2), 8);
  EXPECT_EQ(mixed.order(3), 4);
  for (unsigned p = 0; p < 4; ++p)
    for (int j = 0; j < sightline::shCoefficientCount(mixed.order(p)); ++j)
      EXPECT_EQ(mixed.coefficients(p)[j], double(float((*glyphs[p])[j]))) << "glyph " << p << " j " << j;
}

// ---------------------------------------------------------------------------------------------
// Bounds

// Orders 0 to 12, six random glyphs each (half of them with negative lobes): every surface
// point c + F(w) w over 16,000 Fibonacci directions lies in the glyph's box, the box is centred
// on the glyph, and it is near exact: at most 4.5 % larger than the sampled extent (margin
// 2.5 % for k <= 8, 3.5 % above, plus sampling error). bounds() is the union of the boxes.
TEST(SHGlyphSetBounds, EveryBoxContainsItsGlyph)
{
  std::mt19937 random(1717);
  std::uniform_real_distribution<float> position(-5.0f, 5.0f);
  const std::vector<dvec3> directions = fibonacciSphere(16000);
  for (int order = 0; order <= 12; order += 2)
  {
    std::vector<vec3> centers;
    std::vector<float> coefficients;
    for (int g = 0; g < 6; ++g)
    {
      centers.emplace_back(position(random), position(random), position(random));
      const std::vector<double> b = randomGlyph(order, random, g % 2 == 0 ? 0.0 : 3.0, 0.5 + 0.3 * g);
      coefficients.insert(coefficients.end(), b.begin(), b.end());
    }
    SHGlyphOptions options = canonicalOptions();
    options.trimZeroBands = false;
    const SHGlyphSet set(centers, coefficients, order, options);
    ASSERT_EQ(set.size(), 6u);
    Box3 all;
    for (unsigned p = 0; p < set.size(); ++p)
    {
      const Box3 box = set.bounds(p);
      all.extend(box);
      const dvec3 center(set.center(p));
      dvec3 extent(0.0);
      for (const dvec3& w : directions)
      {
        const dvec3 offset = glyphFunction(order, set.coefficients(p), w) * w;
        extent = glm::max(extent, glm::abs(offset));
        const dvec3 point = center + offset;
        for (int axis = 0; axis < 3; ++axis)
        {
          ASSERT_LE(box.lower[axis], point[axis]) << "order " << order << " glyph " << p << " axis " << axis;
          ASSERT_GE(box.upper[axis], point[axis]) << "order " << order << " glyph " << p << " axis " << axis;
        }
      }
      for (int axis = 0; axis < 3; ++axis)
      {
        const double half = 0.5 * (double(box.upper[axis]) - double(box.lower[axis]));
        EXPECT_NEAR(0.5 * (double(box.upper[axis]) + double(box.lower[axis])), center[axis], 1e-5);
        EXPECT_LE(half, 1.045 * extent[axis]) << "order " << order << " axis " << axis;
      }
    }
    for (int axis = 0; axis < 3; ++axis)
    {
      EXPECT_EQ(set.bounds().lower[axis], all.lower[axis]);
      EXPECT_EQ(set.bounds().upper[axis], all.upper[axis]);
    }
  }
}

// A k = 0 glyph is a sphere of radius |b_0| Y_0^0: its exact box has half extent r on every
// axis, and the set pads it by the paper's 2.5 %.
TEST(SHGlyphSetBounds, SphereGlyphBoxIsThePaddedSphereBox)
{
  for (float coefficient : { 1.0f, -2.5f, 0.3f })
  {
    const vec3 center(1.5f, -2.0f, 0.25f);
    const SHGlyphSet set({ center }, { coefficient }, 0, canonicalOptions());
    ASSERT_EQ(set.size(), 1u);
    const double r = std::fabs(double(coefficient)) * kY00;
    const Box3 box = set.bounds(0);
    for (int axis = 0; axis < 3; ++axis)
    {
      EXPECT_NEAR(box.lower[axis], center[axis] - 1.025 * r, 2e-6 * (1.0 + std::fabs(center[axis])))
        << "coefficient " << coefficient << " axis " << axis;
      EXPECT_NEAR(box.upper[axis], center[axis] + 1.025 * r, 2e-6 * (1.0 + std::fabs(center[axis])))
        << "coefficient " << coefficient << " axis " << axis;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The Embree geometry

struct GlyphField
{
  std::shared_ptr<SHGlyphSet> set;
  std::unique_ptr<EmbreeScene> scene;
};

/// Glyphs of orders 4 and 6 (with negative lobes, several intersections per ray) at random
/// positions in [-4, 4]^3, some overlapping.
GlyphField glyphField(std::mt19937& random, SHGlyphOptions options, int count = 40)
{
  std::uniform_real_distribution<float> position(-4.0f, 4.0f);
  std::vector<vec3> centers;
  std::vector<float> coefficients;
  for (int g = 0; g < count; ++g)
  {
    centers.emplace_back(position(random), position(random), position(random));
    const int order = g % 3 == 0 ? 4 : 6;
    std::vector<double> b(sightline::shCoefficientCount(6), 0.0);
    const std::vector<double> glyph = randomGlyph(order, random, g % 2 ? 2.0 : 0.5, 0.6 + 0.02 * g);
    std::copy(glyph.begin(), glyph.end(), b.begin());
    coefficients.insert(coefficients.end(), b.begin(), b.end());
  }
  options.convention = canonicalConvention();
  GlyphField field;
  field.set = std::make_shared<SHGlyphSet>(centers, coefficients, 6, options);
  field.scene = sceneOf(field.set);
  return field;
}

/// Random origins in [-6, 6]^3; two thirds of the rays are aimed near a random glyph's centre.
Ray randomSceneRay(const SHGlyphSet& set, std::mt19937& random)
{
  std::uniform_real_distribution<float> position(-6.0f, 6.0f), unit(0.0f, 1.0f);
  Ray ray;
  ray.origin = vec3(position(random), position(random), position(random));
  ray.direction = vec3(randomUnit(random));
  if (unit(random) < 0.67f)
  {
    const unsigned target = unsigned(random() % set.size());
    const dvec3 aim = dvec3(set.center(target)) + 0.5 * randomUnit(random) - dvec3(ray.origin);
    if (glm::length(aim) > 1e-3)
      ray.direction = vec3(glm::normalize(aim));
  }
  ray.tnear = unit(random) < 0.3f ? 3.0f * unit(random) : 0.0f;
  ray.tfar = unit(random) < 0.3f ? ray.tnear + 8.0f * unit(random) : sightline::kInfinity;
  return ray;
}

// Through the BVH, the nearest hit is the smallest first root over all glyphs (within 1e-5,
// the roots being found with relative tolerance 1e-6), and occluded() says whether any glyph
// has a root in (tnear, tfar).
TEST(SHGlyphSetEmbree, NearestHitAndOcclusionMatchBruteForce)
{
  std::mt19937 random(8080);
  const GlyphField field = glyphField(random, {});
  const SHGlyphSet& set = *field.set;
  ASSERT_EQ(set.size(), 40u);
  int hits = 0, misses = 0, clipped = 0;
  for (int r = 0; r < 2500; ++r)
  {
    const Ray ray = randomSceneRay(set, random);
    std::optional<std::pair<double, unsigned>> nearest;
    for (unsigned p = 0; p < set.size(); ++p)
    {
      const auto t = firstRoot(set, p, ray);
      if (t && (!nearest || *t < nearest->first))
        nearest = std::make_pair(*t, p);
    }
    RTCRayHit rh = sightline::makeRayHit(ray);
    const bool hit = field.scene->intersect(rh);
    ASSERT_EQ(hit, nearest.has_value()) << "ray " << r;
    EXPECT_EQ(field.scene->occluded(ray), hit) << "ray " << r;
    if (!hit)
    {
      ++misses;
      continue;
    }
    ++hits;
    clipped += ray.tnear > 0.0f || std::isfinite(ray.tfar);
    EXPECT_NEAR(rh.ray.tfar, nearest->first, 1e-5 * (1.0 + nearest->first)) << "ray " << r;
    if (rh.hit.primID != nearest->second)
    {
      // Only a tie may pick another glyph.
      const auto other = firstRoot(set, rh.hit.primID, ray);
      ASSERT_TRUE(other.has_value());
      EXPECT_NEAR(*other, nearest->first, 1e-5) << "ray " << r;
    }
    // The reported normal is the glyph's outward normal at the hit (Eq. 11).
    const dvec3 p = pointOnRay(ray, rh.ray.tfar) - dvec3(set.center(rh.hit.primID));
    const dvec3 expected = sightline::shGlyphNormal(set.order(rh.hit.primID), set.coefficients(rh.hit.primID), p);
    const dvec3 normal(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    EXPECT_GT(glm::dot(glm::normalize(normal), glm::normalize(expected)), 0.9999) << "ray " << r;
  }
  EXPECT_GT(hits, 500);
  EXPECT_GT(misses, 300);
  EXPECT_GT(clipped, 100);
}

// F = 0.1 + 0.45 (3 z^2 - 1): positive caps of radius 1 at the poles and a negative lobe of
// radius 0.35 around the equator.
std::vector<double> negativeLobeGlyph()
{
  std::vector<double> b(6, 0.0);
  b[0] = 0.1 / kY00;
  // Y_2^0 = sqrt(5 / (16 pi)) (3 z^2 - 1)
  b[sightline::shIndex(2, 0)] = 0.45 / std::sqrt(5.0 / (16.0 * kPi));
  return b;
}

TEST(SHGlyphSetEmbree, HiddenNegativeLobesAreNotHit)
{
  const std::vector<double> b = negativeLobeGlyph();
  SHGlyphOptions options = canonicalOptions();
  const auto shown = singleGlyph(b, 2, options);
  options.hideNegativeLobes = true;
  const auto hidden = singleGlyph(b, 2, options);
  const auto shownScene = sceneOf(shown), hiddenScene = sceneOf(hidden);
  const double* c = shown->coefficients(0);
  EXPECT_NEAR(glyphFunction(2, c, { 0, 0, 1 }), 1.0, 1e-6);
  EXPECT_NEAR(glyphFunction(2, c, { 1, 0, 0 }), -0.35, 1e-6);

  // In the equatorial plane only the negative lobe is there.
  for (float y : { 0.0f, 0.1f, 0.2f, 0.3f })
  {
    Ray ray;
    ray.origin = vec3(-3.0f, y, 0.0f);
    ray.direction = vec3(1.0f, 0.0f, 0.0f);
    SurfaceHit hit;
    ASSERT_TRUE(shown->intersect(0, ray, hit)) << y;
    EXPECT_NEAR(hit.t, 3.0 - std::sqrt(0.35 * 0.35 - double(y) * y), 1e-5);
    EXPECT_FALSE(hidden->intersect(0, ray, hit)) << y;
    EXPECT_FALSE(hiddenScene->occluded(ray)) << y;
    EXPECT_TRUE(shownScene->occluded(ray)) << y;
  }

  // Random rays: the hidden set reports the first root on a positive lobe, the shown set the
  // first root of all; both through the BVH.
  std::mt19937 random(5);
  int negativeFirst = 0, hiddenHits = 0;
  for (int r = 0; r < 1500; ++r)
  {
    const Ray ray = rayTowards(dvec3(0.0), 3.0, 1.0, random);
    double t[kMaxGlyphHits];
    const int count = shown->allIntersections(0, ray, t);
    std::optional<double> first, firstPositive;
    for (int i = 0; i < count; ++i)
    {
      const dvec3 w = glm::normalize(pointOnRay(ray, t[i]));
      if (!first)
        first = t[i];
      if (!firstPositive && glyphFunction(2, c, w) > 0.0)
        firstPositive = t[i];
    }
    negativeFirst += first && first != firstPositive;
    RTCRayHit a = sightline::makeRayHit(ray), h = sightline::makeRayHit(ray);
    ASSERT_EQ(shownScene->intersect(a), first.has_value());
    ASSERT_EQ(hiddenScene->intersect(h), firstPositive.has_value()) << "ray " << r;
    EXPECT_EQ(hiddenScene->occluded(ray), firstPositive.has_value()) << "ray " << r;
    if (first)
    {
      EXPECT_NEAR(a.ray.tfar, *first, 1e-5);
    }
    if (firstPositive)
    {
      ++hiddenHits;
      EXPECT_NEAR(h.ray.tfar, *firstPositive, 1e-5);
      const dvec3 w = glm::normalize(pointOnRay(ray, h.ray.tfar));
      EXPECT_GT(glyphFunction(2, c, w), 0.0);
    }
  }
  EXPECT_GT(negativeFirst, 50) << "rays whose first hit is on the negative lobe";
  EXPECT_GT(hiddenHits, 200);
}

// ---------------------------------------------------------------------------------------------
// Colours

TEST(SHGlyphSetColors, DirectionNegativeLobeAndPerGlyphColours)
{
  const std::vector<double> b = negativeLobeGlyph();
  const vec3 center(2.0f, -1.0f, 0.5f);
  std::vector<float> input = toFloat(b);
  input.insert(input.end(), input.begin(), input.end());
  const std::vector<vec3> centers{ center, center + vec3(5.0f, 0.0f, 0.0f) };
  const std::vector<std::uint32_t> colors{ sightline::packRGBA8(255, 128, 0), sightline::packRGBA8(0, 51, 255) };
  const vec3 glyphColors[2] = { vec3(1.0f, 128.0f / 255.0f, 0.0f), vec3(0.0f, 0.2f, 1.0f) };
  const vec3 magenta(1.0f, 0.0f, 1.0f);

  SHGlyphOptions options = canonicalOptions();
  const SHGlyphSet direction(centers, input, 2, options);
  EXPECT_TRUE(direction.hasPrimitiveColors());
  options.negativeLobeColor = magenta;
  const SHGlyphSet marked(centers, input, 2, options);
  options.coloring = SHColoring::PerGlyph;
  const SHGlyphSet perGlyph(centers, input, 2, options, {}, colors);
  EXPECT_TRUE(perGlyph.hasPrimitiveColors());
  // Per-glyph colouring without colours falls back to the material.
  const SHGlyphSet noColors(centers, input, 2, options);
  EXPECT_EQ(noColors.options().coloring, SHColoring::Material);
  // A negative-lobe colour needs per-point colours even with the material's colour elsewhere.
  EXPECT_TRUE(noColors.hasPrimitiveColors());
  options.coloring = SHColoring::Material;
  const SHGlyphSet materialMarked(centers, input, 2, options);
  EXPECT_TRUE(materialMarked.hasPrimitiveColors());
  options.negativeLobeColor = vec3(-1.0f);
  EXPECT_FALSE(SHGlyphSet(centers, input, 2, options).hasPrimitiveColors());
  {
    // Material colouring: the material's colour on positive lobes, the marker on negative ones.
    std::mt19937 random(7);
    int checked = 0;
    for (int r = 0; r < 400; ++r)
    {
      const dvec3 w = randomUnit(random);
      const double value = sightline::evaluateSHSum<double>(2, materialMarked.coefficients(0), w.x, w.y, w.z);
      const vec3 point = materialMarked.center(0) + vec3(std::abs(value) * w);
      const vec3 c = materialMarked.surfaceColor(0, point);
      const vec3 expected = value < 0.0 ? magenta : materialMarked.material.color;
      EXPECT_LT(glm::length(c - expected), 1e-6f);
      ++checked;
    }
    EXPECT_EQ(checked, 400);
  }

  std::mt19937 random(99);
  int negative = 0, positive = 0;
  for (int r = 0; r < 1000; ++r)
  {
    const unsigned p = unsigned(r % 2);
    const Ray ray = rayTowards(dvec3(centers[p]), 3.0, 1.0, random);
    SurfaceHit hit;
    if (!direction.intersect(p, ray, hit))
      continue;
    const vec3 point = vec3(pointOnRay(ray, hit.t));
    const dvec3 w = glm::normalize(dvec3(point) - dvec3(centers[p]));
    const bool onNegative = glyphFunction(2, direction.coefficients(p), w) < 0.0;
    negative += onNegative;
    positive += !onNegative;
    const vec3 expected = vec3(glm::abs(w));
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(direction.surfaceColor(p, point)[i], expected[i], 1e-6) << "without a lobe colour";
    const vec3 m = marked.surfaceColor(p, point);
    const vec3 g = perGlyph.surfaceColor(p, point);
    if (onNegative)
    {
      EXPECT_EQ(m, magenta);
      EXPECT_EQ(g, magenta);
    }
    else
    {
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(m[i], expected[i], 1e-6);
      EXPECT_EQ(g, glyphColors[p]);
    }
  }
  EXPECT_GT(negative, 20);
  EXPECT_GT(positive, 20);
  for (unsigned p = 0; p < 2; ++p)
    EXPECT_EQ(perGlyph.primitiveColor(p), glyphColors[p]);
}

// ---------------------------------------------------------------------------------------------
// Ray-marching baselines

std::unique_ptr<SHGlyphSet> marchingSet(const std::vector<double>& b, int order, int steps,
                                        SHMarchingBound bound, bool tightBoxes = false)
{
  SHGlyphOptions options = canonicalOptions();
  options.method = SHIntersectionMethod::RayMarching;
  options.marchingSteps = steps;
  options.marchingBound = bound;
  options.marchingUsesTightBoxes = tightBoxes;
  return std::make_unique<SHGlyphSet>(std::vector<vec3>{ vec3(0.0f) }, toFloat(b), order, options);
}

// On a smooth k = 4 glyph, 200 steps plus 10 bisection steps find the first intersection of
// the exact method to within one step (2R / 200) on nearly every ray (>= 97 % measured against
// rays the exact method hits) and never hit where the exact method misses.
TEST(SHGlyphSetMarching, AgreesWithTheExactMethodOnASmoothGlyph)
{
  const std::vector<double> b =
    fibreGlyph(4, { { 1, 0.2, 0 }, { 0, 1, 0.5 } }, 0.3, 8.0);
  const auto exact = singleGlyph(b, 4);
  for (SHMarchingBound bound : { SHMarchingBound::Cylinder, SHMarchingBound::Sphere })
  {
    const auto marching = marchingSet(b, 4, 200, bound);
    const double R = sightline::shGlyphBoundingRadius(4, exact->coefficients(0));
    const double step = 2.0 * R / 200.0;
    std::mt19937 random(31);
    int exactHits = 0, agree = 0, extra = 0;
    double worst = 0.0;
    for (int r = 0; r < 2000; ++r)
    {
      const Ray ray = rayTowards(dvec3(0.0), 2.5 * R, 1.0, random);
      SurfaceHit e, m;
      const bool hitExact = exact->intersect(0, ray, e);
      const bool hitMarching = marching->intersect(0, ray, m);
      extra += hitMarching && !hitExact;
      if (!hitExact)
        continue;
      ++exactHits;
      if (hitMarching && std::fabs(double(m.t) - e.t) <= step)
      {
        ++agree;
        worst = std::max(worst, std::fabs(double(m.t) - e.t));
      }
    }
    ASSERT_GT(exactHits, 500);
    EXPECT_GE(agree, 0.97 * exactHits) << "bound " << int(bound);
    EXPECT_EQ(extra, 0);
    // Bisection shrinks the bracket by 2^10: agreeing rays are far better than one step.
    EXPECT_LT(worst, step / 100.0);
    RecordProperty(bound == SHMarchingBound::Cylinder ? "cylinder_agreement" : "sphere_agreement",
                   number(double(agree) / exactHits));
  }
}

// A thin lobe: a ray crossing a sharp k = 8 fibre lobe near its tip stays inside for less than
// one marching step; at 100 steps the baseline misses it where the exact method finds both
// intersections. This documents why the baseline needs many steps.
TEST(SHGlyphSetMarching, MissesAThinLobeTheExactMethodFinds)
{
  const std::vector<double> b = fibreGlyph(8, { { 1, 0, 0 } }, 0.02, 40.0);
  const auto exact = singleGlyph(b, 8);
  const auto marching = marchingSet(b, 8, 100, SHMarchingBound::Cylinder);
  const double* c = exact->coefficients(0);
  const double R = sightline::shGlyphBoundingRadius(8, c);
  const double step = 2.0 * R / 100.0;
  const double tip = glyphFunction(8, c, { 1, 0, 0 });
  ASSERT_GT(tip, 0.9);

  // Rays in the plane z = 0 through the point (tip + s, 0, 0) on the lobe's axis, tilted from
  // the perpendicular: with s slightly less than the cap's radius times (1 - cos tilt) they
  // graze the rounded tip. (A perpendicular ray would not do: the cylinder bound centres its
  // samples on the point nearest the glyph centre, which is then the middle of the chord.)
  auto tipRay = [&](int i, int j)
  {
    const double tilt = (15.0 + 5.0 * j) * kPi / 180.0;
    const dvec3 direction(-std::sin(tilt), std::cos(tilt), 0.0);
    const dvec3 through(tip + 0.03 * i / 400.0, 0.0, 0.0);
    Ray ray;
    ray.origin = vec3(through - 2.0 * R * direction);
    ray.direction = vec3(direction);
    return ray;
  };
  int missed = 0, exactHits = 0, thin = 0;
  double thinnest = kInf;
  for (int i = 0; i < 400; ++i)
    for (int j = 0; j < 10; ++j)
    {
      const Ray ray = tipRay(i, j);
      double t[kMaxGlyphHits];
      const int count = exact->allIntersections(0, ray, t);
      if (count < 2)
        continue;
      ++exactHits;
      thin += t[1] - t[0] < step;
      SurfaceHit e, m;
      ASSERT_TRUE(exact->intersect(0, ray, e));
      EXPECT_NEAR(e.t, t[0], 1e-6);
      if (marching->intersect(0, ray, m))
        continue;
      ++missed;
      // A genuine crossing: the midpoint of the first interval is inside the glyph, points
      // just outside it are not, and the interval is shorter than a step.
      const double chord = t[1] - t[0];
      thinnest = std::min(thinnest, chord);
      EXPECT_LT(chord, step);
      EXPECT_TRUE(sightline::insideSHGlyph(8, c, pointOnRay(ray, 0.5 * (t[0] + t[1]))));
      EXPECT_FALSE(sightline::insideSHGlyph(8, c, pointOnRay(ray, t[0] - 1e-4)));
      EXPECT_FALSE(sightline::insideSHGlyph(8, c, pointOnRay(ray, t[1] + 1e-4)));
    }
  EXPECT_GT(thin, 30) << "rays crossing the lobe for less than one step";
  EXPECT_GE(missed, 5) << "100 marching steps should miss some tip crossings";
  RecordProperty("tip_rays_hit_exactly", exactHits);
  RecordProperty("tip_rays_thinner_than_a_step", thin);
  RecordProperty("tip_rays_missed_by_marching_100", missed);
  RecordProperty("thinnest_missed_chord", number(thinnest));

  // With 10x the steps the same tip is found on more rays.
  const auto fine = marchingSet(b, 8, 1000, SHMarchingBound::Cylinder);
  int fineMissed = 0;
  for (int i = 0; i < 400; ++i)
    for (int j = 0; j < 10; ++j)
    {
      const Ray ray = tipRay(i, j);
      SurfaceHit hit;
      fineMissed += exact->intersect(0, ray, hit) && !fine->intersect(0, ray, hit);
    }
  EXPECT_LT(fineMissed, missed);
}

// marchingUsesTightBoxes swaps the bounding-sphere boxes for the near-exact ones and changes
// nothing else: the same hits per primitive and through the BVH.
TEST(SHGlyphSetMarching, TightBoxesChangeOnlyTheBoxes)
{
  std::mt19937 random(12);
  const std::vector<double> b = fibreGlyph(4, { { 1, 0, 0 } }, 0.1, 10.0);
  const auto loose = marchingSet(b, 4, 150, SHMarchingBound::Sphere, false);
  const auto tight = marchingSet(b, 4, 150, SHMarchingBound::Sphere, true);
  const auto exact = singleGlyph(b, 4);
  const double R = sightline::shGlyphBoundingRadius(4, exact->coefficients(0));
  for (int axis = 0; axis < 3; ++axis)
  {
    EXPECT_EQ(tight->bounds(0).lower[axis], exact->bounds(0).lower[axis]);
    EXPECT_EQ(tight->bounds(0).upper[axis], exact->bounds(0).upper[axis]);
    EXPECT_NEAR(loose->bounds(0).upper[axis], R, 1e-6 * R);
    EXPECT_NEAR(loose->bounds(0).lower[axis], -R, 1e-6 * R);
  }
  // A fibre along x: the tight box is much thinner across it.
  EXPECT_LT(tight->bounds(0).upper.y, 0.8 * loose->bounds(0).upper.y);

  // Shared pointers for the scenes (the sets above are unique).
  const auto looseScene = sceneOf(std::shared_ptr<const SHGlyphSet>(marchingSet(b, 4, 150, SHMarchingBound::Sphere, false)));
  const auto tightScene = sceneOf(std::shared_ptr<const SHGlyphSet>(marchingSet(b, 4, 150, SHMarchingBound::Sphere, true)));
  int hits = 0;
  for (int r = 0; r < 1500; ++r)
  {
    const Ray ray = rayTowards(dvec3(0.0), 2.0 * R, R, random);
    SurfaceHit a, c;
    const bool hitLoose = loose->intersect(0, ray, a);
    ASSERT_EQ(tight->intersect(0, ray, c), hitLoose);
    hits += hitLoose;
    if (hitLoose)
    {
      EXPECT_EQ(a.t, c.t);
    }
    RTCRayHit ra = sightline::makeRayHit(ray), rc = sightline::makeRayHit(ray);
    ASSERT_EQ(looseScene->intersect(ra), hitLoose);
    ASSERT_EQ(tightScene->intersect(rc), hitLoose);
    if (hitLoose)
    {
      EXPECT_EQ(ra.ray.tfar, rc.ray.tfar);
    }
  }
  EXPECT_GT(hits, 300);
}

// ---------------------------------------------------------------------------------------------
// Inside length (uncertainty volumes)

// A k = 0 glyph is a sphere: the inside length is the analytic chord clipped to [tnear, tfar]
// (1e-6 of the radius) and the entry is max(t0, tnear) (float, 1e-5). Lengths and entries are
// in ray-parameter units, as the renderer expects (it multiplies by the world length of the
// direction).
TEST(SHGlyphSetInsideLength, SphereGlyphGivesTheClippedChord)
{
  const dvec3 center(0.5, -1.0, 2.0);
  const double radius = 1.3;
  const auto set = std::make_shared<SHGlyphSet>(std::vector<vec3>{ vec3(center) },
                                                std::vector<float>{ float(radius / kY00) }, 0,
                                                canonicalOptions());
  const double r = double(float(radius / kY00)) * kY00;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int through = 0, startInside = 0, endInside = 0, missed = 0;
  for (int i = 0; i < 3000; ++i)
  {
    Ray ray = rayTowards(center, 4.0, 1.5 * r, random);
    const double scale = i % 3 == 0 ? 2.5 : 1.0; // some non-unit directions
    ray.direction *= float(scale);
    // Analytic chord in ray parameters.
    const dvec3 o = dvec3(ray.origin) - center, d = dvec3(ray.direction);
    const double a = glm::dot(d, d), h = glm::dot(o, d), c = glm::dot(o, o) - r * r;
    const double discriminant = h * h - a * c;
    const double t0 = discriminant > 0 ? (-h - std::sqrt(discriminant)) / a : 0.0;
    const double t1 = discriminant > 0 ? (-h + std::sqrt(discriminant)) / a : 0.0;
    // Segments: whole ray, starting inside, ending inside, both, before the sphere.
    const int kind = i % 5;
    const double span = t1 - t0;
    ray.tnear = float(kind == 1 || kind == 3 ? t0 + unit(random) * span : 0.0);
    ray.tfar = kind == 2 || kind == 3 ? float(std::max(double(ray.tnear), t0) + unit(random) * (t1 - std::max(double(ray.tnear), t0)))
             : kind == 4          ? float(t0 * unit(random))
                                  : sightline::kInfinity;
    if (discriminant <= 0 && kind != 0)
      continue;
    const double tnear = ray.tnear, tfar = ray.tfar;
    const double expected = discriminant > 0 ? std::max(0.0, std::min(t1, tfar) - std::max(t0, tnear)) : 0.0;
    float entry = kInf;
    const double length = set->insideLength(0, ray, entry);
    EXPECT_NEAR(length, expected, 1e-6 * r) << "ray " << i << " kind " << kind;
    if (expected > 1e-6)
    {
      EXPECT_NEAR(entry, std::max(t0, tnear), 1e-5) << "ray " << i;
      through += kind == 0;
      startInside += kind == 1 || kind == 3;
      endInside += kind == 2 || kind == 3;
    }
    else
    {
      EXPECT_EQ(entry, kInf) << "ray " << i << ": no entry without an inside";
      missed += kind == 0 || kind == 4;
    }
  }
  EXPECT_GT(through, 200);
  EXPECT_GT(startInside, 200);
  EXPECT_GT(endInside, 200);
  EXPECT_GT(missed, 200);

  // The scene's volume query adds the lengths of all glyphs on the ray.
  const auto two = std::make_shared<SHGlyphSet>(
    std::vector<vec3>{ vec3(0.0f), vec3(0.0f, 0.0f, -5.0f) },
    std::vector<float>{ float(1.0 / kY00), float(2.0 / kY00) }, 0, canonicalOptions());
  const auto scene = sceneOf(two);
  Ray ray;
  ray.origin = vec3(0.0f, 0.6f, 10.0f);
  ray.direction = vec3(0.0f, 0.0f, -1.0f);
  float entry = kInf;
  const double total = scene->insideLength(ray, entry);
  EXPECT_NEAR(total, 2.0 * std::sqrt(1.0 - 0.36) + 2.0 * std::sqrt(4.0 - 0.36), 1e-5);
  EXPECT_NEAR(entry, 10.0 - std::sqrt(1.0 - 0.36), 1e-5);
}

/// Inside intervals of the ray segment [tnear, tfar] (finite) in the glyph, from a scan of
/// `samples` points refined by 60 bisection steps at every change of inside/outside.
double referenceInsideLength(int order, const double* b, const Ray& ray, double tnear, double tfar,
                             int samples, int& intervals, double& entry)
{
  auto inside = [&](double t)
  {
    const dvec3 p = pointOnRay(ray, t);
    const double r = glm::length(p);
    return r < std::fabs(glyphFunction(order, b, p / r));
  };
  double total = 0.0, start = tnear;
  bool previous = inside(tnear);
  double previousT = tnear;
  intervals = 0;
  entry = kInf;
  if (previous)
    entry = tnear;
  for (int i = 1; i <= samples; ++i)
  {
    const double t = tnear + (tfar - tnear) * i / samples;
    const bool now = inside(t);
    if (now != previous)
    {
      double lo = previousT, hi = t;
      for (int k = 0; k < 60; ++k)
      {
        const double mid = 0.5 * (lo + hi);
        (inside(mid) == previous ? lo : hi) = mid;
      }
      const double crossing = 0.5 * (lo + hi);
      if (now)
      {
        start = crossing;
        entry = std::min(entry, crossing);
      }
      else
      {
        total += crossing - start;
        ++intervals;
      }
      previous = now;
    }
    previousT = t;
  }
  if (previous)
  {
    total += tfar - start;
    ++intervals;
  }
  return total;
}

// A k = 4 glyph with negative lobes (rays cross several intervals): the inside length equals
// the sum of inside intervals from a dense scan (20,000 samples, bisection-refined) within
// 1e-5 of the glyph size, for whole rays and for segments starting or ending inside.
TEST(SHGlyphSetInsideLength, GeneralGlyphMatchesADenseScan)
{
  std::mt19937 random(4242);
  const std::vector<double> b = randomGlyph(4, random, 0.3, 1.0);
  const auto set = singleGlyph(b, 4);
  const double* c = set->coefficients(0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int multiple = 0, nonzero = 0;
  for (int i = 0; i < 240; ++i)
  {
    Ray ray = rayTowards(dvec3(0.0), 2.0, 0.5, random);
    const int kind = i % 3;
    // Whole segment across the bounding sphere, or clipped to start or end near the centre.
    ray.tnear = kind == 1 ? float(1.5 + unit(random)) : 0.0f;
    ray.tfar = kind == 2 ? float(1.5 + unit(random)) : (i % 2 ? sightline::kInfinity : 4.0f);
    const double tfar = std::isfinite(ray.tfar) ? double(ray.tfar) : 4.0;
    int intervals = 0;
    double expectedEntry = 0.0;
    const double expected =
      referenceInsideLength(4, c, ray, ray.tnear, tfar, 20000, intervals, expectedEntry);
    float entry = kInf;
    const double length = set->insideLength(0, ray, entry);
    EXPECT_NEAR(length, expected, 1e-5) << "ray " << i << " with " << intervals << " intervals";
    if (expected > 0.0)
    {
      ++nonzero;
      EXPECT_NEAR(entry, expectedEntry, 1e-5) << "ray " << i;
    }
    multiple += intervals >= 2;
  }
  EXPECT_GT(nonzero, 120);
  EXPECT_GT(multiple, 15) << "rays crossing more than one inside interval";
}
} // namespace

// Cached boxes: a set built with the half-extents another set computed has the same boxes, a
// NaN entry is computed afresh, and boxes scale linearly with the glyph (what lets a viewer
// cache one box per voxel and reuse it for every scale and normalisation).
TEST(SHGlyphSetBounds, CachedHalfExtentsAreReusedAndNaNEntriesComputed)
{
  std::mt19937 random(4242);
  const int order = 8;
  std::vector<vec3> centers;
  std::vector<float> coefficients;
  for (int g = 0; g < 5; ++g)
  {
    centers.emplace_back(float(3 * g), 0.0f, 0.0f);
    const std::vector<double> b = randomGlyph(order, random, 1.0, 0.6);
    coefficients.insert(coefficients.end(), b.begin(), b.end());
  }
  const SHGlyphSet reference(centers, coefficients, order, canonicalOptions());
  ASSERT_EQ(reference.size(), 5u);

  std::vector<vec3> cached(5);
  for (unsigned p = 0; p < 5; ++p)
    cached[p] = reference.halfExtents(p);
  cached[2] = vec3(kNaN);
  const SHGlyphSet reused(centers, coefficients, order, canonicalOptions(), {}, {}, cached);
  for (unsigned p = 0; p < 5; ++p)
    for (int axis = 0; axis < 3; ++axis)
    {
      EXPECT_EQ(reused.bounds(p).lower[axis], reference.bounds(p).lower[axis]) << "glyph " << p;
      EXPECT_EQ(reused.bounds(p).upper[axis], reference.bounds(p).upper[axis]) << "glyph " << p;
    }

  // A cached box is taken as given: proof that it is not recomputed.
  std::vector<vec3> fake(5, vec3(7.0f));
  const SHGlyphSet trusted(centers, coefficients, order, canonicalOptions(), {}, {}, fake);
  EXPECT_FLOAT_EQ(trusted.halfExtents(3).y, 7.0f);

  const std::vector<float> scales(5, -2.5f);
  const SHGlyphSet scaled(centers, coefficients, order, canonicalOptions(), scales);
  for (unsigned p = 0; p < 5; ++p)
    for (int axis = 0; axis < 3; ++axis)
      EXPECT_NEAR(scaled.halfExtents(p)[axis], 2.5f * reference.halfExtents(p)[axis],
        1e-5f * scaled.halfExtents(p)[axis]) << "glyph " << p << " axis " << axis;

  EXPECT_THROW(SHGlyphSet(centers, coefficients, order, canonicalOptions(), {}, {},
                 std::vector<vec3>(4, vec3(1.0f))),
    std::invalid_argument);
}

// Max amplitude: a zonal glyph peaks on the pole with the analytic value sum_l c_l0 Y_l0(pole);
// random glyphs are never below a 200k-direction scan and every value is attained (the search
// only evaluates F). The coefficient norm is the same in every convention.
TEST(SHGlyphSetNormalisation, MaxAmplitudeAndCoefficientNorm)
{
  const int order = 8;
  std::vector<float> zonal(sightline::shCoefficientCount(order), 0.0f);
  double pole = 0.0;
  for (int l = 0; l <= order; l += 2)
  {
    zonal[sightline::shIndex(l, 0)] = float(1.0 / (1 + l));
    pole += double(zonal[sightline::shIndex(l, 0)]) * std::sqrt((2 * l + 1) / (4 * kPi));
  }
  EXPECT_NEAR(sightline::shMaxAmplitude(order, zonal.data(), canonicalConvention()), pole, 1e-5 * pole);

  std::mt19937 random(99);
  const std::vector<dvec3> dense = fibonacciSphere(200000);
  for (int k = 2; k <= 12; k += 2)
  {
    const std::vector<double> b = randomGlyph(k, random, k % 4 == 0 ? 0.0 : 2.0, 0.5);
    const std::vector<float> c(b.begin(), b.end());
    double scan = 0.0;
    for (const dvec3& w : dense)
      scan = std::max(scan, std::abs(glyphFunction(k, b.data(), w)));
    const double found = sightline::shMaxAmplitude(k, c.data(), canonicalConvention());
    EXPECT_GE(found, scan * (1.0 - 1e-9)) << "order " << k; // every peak is climbed
    EXPECT_LE(found, scan * (1.0 + 1e-3)) << "order " << k; // the scan's grid is that fine

    double sum = 0.0;
    for (float v : c)
      sum += double(v) * double(v);
    EXPECT_NEAR(sightline::shCoefficientNorm(k, c.data(), canonicalConvention()), std::sqrt(sum), 1e-12);
  }

  // The same function in DIPY's legacy basis has the same amplitude and norm.
  const std::vector<double> b = randomGlyph(order, random, 1.0, 0.5);
  const std::vector<float> canonical(b.begin(), b.end());
  const SHConvention dipy = SHConvention::fromName("descoteaux07", true);
  std::vector<float> legacy(canonical.size());
  const auto toCanonical = sightline::SHConversion::toCanonical(dipy, order);
  // Invert the signed permutation by converting unit vectors.
  for (std::size_t j = 0; j < canonical.size(); ++j)
  {
    std::vector<float> unit(canonical.size(), 0.0f), image(canonical.size());
    unit[j] = 1.0f;
    toCanonical.apply(unit.data(), image.data());
    for (std::size_t i = 0; i < canonical.size(); ++i)
      if (image[i] != 0.0f)
        legacy[j] = canonical[i] / image[i];
  }
  EXPECT_NEAR(sightline::shMaxAmplitude(order, legacy.data(), dipy),
    sightline::shMaxAmplitude(order, canonical.data(), canonicalConvention()), 1e-9);
  EXPECT_NEAR(sightline::shCoefficientNorm(order, legacy.data(), dipy),
    sightline::shCoefficientNorm(order, canonical.data(), canonicalConvention()), 1e-9);
  EXPECT_THROW(sightline::shMaxAmplitude(7, canonical.data(), canonicalConvention()), std::invalid_argument);
}
