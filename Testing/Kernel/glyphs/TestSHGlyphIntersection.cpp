// SPDX-License-Identifier: BSD-3-Clause
// intersectSHGlyph (Algorithm 1 of Peters et al. 2023) and shGlyphNormal (Eq. 11) against
// independent long double references (SHGlyphTestSupport.h): the reference finds the crossings
// of |p| = |F(p / |p|)| along the ray by certified sampling in the ray's plane, never through
// the polynomial of Algorithm 1.
//
// Units and tolerances. R is the addition-theorem bound on |F| (the glyph's bounding radius),
// the natural size of a glyph; every distance tolerance is relative to it:
//   - double: a root must be within kToleranceDouble = 1e-5 R of the reference (10x the
//     kernel's default tolerance of 1e-6; measured worst 8.6e-7 R over 54,000 random rays);
//   - float: kToleranceFloat = 5e-4 R for k <= 8 and kToleranceFloatHigh = 1e-3 R for k >= 10
//     (the kernel's float tolerance is 1e-4; measured worst 1.3e-4 R for k <= 10).
// Reference roots closer to a neighbour than the "resolution" (1e-5 R in double, 1e-3 R /
// 1e-2 R in float) are a sliver or a nearly tangent pair that the arithmetic cannot separate:
// missing them is counted apart ("unresolved") and not an error (see HitComparison). They occur
// mainly for rays passing within ~1e-4 R of the centre of a glyph with negative lobes, where the
// zero cones of F meet.
//
// Counts of misses / spurious roots per order are printed ("[ glyphs   ]" lines) and recorded
// as test properties.
#include "KernelTestSupport.h"
#include "glyphs/SHGlyphTestSupport.h"

#include "sightline/glyphs/SHGlyph.h"
#include "sightline/math/SphericalHarmonics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using sightline_test::number;
using namespace sightline_test::glyph;
using sightline::dvec3;
using sightline::intersectSHGlyph;
using sightline::kMaxGlyphHits;
using sightline::shCoefficientCount;
using sightline::shGlyphHalfExtents;
using sightline::shGlyphNormal;
using sightline::shIndex;

constexpr long double kToleranceDouble = 1e-5L;
constexpr long double kResolutionDouble = 1e-5L;
constexpr long double kToleranceFloat = 5e-4L;
constexpr long double kResolutionFloat = 1e-3L;
constexpr long double kToleranceFloatHigh = 1e-3L;
constexpr long double kResolutionFloatHigh = 1e-2L;

template <class T>
long double toleranceFor(int order)
{
  if (sizeof(T) == sizeof(double))
    return kToleranceDouble;
  return order <= 8 ? kToleranceFloat : kToleranceFloatHigh;
}
template <class T>
long double resolutionFor(int order)
{
  if (sizeof(T) == sizeof(double))
    return kResolutionDouble;
  return order <= 8 ? kResolutionFloat : kResolutionFloatHigh;
}
template <class T>
const char* typeName()
{
  return sizeof(T) == sizeof(double) ? "double" : "float";
}

/// One ray-glyph query: the inputs rounded to T, the kernel's answer and the reference for
/// exactly those rounded inputs.
template <class T>
struct Query
{
  int order = 0;
  std::vector<T> b;
  std::vector<double> bExact; ///< b in double (exact copy of the T values)
  T origin[3], direction[3];
  T tmin = 0, tmax = std::numeric_limits<T>::infinity();
  long double radius = 0; ///< R of the rounded coefficients
  int count = 0;
  T t[kMaxGlyphHits];
  ReferenceHits reference;
  HitComparison comparison;

  Vec3L originL() const { return { origin[0], origin[1], origin[2] }; }
  Vec3L directionL() const { return { direction[0], direction[1], direction[2] }; }
  /// The point at parameter t along the unit direction, in long double.
  Vec3L point(long double s) const
  {
    const Vec3L d = directionL();
    return add(originL(), scaled(d, s / norm(d)));
  }
};

template <class T>
Query<T> query(int order, const std::vector<double>& coefficients, const Vec3L& origin,
  const Vec3L& direction, long double tmin = 0, long double tmax = INFINITY,
  bool firstOnly = false, long double toleranceScale = 1)
{
  Query<T> q;
  q.order = order;
  for (double x : coefficients)
  {
    q.b.push_back(T(x));
    q.bExact.push_back(double(T(x)));
  }
  q.radius = boundingRadiusReference(order, q.bExact.data());
  // The direction is normalised in long double and then rounded: |d| = 1 to T's precision.
  const long double length = norm(direction);
  for (int i = 0; i < 3; ++i)
  {
    q.origin[i] = T(origin[i]);
    q.direction[i] = T(direction[i] / length);
  }
  q.tmin = T(tmin);
  q.tmax = std::isinf(tmax) ? std::numeric_limits<T>::infinity() : T(tmax);
  q.count = intersectSHGlyph<T>(order, q.b.data(), q.origin, q.direction, q.tmin, q.tmax,
    sightline::defaultGlyphTolerance<T>(), q.t, firstOnly);
  q.reference = referenceHits(order, q.bExact.data(), q.originL(), q.directionL(), q.tmin,
    q.tmax);
  if (firstOnly && q.reference.t.size() > 1)
  {
    q.reference.t.resize(1);
    q.reference.grazing.resize(1);
  }
  q.comparison = compareHits(q.reference, q.t, q.count,
    toleranceScale * toleranceFor<T>(order) * q.radius, q.tmin, q.tmax,
    toleranceScale * resolutionFor<T>(order) * q.radius);
  return q;
}

template <class T>
std::string describe(const Query<T>& q)
{
  std::ostringstream out;
  out.precision(17);
  out << typeName<T>() << " k = " << q.order << ", origin (" << q.origin[0] << ", "
      << q.origin[1] << ", " << q.origin[2] << "), direction (" << q.direction[0] << ", "
      << q.direction[1] << ", " << q.direction[2] << "), t in [" << q.tmin << ", " << q.tmax
      << "], R = " << double(q.radius) << ", ray-centre distance e.o = "
      << double(q.reference.eo / q.radius) << " R, b = {";
  for (std::size_t j = 0; j < q.b.size() && j < 8; ++j)
    out << (j ? ", " : "") << q.b[j];
  out << (q.b.size() > 8 ? ", ...}" : "}") << "\n  " << q.comparison.detail;
  return out.str();
}

/// A random point of the glyph's (padded) box and a ray towards it from 3 R away.
struct AimedRay
{
  Vec3L origin, direction;
};
AimedRay aimAtBox(int order, const std::vector<double>& b, long double distance,
  std::mt19937_64& random)
{
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const dvec3 h = shGlyphHalfExtents(order, b.data());
  const Vec3L target{ h.x * unit(random), h.y * unit(random), h.z * unit(random) };
  const Vec3L direction = randomUnitVector(random);
  return { add(target, scaled(direction, -distance)), direction };
}

std::vector<double> positiveGlyph(int order, std::mt19937_64& random)
{
  // b0 = 1 (F ~ 0.28) and the rest at most 0.02 / sqrt(count): F > 0.2 everywhere.
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> b(shCoefficientCount(order));
  const double scale = 0.02 / std::sqrt(double(b.size()));
  for (double& x : b)
    x = scale * unit(random);
  b[0] = 1.0;
  return b;
}

/// Per-order totals of a random-ray sweep.
struct Totals
{
  int rays = 0, references = 0, misses = 0, spurious = 0, unresolved = 0, unsorted = 0;
  int nearCentre = 0, nearCentreWrong = 0; // rays set apart (float: within 0.02 R of the centre)
  long double worstError = 0; // relative to R
  void add(const HitComparison& c, long double radius)
  {
    ++rays;
    references += c.references;
    misses += c.misses;
    spurious += c.spurious;
    unresolved += c.unresolvedMisses;
    unsorted += !c.sorted;
    worstError = std::max(worstError, c.worstError / radius);
  }
  std::string line() const
  {
    std::ostringstream out;
    out << rays << " rays, " << references << " reference hits: misses " << misses
        << ", spurious " << spurious << ", unresolved " << unresolved << ", worst error "
        << number(worstError) << " R";
    if (nearCentre > 0)
      out << "; set apart: " << nearCentre << " rays within 0.02 R of the centre, "
          << nearCentreWrong << " misses + spurious among them";
    return out.str();
  }
};

constexpr Family kFamilies[] = { Family::Uniform, Family::PositiveMean, Family::Fibres };

/// Random glyphs of all three families and rays from 3 R aimed at random points of their box.
/// In float, rays whose line passes within 0.02 R of the centre are counted apart: they meet the
/// float near-centre defect pinned down by NearCentreOfAPositiveGlyphFloat.
template <class T>
Totals randomRaySweep(int order, int raysPerFamily, std::uint64_t seed, int maxFailuresShown,
  std::vector<std::string>* failures)
{
  const long double setApart = sizeof(T) == sizeof(float) ? 0.02L : 0;
  std::mt19937_64 random(seed);
  Totals totals;
  for (Family family : kFamilies)
    for (int i = 0; i < raysPerFamily; ++i)
    {
      const std::vector<double> b = randomCoefficients(order, family, random);
      const long double radius = boundingRadiusReference(order, b.data());
      const AimedRay ray = aimAtBox(order, b, 3 * radius, random);
      const Query<T> q = query<T>(order, b, ray.origin, ray.direction);
      if (q.reference.eo < setApart * q.radius)
      {
        ++totals.nearCentre;
        totals.nearCentreWrong += q.comparison.misses + q.comparison.spurious;
        continue;
      }
      totals.add(q.comparison, q.radius);
      if (!q.comparison.clean() && failures && int(failures->size()) < maxFailuresShown)
        failures->push_back(std::string(familyName(family)) + ": " + describe(q));
    }
  return totals;
}

// ------------------------------------------------------------------------------------------
// Order 0: a sphere of radius |b0| Y_0^0.

template <class T>
void checkSphere(long double relativeTolerance)
{
  std::mt19937_64 random(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int hits = 0;
  for (int i = 0; i < 4000; ++i)
  {
    const double b0 = (random() % 2 ? 1 : -1) * std::exp(3 * unit(random));
    const std::vector<double> b{ b0 };
    const long double r = std::fabs((long double)T(b0)) * y00();
    Vec3L origin{ 4 * r * unit(random), 4 * r * unit(random), 4 * r * unit(random) };
    const Vec3L target{ 1.2L * r * unit(random), 1.2L * r * unit(random), 1.2L * r * unit(random) };
    const Query<T> q = query<T>(0, b, origin, add(target, scaled(origin, -1)));
    // Analytic roots in long double for the rounded inputs.
    const Vec3L o = q.originL();
    const Vec3L d = scaled(q.directionL(), 1 / norm(q.directionL()));
    const long double dO = dot(d, o);
    const long double eo2 = dot(o, o) - dO * dO;
    std::vector<long double> expected;
    if (eo2 < r * r)
    {
      const long double half = std::sqrt(r * r - eo2);
      // Grazing rays (half chord < 1e-3 r) are tested separately.
      if (half < 1e-3L * r)
        continue;
      for (long double t : { -dO - half, -dO + half })
        if (t >= 0)
          expected.push_back(t);
    }
    else if (eo2 < r * r * (1 + 1e-6L))
      continue;
    SCOPED_TRACE(describe(q));
    ASSERT_EQ(q.count, int(expected.size()));
    for (int j = 0; j < q.count; ++j)
      EXPECT_NEAR(double(q.t[j]), double(expected[j]),
        double(relativeTolerance * std::max(r, norm(o))));
    hits += q.count;
  }
  EXPECT_GT(hits, 2000);
}

// Random rays against the analytic sphere, double: |t - t_exact| <= 1e-12 max(r, |o|) away
// from grazing (half chord >= 1e-3 r); float: 2e-6 max(r, |o|) (a few float ulps of |o|).
TEST(SHGlyphIntersection, OrderZeroIsTheSphereDouble)
{
  checkSphere<double>(1e-12L);
}
TEST(SHGlyphIntersection, OrderZeroIsTheSphereFloat)
{
  checkSphere<float>(2e-6L);
}

// Grazing rays on the sphere: at distance r (1 - delta) the two roots -d.o +- r sqrt(2 delta)
// must be found to 1e-12 r + 4 eps r / sqrt(delta) in double (the conditioning of a root pair);
// at r (1 + delta) nothing; at exactly r (eps = e.o / g_max = 1 in the kernel) no crash, and
// whatever is reported lies within 1e-7 r of the tangent point.
TEST(SHGlyphIntersection, GrazingRaysOnTheSphere)
{
  for (double b0 : { 1.0, -3.5, 1e-3 })
  {
    const std::vector<double> b{ b0 };
    // The kernel's radius: F evaluated in double, the value the tangent test below hits exactly.
    const double r = std::fabs(sightline::evaluateSHSum<double>(0, b.data(), 0.0, 0.0, 1.0));
    ASSERT_NEAR(r, std::fabs(b0) * double(y00()), 1e-15 * r);
    double t[kMaxGlyphHits];
    for (int j = 1; j <= 14; ++j)
    {
      const long double delta = std::pow(10.0L, -j);
      for (int side : { -1, 1 })
      {
        const double offset = double(r * (1 + side * delta));
        const double origin[3] = { offset, 0.0, -10 * r };
        const double direction[3] = { 0.0, 0.0, 1.0 };
        const int count = intersectSHGlyph<double>(0, b.data(), origin, direction, 0.0, INFINITY,
          1e-6, t, false);
        const long double eo = offset;
        SCOPED_TRACE("b0 = " + std::to_string(b0) + ", delta = 1e-" + std::to_string(j) +
          (side < 0 ? " inside" : " outside"));
        if (eo >= r)
        {
          EXPECT_EQ(count, 0);
          continue;
        }
        const long double half = std::sqrt((long double)r * r - eo * eo);
        const long double tolerance =
          1e-12L * r + 4 * std::numeric_limits<double>::epsilon() * r * r / half;
        ASSERT_EQ(count, 2);
        EXPECT_NEAR(t[0], double(10 * r - half), double(tolerance));
        EXPECT_NEAR(t[1], double(10 * r + half), double(tolerance));
      }
    }
    // Exactly tangent, in double and float.
    {
      const double origin[3] = { r, 0.0, -10 * r };
      const double direction[3] = { 0.0, 0.0, 1.0 };
      const int count =
        intersectSHGlyph<double>(0, b.data(), origin, direction, 0.0, INFINITY, 1e-6, t, false);
      EXPECT_LE(count, 2);
      for (int i = 0; i < count; ++i)
        EXPECT_NEAR(t[i], 10 * r, 1e-7 * r) << "exact tangent, double";
    }
    {
      const float bf = float(b0);
      const float rf = std::fabs(sightline::evaluateSHSum<float>(0, &bf, 0.0f, 0.0f, 1.0f));
      const float origin[3] = { rf, 0.0f, -10 * rf };
      const float direction[3] = { 0.0f, 0.0f, 1.0f };
      float tf[kMaxGlyphHits];
      const int count =
        intersectSHGlyph<float>(0, &bf, origin, direction, 0.0f, INFINITY, 1e-4f, tf, false);
      EXPECT_LE(count, 2);
      for (int i = 0; i < count; ++i)
        EXPECT_NEAR(tf[i], 10 * rf, 1e-3 * rf) << "exact tangent, float";
    }
  }
}

// ------------------------------------------------------------------------------------------
// Random rays, all orders. Target for double: no misses and no spurious roots at all.

TEST(SHGlyphIntersection, RandomRaysDouble)
{
  for (int order = 0; order <= 16; order += 2)
  {
    const int rays = order <= 12 ? 300 : 100;
    std::vector<std::string> failures;
    const Totals totals = randomRaySweep<double>(order, rays, 1000 + order, 5, &failures);
    std::cout << "[ glyphs   ] double k = " << order << ": " << totals.line() << std::endl;
    const std::string key = "double_k" + std::to_string(order) + "_";
    RecordProperty(key + "misses", totals.misses);
    RecordProperty(key + "spurious", totals.spurious);
    RecordProperty(key + "unresolved", totals.unresolved);
    RecordProperty(key + "worst_error", number(totals.worstError));
    SCOPED_TRACE("k = " + std::to_string(order) + ": " + totals.line());
    EXPECT_EQ(totals.misses, 0);
    EXPECT_EQ(totals.spurious, 0);
    EXPECT_EQ(totals.unsorted, 0);
    EXPECT_GT(totals.references, totals.rays); // most rays hit
    for (const std::string& failure : failures)
      ADD_FAILURE() << failure;
  }
}

// Float: no misses and no spurious roots for k <= 10 at 5e-4 R (k <= 8) / 1e-3 R (k = 10);
// measured worst errors 1e-4 R. From k = 12 on, single precision loses roots (Peters et al.,
// Sec. 5.2, report the same for float at k = 10 and 12); the bound asserted for k = 12 is the
// measured rate with a margin: (misses + spurious) <= 10 % of the reference hits (measured
// 3.5 % here; 5.4 % over 6000 rays of a longer offline run, 9.4 % for the uniform family
// alone). k = 14 and 16 are reported only (measured 96 % and 220 %: float is not usable there),
// but must stay sorted and inside [tmin, tmax]. Rays within 0.02 R of the centre are set apart
// (see randomRaySweep); a 54,000-ray offline run found float errors for k <= 10 only among
// those (1 at k = 8, 1 at k = 10).
TEST(SHGlyphIntersection, RandomRaysFloat)
{
  for (int order = 0; order <= 16; order += 2)
  {
    const int rays = order <= 12 ? 300 : 100;
    std::vector<std::string> failures;
    const Totals totals = randomRaySweep<float>(order, rays, 2000 + order, 5, &failures);
    std::cout << "[ glyphs   ] float  k = " << order << ": " << totals.line() << std::endl;
    const std::string key = "float_k" + std::to_string(order) + "_";
    RecordProperty(key + "misses", totals.misses);
    RecordProperty(key + "spurious", totals.spurious);
    RecordProperty(key + "unresolved", totals.unresolved);
    RecordProperty(key + "worst_error", number(totals.worstError));
    SCOPED_TRACE("k = " + std::to_string(order) + ": " + totals.line());
    EXPECT_EQ(totals.unsorted, 0);
    const int wrong = totals.misses + totals.spurious;
    if (order <= 10)
    {
      EXPECT_EQ(wrong, 0);
      for (const std::string& failure : failures)
        ADD_FAILURE() << failure;
    }
    else if (order == 12)
    {
      EXPECT_LE(wrong, totals.references / 10);
    }
  }
}

// firstOnly returns exactly the smallest root in [tmin, tmax] of the full answer.
template <class T>
void checkFirstOnly(int maxOrder)
{
  std::mt19937_64 random(31);
  for (int order = 0; order <= maxOrder; order += 2)
    for (Family family : kFamilies)
      for (int i = 0; i < 60; ++i)
      {
        const std::vector<double> b = randomCoefficients(order, family, random);
        const long double radius = boundingRadiusReference(order, b.data());
        const AimedRay ray = aimAtBox(order, b, 3 * radius, random);
        // Half the rays start at a random point along the way, some inside the glyph.
        std::uniform_real_distribution<double> start(0.5, 1.2);
        const long double tmin = i % 2 ? 3 * radius * start(random) : 0;
        const Query<T> all = query<T>(order, b, ray.origin, ray.direction, tmin);
        const Query<T> first = query<T>(order, b, ray.origin, ray.direction, tmin, INFINITY, true);
        SCOPED_TRACE(describe(first));
        ASSERT_EQ(first.count, std::min(1, all.count));
        if (first.count == 1)
        {
          EXPECT_EQ(first.t[0], all.t[0]);
          EXPECT_GE(first.t[0], first.tmin);
        }
        if (all.comparison.clean())
        {
          EXPECT_TRUE(first.comparison.clean());
        }
      }
}
TEST(SHGlyphIntersection, FirstOnlyReturnsTheSmallestRootDouble)
{
  checkFirstOnly<double>(16);
}
TEST(SHGlyphIntersection, FirstOnlyReturnsTheSmallestRootFloat)
{
  checkFirstOnly<float>(8);
}

// tmin and tmax clip the answer to exactly the roots inside: rays with >= 4 hits, the interval
// cut halfway between hits 1 and 2 and between hits 3 and 4 (and beyond both ends).
template <class T>
void checkClipping(int maxOrder)
{
  std::mt19937_64 random(41);
  int clipped = 0;
  for (int order = 4; order <= maxOrder; order += 2)
    for (int i = 0; i < 200 && clipped < 40 * (order / 2 - 1); ++i)
    {
      const std::vector<double> b = randomCoefficients(order, Family::Uniform, random);
      const long double radius = boundingRadiusReference(order, b.data());
      const AimedRay ray = aimAtBox(order, b, 3 * radius, random);
      const Query<T> all = query<T>(order, b, ray.origin, ray.direction);
      if (!all.comparison.clean() || all.count < 4 || all.comparison.unresolvedMisses > 0)
        continue;
      ++clipped;
      const long double tmin = 0.5L * ((long double)all.t[0] + all.t[1]);
      const long double tmax = 0.5L * ((long double)all.t[2] + all.t[3]);
      const Query<T> cut = query<T>(order, b, ray.origin, ray.direction, tmin, tmax);
      SCOPED_TRACE(describe(cut));
      EXPECT_TRUE(cut.comparison.clean());
      ASSERT_EQ(cut.count, 2);
      EXPECT_GE(cut.t[0], cut.tmin);
      EXPECT_LE(cut.t[1], cut.tmax);
      // Nothing before the first hit or after the last one.
      const long double before = (long double)all.t[0] - 0.1L * radius;
      EXPECT_EQ(query<T>(order, b, ray.origin, ray.direction, 0, before).count, 0);
      const long double after = (long double)all.t[all.count - 1] + 0.1L * radius;
      EXPECT_EQ(query<T>(order, b, ray.origin, ray.direction, after).count, 0);
      // An empty interval.
      EXPECT_EQ(query<T>(order, b, ray.origin, ray.direction, tmax, tmin).count, 0);
    }
  EXPECT_GT(clipped, 40);
}
TEST(SHGlyphIntersection, TminTmaxClipDouble)
{
  checkClipping<double>(12);
}
TEST(SHGlyphIntersection, TminTmaxClipFloat)
{
  checkClipping<float>(8);
}

// ------------------------------------------------------------------------------------------
// Rays through or near the centre.

// A glyph with F > 0.2 everywhere (so the centre is strictly inside it) and a ray exactly
// through the centre: the surface is crossed exactly twice, at t = -d.o -+ F(d).
// KNOWN BUG (fails at the time of writing, k >= 2, double and float): with e.o = 0 the
// polynomial of Algorithm 1 is w^(2k) ((g_k / g_max)^2 - w^2), whose root w = 0 of multiplicity
// 2k makes the kernel report a third "hit" at the centre, t = -d.o, where |p| = 0 < F.
template <class T>
void checkExactCentre()
{
  std::mt19937_64 random(51);
  for (int order = 0; order <= 16; order += 2)
  {
    int rays = 0, wrong = 0;
    std::string example;
    for (int i = 0; i < 8; ++i)
    {
      const std::vector<double> b = positiveGlyph(order, random);
      // Axis-aligned directions make e.o exactly zero in any arithmetic; the others do so when
      // the rounded direction happens to be an exact multiple of the origin.
      Vec3L direction{ 0, 0, 0 };
      if (i < 3)
        direction[i] = 1;
      else
        direction = randomUnitVector(random);
      const Vec3L d{ T(direction[0]), T(direction[1]), T(direction[2]) };
      const Query<T> q = query<T>(order, b, scaled(d, -4), d); // 4 = 14 R: well outside
      if (q.reference.eo != 0)
        continue; // the rounded direction was not quite unit: not a centre ray
      ++rays;
      EXPECT_EQ(q.reference.t.size(), 2u) << describe(q);
      if (q.count != 2 || !q.comparison.clean())
      {
        ++wrong;
        if (example.empty())
          example = describe(q);
      }
    }
    EXPECT_EQ(wrong, 0) << typeName<T>() << " k = " << order << ": " << wrong << " of " << rays
                        << " rays through the exact centre of a glyph that contains the centre "
                           "do not report exactly its two crossings, e.g.\n"
                        << example;
    EXPECT_GE(rays, 3);
  }
}
TEST(SHGlyphIntersection, RayThroughTheExactCentreDouble)
{
  checkExactCentre<double>();
}
TEST(SHGlyphIntersection, RayThroughTheExactCentreFloat)
{
  checkExactCentre<float>();
}

// Rays 1e-2, 1e-4 and 1e-7 R from the centre, random glyphs of all families: double finds
// everything resolvable (near the centre of a glyph with negative lobes the zero cones give
// root pairs only ~e.o^2 apart, which are unresolved by definition).
TEST(SHGlyphIntersection, NearCentreRaysDouble)
{
  std::mt19937_64 random(61);
  for (int order = 2; order <= 16; order += 2)
  {
    Totals totals;
    for (long double offset : { 1e-2L, 1e-4L, 1e-7L })
      for (Family family : kFamilies)
        for (int i = 0; i < 20; ++i)
        {
          const std::vector<double> b = randomCoefficients(order, family, random);
          const long double radius = boundingRadiusReference(order, b.data());
          const Vec3L d = randomUnitVector(random);
          Vec3L side = randomUnitVector(random);
          side = add(side, scaled(d, -dot(side, d)));
          side = scaled(side, 1 / norm(side));
          const Vec3L origin = add(scaled(d, -3 * radius), scaled(side, offset * radius));
          const Query<double> q = query<double>(order, b, origin, d);
          totals.add(q.comparison, q.radius);
          if (!q.comparison.clean())
            ADD_FAILURE() << "offset " << double(offset) << " R: " << describe(q);
        }
    std::cout << "[ glyphs   ] near-centre double k = " << order << ": " << totals.line()
              << std::endl;
    RecordProperty("near_centre_k" + std::to_string(order) + "_unresolved", totals.unresolved);
  }
}

// A glyph with F > 0.2 everywhere and rays parallel to an axis at 1e-7 R from the centre (e.o
// exact in float and double): two crossings, nothing at the centre.
// KNOWN BUG (fails at the time of writing for float, k >= 4; double passes): the kernel's h_i
// = g_i / g_max eps^(k - i), eps = e.o / g_max, underflow for small eps, so that P(0) = h_0^2 -
// eps^(2k+2) is exactly 0 and w = 0 is reported as a touching root: a hit at the centre, where
// |p| = e.o << F. Measured onset (largest e.o with the extra hit, rays along z, b0 = 1 and the
// other coefficients <= 0.02, R ~ 0.3): 1e-6 (k = 4), 1e-4 (k = 6), 1e-3 (k = 8), 3e-3 (k = 10),
// 1e-2 (k = 12), 3e-2 (k = 14, 16) in float; 1e-17 (k = 10), 3e-15 (k = 12), 3e-12 (k = 14, 16)
// in double. Random rays meet it too (RandomRaysFloat sets rays within 0.02 R apart).
template <class T>
void checkNearCentreOfPositiveGlyph()
{
  std::mt19937_64 random(71);
  for (int order = 2; order <= 16; order += 2)
  {
    int wrong = 0;
    std::string example;
    for (int axis = 0; axis < 3; ++axis)
    {
      const std::vector<double> b = positiveGlyph(order, random);
      const long double radius = boundingRadiusReference(order, b.data());
      Vec3L d{ 0, 0, 0 }, origin{ 0, 0, 0 };
      d[axis] = 1;
      origin[axis] = -4;
      origin[(axis + 1) % 3] = T(1e-7L * radius);
      const Query<T> q = query<T>(order, b, origin, d);
      EXPECT_EQ(q.reference.t.size(), 2u) << describe(q);
      if (q.count != 2 || !q.comparison.clean())
      {
        ++wrong;
        if (example.empty())
          example = describe(q);
      }
    }
    EXPECT_EQ(wrong, 0) << typeName<T>() << " k = " << order << ": " << wrong
                        << " of 3 rays 1e-7 R from the centre of a glyph with F > 0 do not "
                           "report exactly its two crossings, e.g.\n"
                        << example;
  }
}
TEST(SHGlyphIntersection, NearCentreOfAPositiveGlyphDouble)
{
  checkNearCentreOfPositiveGlyph<double>();
}
TEST(SHGlyphIntersection, NearCentreOfAPositiveGlyphFloat)
{
  checkNearCentreOfPositiveGlyph<float>();
}

// The pure zonal glyph Y_4^0 (F = 3 / (16 sqrt(pi)) (35 z^4 - 30 z^2 + 3)): two zero cones
// through the centre, a negative belt, roots of high multiplicity for rays along z.
TEST(SHGlyphIntersection, ZonalY40AlongTheAxis)
{
  std::vector<double> b(shCoefficientCount(4), 0.0);
  b[shIndex(4, 0)] = 1.0;
  const long double top = 3 / (16 * std::sqrt(kPi)) * 8; // F(z = +-1)
  const long double radius = boundingRadiusReference(4, b.data());
  double t[kMaxGlyphHits];
  // Exactly along the axis: crossings at -d.o -+ F(z) = 5 -+ 0.846. The centre is a point of
  // this glyph's surface (the zero cones meet there), so a touching root there is allowed.
  for (double sign : { 1.0, -1.0 })
  {
    const double origin[3] = { 0.0, 0.0, -5.0 * sign };
    const double direction[3] = { 0.0, 0.0, sign };
    const int count =
      intersectSHGlyph<double>(4, b.data(), origin, direction, 0.0, INFINITY, 1e-6, t, false);
    ASSERT_GE(count, 2);
    ASSERT_LE(count, 3);
    EXPECT_NEAR(t[0], double(5 - top), double(kToleranceDouble * radius));
    EXPECT_NEAR(t[count - 1], double(5 + top), double(kToleranceDouble * radius));
    if (count == 3)
    {
      EXPECT_NEAR(t[1], 5.0, double(kToleranceDouble * radius));
    }
  }
  // Parallel to the axis at offsets from 1e-8 to 0.5 R, and along the zero cones: against the
  // reference.
  const long double zCone[2] = { std::sqrt((30 - std::sqrt(480.0L)) / 70),
    std::sqrt((30 + std::sqrt(480.0L)) / 70) };
  std::mt19937_64 random(81);
  for (int j = 0; j <= 8; ++j)
    for (int i = 0; i < 3; ++i)
    {
      const long double offset = 0.5L * std::pow(10.0L, -j) * radius;
      Vec3L d{ 0, 0, 1 };
      if (i > 0)
      {
        // Along a zero cone, with a random azimuth.
        const long double z = zCone[i - 1];
        const long double phi = 2 * kPi * std::uniform_real_distribution<double>(0, 1)(random);
        const long double s = std::sqrt(1 - z * z);
        d = { s * std::cos(phi), s * std::sin(phi), z };
      }
      Vec3L side = randomUnitVector(random);
      side = add(side, scaled(d, -dot(side, d)));
      side = scaled(side, 1 / norm(side));
      const Vec3L origin = add(scaled(d, -3 * radius), scaled(side, offset));
      const Query<double> q = query<double>(4, b, origin, d);
      EXPECT_TRUE(q.comparison.clean()) << describe(q);
    }
  // Exactly along a zero cone through the centre: F(d) = 0, the ray only touches the surface at
  // the centre. Anything reported must be the centre.
  for (long double z : zCone)
  {
    const double s = double(std::sqrt(1 - z * z));
    const double direction[3] = { s, 0.0, double(z) };
    const double origin[3] = { -3 * direction[0], 0.0, -3 * direction[2] };
    const int count =
      intersectSHGlyph<double>(4, b.data(), origin, direction, 0.0, INFINITY, 1e-6, t, false);
    for (int i = 0; i < count; ++i)
    {
      EXPECT_TRUE(std::isfinite(t[i]));
      EXPECT_NEAR(t[i], 3.0, 1e-3) << "along a zero cone, hit " << i << " of " << count;
    }
  }
}

// Glyphs with negative lobes: pure zonal Y_2^0, Y_4^0, Y_6^0, a sectoral Y_4^4 and random
// uniform glyphs, random rays; all hits found, and many of them on negative lobes.
TEST(SHGlyphIntersection, NegativeLobes)
{
  std::mt19937_64 random(91);
  int negativeHits = 0;
  Totals totals;
  for (int order = 2; order <= 8; order += 2)
    for (int variant = 0; variant < 3; ++variant)
    {
      std::vector<double> b(shCoefficientCount(order), 0.0);
      if (variant == 0)
        b[shIndex(order, 0)] = 1.0;
      else if (variant == 1)
        b[shIndex(order, order)] = -1.0;
      else
        b = randomCoefficients(order, Family::Uniform, random);
      const long double radius = boundingRadiusReference(order, b.data());
      for (int i = 0; i < 150; ++i)
      {
        const AimedRay ray = aimAtBox(order, b, 3 * radius, random);
        const Query<double> q = query<double>(order, b, ray.origin, ray.direction);
        totals.add(q.comparison, q.radius);
        if (!q.comparison.clean())
          ADD_FAILURE() << describe(q);
        for (long double s : q.reference.t)
          negativeHits += evaluateF(order, b.data(), q.point(s)) < 0;
      }
    }
  std::cout << "[ glyphs   ] negative lobes: " << totals.line() << ", " << negativeHits
            << " reference hits on negative lobes" << std::endl;
  EXPECT_GT(negativeHits, 500);
}

// Secondary rays from inside: origins at a random fraction of the way from the centre to the
// surface, tmin = 0; the exits must be found (an odd number of crossings when nothing is
// unresolved) and match the reference. In float, rays whose line passes within 0.01 R of the
// centre are left out (counted): they run into the float near-centre defect that
// NearCentreOfAPositiveGlyphFloat pins down (the low coefficients of Algorithm 1's polynomial
// scale like (e.o / g_max)^(2k) and become subnormal or zero).
template <class T>
void checkRaysFromInside(int maxOrder)
{
  std::mt19937_64 random(101);
  std::uniform_real_distribution<double> fraction(0.05, 0.95);
  const bool single = sizeof(T) == sizeof(float);
  for (int order = 0; order <= maxOrder; order += 2)
  {
    Totals totals;
    int skipped = 0;
    for (Family family : kFamilies)
      for (int i = 0; i < 60; ++i)
      {
        const std::vector<double> b = randomCoefficients(order, family, random);
        const Vec3L w = randomUnitVector(random);
        std::vector<double> rounded;
        for (double x : b)
          rounded.push_back(double(T(x)));
        const long double f = std::fabs(evaluateF(order, rounded.data(), w));
        const Vec3L origin = scaled(w, fraction(random) * f);
        const Query<T> q = query<T>(order, b, origin, randomUnitVector(random));
        if (surfaceResidual(order, q.bExact.data(), q.originL()) > -1e-3L * q.radius ||
          (single && q.reference.eo < 0.01L * q.radius))
        {
          ++skipped; // rounding put the origin (nearly) on the surface, or float near the centre
          continue;
        }
        totals.add(q.comparison, q.radius);
        SCOPED_TRACE(describe(q));
        if (q.comparison.unresolvedMisses == 0)
        {
          EXPECT_EQ(q.reference.t.size() % 2, 1u) << "reference parity";
          EXPECT_EQ(q.count % 2, 1) << "a ray from inside must leave the glyph";
        }
        EXPECT_TRUE(q.comparison.clean());
      }
    std::cout << "[ glyphs   ] from inside " << typeName<T>() << " k = " << order << ": "
              << totals.line() << " (" << skipped << " left out)" << std::endl;
    EXPECT_GT(totals.rays, single ? 100 : 150);
  }
}
TEST(SHGlyphIntersection, RaysFromInsideDouble)
{
  checkRaysFromInside<double>(16);
}
TEST(SHGlyphIntersection, RaysFromInsideFloat)
{
  checkRaysFromInside<float>(8);
}

// Shadow rays: from a hit point of a primary ray, in a random direction, with
// tmin = 1e-4 R to step off the surface: no self-hit, and the rest as the reference.
TEST(SHGlyphIntersection, SecondaryRaysFromTheSurface)
{
  std::mt19937_64 random(111);
  int rays = 0;
  for (int order = 2; order <= 12; order += 2)
    for (Family family : kFamilies)
      for (int i = 0; i < 40; ++i)
      {
        const std::vector<double> b = randomCoefficients(order, family, random);
        const long double radius = boundingRadiusReference(order, b.data());
        const AimedRay ray = aimAtBox(order, b, 3 * radius, random);
        const Query<double> primary = query<double>(order, b, ray.origin, ray.direction);
        if (primary.count == 0 || !primary.comparison.clean())
          continue;
        const Vec3L hit = primary.point(primary.t[0]);
        const long double tmin = 1e-4L * radius;
        const Query<double> shadow =
          query<double>(order, b, hit, randomUnitVector(random), tmin);
        // A reference root within the tolerance of tmin may fall either way.
        bool ambiguous = false;
        for (long double t : referenceHits(order, shadow.bExact.data(), shadow.originL(),
               shadow.directionL(), 0, INFINITY).t)
          ambiguous = ambiguous || std::fabs(t - tmin) < 2 * kToleranceDouble * radius;
        if (ambiguous)
          continue;
        ++rays;
        EXPECT_TRUE(shadow.comparison.clean()) << describe(shadow);
        for (int j = 0; j < shadow.count; ++j)
          EXPECT_GE(shadow.t[j], tmin);
      }
  EXPECT_GT(rays, 300);
}

// Ray origins 1e4 R away, aimed at the glyph's box. Double: the usual tolerance (t ~ 1e4 R
// costs 1e4 R * 1.1e-16 ~ 1e-12 R). Float, k <= 8: the float origin alone is uncertain by
// |o| 2^-24 = 6e-4 R, e = o - (d.o) d cancels 1e4 R down to R and oblique incidence magnifies
// lateral errors, so 3e-2 R (resolution 6e-2 R); measured worst 1e-2 R.
TEST(SHGlyphIntersection, FarAwayOrigins)
{
  std::mt19937_64 random(121);
  for (int order = 2; order <= 12; order += 2)
  {
    Totals doubles, floats;
    for (Family family : kFamilies)
      for (int i = 0; i < 40; ++i)
      {
        const std::vector<double> b = randomCoefficients(order, family, random);
        const long double radius = boundingRadiusReference(order, b.data());
        const AimedRay ray = aimAtBox(order, b, 1e4L * radius, random);
        const Query<double> q = query<double>(order, b, ray.origin, ray.direction);
        doubles.add(q.comparison, q.radius);
        EXPECT_TRUE(q.comparison.clean()) << describe(q);
        if (order <= 8)
        {
          const Query<float> f =
            query<float>(order, b, ray.origin, ray.direction, 0, INFINITY, false, 60);
          floats.add(f.comparison, f.radius);
          EXPECT_TRUE(f.comparison.clean()) << describe(f);
        }
      }
    std::cout << "[ glyphs   ] origin 1e4 R away, k = " << order << ": double " << doubles.line();
    if (order <= 8)
      std::cout << "; float " << floats.line();
    std::cout << std::endl;
  }
}

// Near-silhouette rays of order-4 glyphs: in the plane of a random direction d and normal e,
// the silhouette is at e.o = s = max_theta |F(cos theta d + sin theta e)| sin theta. Rays at
// s (1 - delta) cross twice near the tangent point, at s (1 + delta) not at all. Whatever the
// kernel reports must be as the reference within tolerance, with pairs closer than the
// resolution (delta <~ 1e-10) allowed to be missed as a pair.
/// Rays just inside and just outside the silhouette (the largest height of the glyph's
/// cross-section in the ray's plane, found independently of the kernel) at relative distances
/// 1e-2 to 1e-12: inside, both crossings are found; outside, none. This is where the kernel's
/// culling tests (the sampled cross-section height with Bernstein's bound) are tightest.
/// Returns how many inside rays gave a clean pair.
int nearSilhouetteRays(int order, int glyphs, std::uint64_t seed)
{
  std::mt19937_64 random(seed);
  int pairsFound = 0;
  for (int i = 0; i < glyphs; ++i)
  {
    const std::vector<double> b = randomCoefficients(order, kFamilies[i % 3], random);
    const Vec3L d = randomUnitVector(random);
    Vec3L e = randomUnitVector(random);
    e = add(e, scaled(d, -dot(e, d)));
    e = scaled(e, 1 / norm(e));
    auto G = [&](long double theta)
    {
      const Vec3L w = add(scaled(d, std::cos(theta)), scaled(e, std::sin(theta)));
      return std::fabs(evaluateF(order, b.data(), w)) * std::sin(theta);
    };
    // Silhouette: dense sampling, then golden-section refinement to long double precision.
    const int samples = 1000 * (order + 1);
    long double bestTheta = 0, best = -1;
    for (int j = 1; j < samples; ++j)
    {
      const long double theta = kPi * j / samples;
      if (G(theta) > best)
      {
        best = G(theta);
        bestTheta = theta;
      }
    }
    long double lo = bestTheta - kPi / samples, hi = bestTheta + kPi / samples;
    for (int j = 0; j < 200; ++j)
    {
      const long double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (G(m1) < G(m2))
        lo = m1;
      else
        hi = m2;
    }
    const long double silhouette = G(0.5L * (lo + hi));
    const long double radius = boundingRadiusReference(order, b.data());
    for (int j = 2; j <= 12; j += 2)
      for (int side : { -1, 1 })
      {
        const long double eo = silhouette * (1 + side * std::pow(10.0L, -j));
        const Vec3L origin = add(scaled(d, -3 * radius), scaled(e, eo));
        const Query<double> q = query<double>(order, b, origin, d);
        SCOPED_TRACE("order " + std::to_string(order) + ", glyph " + std::to_string(i) + ", delta = 1e-" +
          std::to_string(j) + (side < 0 ? " inside" : " outside"));
        EXPECT_TRUE(q.comparison.clean()) << describe(q);
        if (side > 0)
          EXPECT_EQ(q.count, 0) << describe(q);
        else
          pairsFound += q.count >= 2 && q.comparison.unresolvedMisses == 0;
      }
  }
  return pairsFound;
}

TEST(SHGlyphIntersection, NearSilhouetteRaysOrder4)
{
  EXPECT_GT(nearSilhouetteRays(4, 40, 131), 150);
}

TEST(SHGlyphIntersection, NearSilhouetteRaysHighOrders)
{
  for (int order : { 8, 12, 16 })
    EXPECT_GT(nearSilhouetteRays(order, 12, 137 + order), 40) << "order " << order;
}

// Nearly zero glyphs: coefficients 1e-20 (and 1e-150 in double; below ~1e-154 the squares in
// the kernel's |o - (d.o) d| underflow and rays are taken for centre rays, a limit of double
// that no glyph data reaches). The answer scales with the glyph (rays scaled alike), nothing is
// NaN, and a ray passing at distance 1 misses.
TEST(SHGlyphIntersection, NearlyZeroGlyphs)
{
  std::mt19937_64 random(141);
  for (int order = 0; order <= 16; order += 2)
    for (int i = 0; i < 10; ++i)
    {
      const std::vector<double> unitB = randomCoefficients(order, kFamilies[i % 3], random);
      const long double radius = boundingRadiusReference(order, unitB.data());
      const AimedRay ray = aimAtBox(order, unitB, 3 * radius, random);
      const Query<double> reference = query<double>(order, unitB, ray.origin, ray.direction);
      for (long double scale : { 1e-20L, 1e-150L })
      {
        std::vector<double> b;
        for (double x : unitB)
          b.push_back(double(x * scale));
        const Query<double> q =
          query<double>(order, b, scaled(ray.origin, scale), ray.direction);
        SCOPED_TRACE(describe(q));
        for (int j = 0; j < q.count; ++j)
          ASSERT_TRUE(std::isfinite(q.t[j]));
        EXPECT_TRUE(q.comparison.clean());
        EXPECT_EQ(q.count, reference.count);
        // Far from the tiny glyph: nothing.
        double t[kMaxGlyphHits];
        const double origin[3] = { 1.0, 0.5, -2.0 }, direction[3] = { 0.0, 0.0, 1.0 };
        EXPECT_EQ(intersectSHGlyph<double>(order, b.data(), origin, direction, 0.0, INFINITY,
                    1e-6, t, false),
          0);
      }
      // Float: 1e-20. Squares of coordinates ~1e-40 are subnormal in float, so the kernel's
      // |e.o| carries ~1e-3 relative error: 10x the float tolerance (5e-3 R) for k <= 8.
      const Query<float> f =
        query<float>(order, [&] {
          std::vector<double> b;
          for (double x : unitB)
            b.push_back(double(x * 1e-20L));
          return b;
        }(), scaled(ray.origin, 1e-20L), ray.direction, 0, INFINITY, false, 10);
      for (int j = 0; j < f.count; ++j)
        EXPECT_TRUE(std::isfinite(f.t[j])) << describe(f);
      if (order <= 8)
      {
        EXPECT_TRUE(f.comparison.clean()) << describe(f);
      }
      // Rays through the exact centre of a tiny glyph from far away: finite answers.
      double t[kMaxGlyphHits];
      std::vector<double> tiny;
      for (double x : unitB)
        tiny.push_back(x * 1e-20);
      const double origin[3] = { 0.0, 0.0, -1.0 }, direction[3] = { 0.0, 0.0, 1.0 };
      const int count =
        intersectSHGlyph<double>(order, tiny.data(), origin, direction, 0.0, INFINITY, 1e-6, t,
          false);
      for (int j = 0; j < count; ++j)
        EXPECT_TRUE(std::isfinite(t[j]) && std::fabs(t[j] - 1.0) < 1e-15);
    }
  // All-zero coefficients: no glyph, no hits.
  std::vector<double> zero(shCoefficientCount(8), 0.0);
  double t[kMaxGlyphHits];
  const double origin[3] = { 0.0, 0.0, -1.0 }, direction[3] = { 0.0, 0.0, 1.0 };
  EXPECT_EQ(
    intersectSHGlyph<double>(8, zero.data(), origin, direction, 0.0, INFINITY, 1e-6, t, false),
    0);
}

TEST(SHGlyphIntersection, InvalidOrdersThrow)
{
  std::vector<double> b(shCoefficientCount(16), 0.1);
  double t[kMaxGlyphHits];
  const double origin[3] = { 0.0, 0.0, -1.0 }, direction[3] = { 0.0, 0.0, 1.0 };
  for (int order : { -2, 1, 3, 18 })
    EXPECT_THROW(intersectSHGlyph<double>(order, b.data(), origin, direction, 0.0, INFINITY,
                   1e-6, t, false),
      std::invalid_argument)
      << "order " << order;
}

// ------------------------------------------------------------------------------------------
// Normals (Eq. 11): n = p - F(w) (I - w w^T) grad F(w) / |p| is half the gradient of
// phi(p) = |p|^2 - F(p / |p|)^2. Reference gradient: fourth-order central differences of phi in
// long double with step h = 2e-4 |p| (truncation ~(k h / |p|)^4 < 1e-11 relative; rounding of
// F in double ~1e-16 R^2 / h, < 1e-9 relative for |p| >= 0.01 R, the points tested). The angle
// between n and the gradient must be below 1e-6 rad with the same orientation; `value` must be
// F(w) (sign included, so negative lobes are told apart) to 1e-12 R; n points outwards
// (n . p = |p|^2 > 0, since the tangential term is orthogonal to p).
TEST(SHGlyphNormal, ParallelToTheImplicitGradient)
{
  std::mt19937_64 random(151);
  int tested = 0, negative = 0;
  long double worstAngle = 0;
  for (int order = 0; order <= 12; order += 2)
    for (int variant = 0; variant < 4; ++variant)
      for (int i = 0; i < 50; ++i)
      {
        std::vector<double> b;
        if (variant < 3)
          b = randomCoefficients(order, kFamilies[variant], random);
        else
        {
          b.assign(shCoefficientCount(order), 0.0);
          b[shIndex(order, 0)] = 1.0; // pure zonal: negative belts
        }
        const long double radius = boundingRadiusReference(order, b.data());
        const AimedRay ray = aimAtBox(order, b, 3 * radius, random);
        const Query<double> q = query<double>(order, b, ray.origin, ray.direction);
        for (int j = 0; j < q.count; ++j)
        {
          const Vec3L pL = q.point(q.t[j]);
          const dvec3 p{ double(pL[0]), double(pL[1]), double(pL[2]) };
          const long double r = norm({ p.x, p.y, p.z });
          if (r < 0.01L * radius)
            continue;
          double value = 0;
          const dvec3 n = shGlyphNormal(order, b.data(), p, &value);
          auto phi = [&](const Vec3L& x)
          {
            const long double f = evaluateF(order, b.data(), x);
            return dot(x, x) - f * f;
          };
          Vec3L gradient{};
          const long double h = 2e-4L * r;
          for (int axis = 0; axis < 3; ++axis)
          {
            auto at = [&](long double s)
            {
              Vec3L x{ p.x, p.y, p.z };
              x[axis] += s;
              return phi(x);
            };
            gradient[axis] = (8 * (at(h) - at(-h)) - (at(2 * h) - at(-2 * h))) / (12 * h);
          }
          const Vec3L nL{ n.x, n.y, n.z };
          const Vec3L crossProduct{ nL[1] * gradient[2] - nL[2] * gradient[1],
            nL[2] * gradient[0] - nL[0] * gradient[2], nL[0] * gradient[1] - nL[1] * gradient[0] };
          const long double angle = std::atan2(norm(crossProduct), dot(nL, gradient));
          worstAngle = std::max(worstAngle, angle);
          const long double f = evaluateF(order, b.data(), { p.x, p.y, p.z });
          SCOPED_TRACE(describe(q) + "\n  hit " + std::to_string(j));
          EXPECT_LT(angle, 1e-6L);
          EXPECT_NEAR(value, double(f), double(1e-12L * radius));
          EXPECT_EQ(value < 0, f < 0);
          EXPECT_GT(dot(nL, { p.x, p.y, p.z }), 0);
          // Half the gradient, also in length (to the same relative accuracy).
          EXPECT_NEAR(double(norm(nL)), double(norm(gradient) / 2), double(1e-6L * norm(gradient)));
          ++tested;
          negative += f < 0;
        }
      }
  std::cout << "[ normals  ] " << tested << " hit points (" << negative
            << " on negative lobes), worst angle to the implicit gradient "
            << number(worstAngle) << " rad" << std::endl;
  RecordProperty("worst_angle", number(worstAngle));
  RecordProperty("negative_lobe_points", negative);
  EXPECT_GT(tested, 2000);
  EXPECT_GT(negative, 300);
}

// The normal at the pole of a sphere is p itself; at the centre it is zero (defined, no NaN).
TEST(SHGlyphNormal, SphereAndCentre)
{
  const std::vector<double> b{ 2.0 };
  const double r = 2 * double(y00());
  double value = 0;
  const dvec3 n = shGlyphNormal(0, b.data(), dvec3(0.3 * r, -0.4 * r, std::sqrt(0.75) * r), &value);
  EXPECT_NEAR(n.x, 0.3 * r, 1e-15);
  EXPECT_NEAR(n.y, -0.4 * r, 1e-15);
  EXPECT_NEAR(n.z, std::sqrt(0.75) * r, 1e-15);
  EXPECT_NEAR(value, r, 1e-15);
  const dvec3 zero = shGlyphNormal(0, b.data(), dvec3(0.0));
  EXPECT_EQ(zero, dvec3(0.0));
}
// insideSHGlyph agrees with the sign of |p| - |F(p / |p|)| away from the surface (points at 0.5
// and 1.5 times the glyph radius in their direction), negative lobes included.
TEST(SHGlyphInside, MatchesTheRadialFunction)
{
  std::mt19937_64 random(161);
  for (int order = 0; order <= 16; order += 2)
    for (Family family : kFamilies)
      for (int i = 0; i < 50; ++i)
      {
        const std::vector<double> b = randomCoefficients(order, family, random);
        const Vec3L w = randomUnitVector(random);
        const long double f = std::fabs(evaluateF(order, b.data(), w));
        for (long double scale : { 0.5L, 1.5L })
        {
          const Vec3L p = scaled(w, scale * f);
          const dvec3 point{ double(p[0]), double(p[1]), double(p[2]) };
          EXPECT_EQ(sightline::insideSHGlyph(order, b.data(), point), scale < 1)
            << "k = " << order << ", " << familyName(family) << ", |F| = " << double(f);
        }
      }
}
} // namespace
