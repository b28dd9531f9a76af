// SPDX-License-Identifier: BSD-3-Clause
// Independent references for the SH glyph tests (TestSHGlyphIntersection.cpp,
// TestSHGlyphBounds.cpp, and glyph builders shared with TestSHGlyphSet.cpp and
// TestSHGlyphRendering.cpp): random coefficient families and a ray-glyph reference that never
// touches the kernel's polynomial path. The glyph function F itself is evaluated with the
// kernel's evaluateSHSum<double>, whose basis TestSphericalHarmonics.cpp verifies against
// MRtrix3 and DIPY; everything else (geometry, root bracketing, refinement, bounds) is written
// here in long double.
#pragma once

#include "sightline/glyphs/SHGlyph.h"
#include "sightline/math/SphericalHarmonics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace sightline_test
{
namespace glyph
{
constexpr long double kPi = 3.141592653589793238462643383279502884L;
/// Y_0^0 = 1 / (2 sqrt(pi)).
inline long double y00()
{
  return 0.5L / std::sqrt(kPi);
}

/// Canonical coefficients of a fibre-like ODF: `isotropic` (as a radius) plus, per fibre, a
/// delta along it smoothed by the heat kernel exp(-l(l+1)/sharpness). Not normalised.
inline std::vector<double> fibreLobeCoefficients(int order, const std::vector<sightline::dvec3>& fibres,
  double isotropic, double sharpness)
{
  const int count = sightline::shCoefficientCount(order);
  std::vector<double> b(count, 0.0), y(count);
  for (const sightline::dvec3& fibre : fibres)
  {
    const sightline::dvec3 u = glm::normalize(fibre);
    sightline::evaluateSH<double>(order, u.x, u.y, u.z, y.data());
    for (int l = 0; l <= order; l += 2)
      for (int m = -l; m <= l; ++m)
        b[sightline::shIndex(l, m)] +=
          std::exp(-l * (l + 1.0) / sharpness) * y[sightline::shIndex(l, m)];
  }
  b[0] += isotropic / double(y00());
  return b;
}

using Vec3L = std::array<long double, 3>;

inline long double dot(const Vec3L& a, const Vec3L& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline long double norm(const Vec3L& a)
{
  return std::sqrt(dot(a, a));
}
inline Vec3L scaled(const Vec3L& a, long double s)
{
  return { a[0] * s, a[1] * s, a[2] * s };
}
inline Vec3L add(const Vec3L& a, const Vec3L& b)
{
  return { a[0] + b[0], a[1] + b[1], a[2] + b[2] };
}

/// F(w) for a direction w (normalised here in long double), with the kernel's SH basis.
inline long double evaluateF(int order, const double* b, const Vec3L& w)
{
  const long double length = norm(w);
  return sightline::evaluateSHSum<double>(
    order, b, double(w[0] / length), double(w[1] / length), double(w[2] / length));
}

/// Signed distance-like residual |p| - |F(p / |p|)|: negative inside, zero on the surface.
inline long double surfaceResidual(int order, const double* b, const Vec3L& p)
{
  const long double r = norm(p);
  if (r == 0)
    return -std::fabs(evaluateF(order, b, { 0, 0, 1 })); // any direction: only the sign counts
  return r - std::fabs(evaluateF(order, b, p));
}

/// A rigorous bound on max |F|: by the addition theorem sum_m Y_lm(w)^2 = (2l + 1) / (4 pi),
/// so |sum_m b_lm Y_lm| <= |b_l| sqrt((2l + 1) / (4 pi)) (Cauchy-Schwarz), summed over bands.
/// Written here independently of shGlyphBoundingRadius, which the bounds test compares to it.
inline long double boundingRadiusReference(int order, const double* b)
{
  long double radius = 0;
  for (int l = 0; l <= order; l += 2)
  {
    long double norm2 = 0;
    for (int m = -l; m <= l; ++m)
      norm2 += (long double)b[sightline::shIndex(l, m)] * b[sightline::shIndex(l, m)];
    radius += std::sqrt(norm2 * (2 * l + 1) / (4 * kPi));
  }
  return radius;
}

inline Vec3L randomUnitVector(std::mt19937_64& random)
{
  std::normal_distribution<double> gaussian;
  Vec3L v;
  do
    v = { gaussian(random), gaussian(random), gaussian(random) };
  while (norm(v) < 1e-3L);
  return scaled(v, 1 / norm(v));
}

/// Coefficient families of the stress tests.
enum class Family
{
  /// Every coefficient uniform in [-1, 1] (the paper's validation, Section 4.2): wild shapes
  /// with negative lobes, zero cones through the centre and many intersections per ray.
  Uniform,
  /// b0 positive and of the order of the other coefficients' norm, the rest uniform in [-1, 1]:
  /// mostly positive blobs with bumps, occasionally small negative lobes.
  PositiveMean,
  /// ODF-like: one to three sharp fibre lobes (Gaussian-smoothed delta functions, the band k
  /// attenuated by e^-2) with 3 % noise; Gibbs ringing gives thin negative lobes at high k.
  Fibres,
};

inline const char* familyName(Family family)
{
  switch (family)
  {
    case Family::Uniform:
      return "uniform";
    case Family::PositiveMean:
      return "positive-mean";
    case Family::Fibres:
      return "fibres";
  }
  return "?";
}

inline std::vector<double> randomCoefficients(int order, Family family, std::mt19937_64& random)
{
  const int n = sightline::shCoefficientCount(order);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  std::vector<double> b(n);
  switch (family)
  {
    case Family::Uniform:
      for (double& x : b)
        x = unit(random);
      break;
    case Family::PositiveMean:
      for (double& x : b)
        x = unit(random);
      b[0] = (1.0 + fraction(random)) * std::sqrt((n - 1) / 3.0) + 0.5;
      break;
    case Family::Fibres:
    {
      std::vector<double> basis(n);
      const int fibres = 1 + int(random() % 3);
      const double sigma = order > 0 ? 2.0 / (order * (order + 1.0)) : 0.0;
      for (int f = 0; f < fibres; ++f)
      {
        const Vec3L mu = randomUnitVector(random);
        sightline::evaluateSH<double>(order, double(mu[0]), double(mu[1]), double(mu[2]),
          basis.data());
        const double weight = 0.5 + 0.5 * fraction(random);
        for (int l = 0; l <= order; l += 2)
          for (int m = -l; m <= l; ++m)
          {
            const int j = sightline::shIndex(l, m);
            b[j] += weight * std::exp(-sigma * l * (l + 1)) * basis[j];
          }
      }
      const double noise = 0.03 * std::abs(b[0]);
      for (double& x : b)
        x += noise * unit(random);
      break;
    }
  }
  return b;
}

/// All parameters t in [tmin, tmax] where the ray o + t d (d normalised here: the kernel
/// assumes unit directions) crosses the glyph surface |p| = |F(p / |p|)|, sorted ascending.
///
/// The method shares nothing with the kernel's Algorithm 1 but the plane that contains the ray
/// and the centre. The ray is o_perp + u d with o_perp = eo e perpendicular to d, and the point
/// seen from the centre at angle theta from d is at u = eo cot(theta), |p| = eo / sin(theta).
/// Intersections are therefore the roots of
///   H(theta) = sigma G(theta) - eo,  G(theta) = F(cos(theta) d + sin(theta) e) sin(theta),
/// for sigma = +1 and -1. G is a trigonometric polynomial of degree n = k + 1 whatever the
/// distance eo, so uniform sampling in theta resolves it equally well for rays through the
/// centre and far from it, and Bernstein's inequality bounds its second derivative rigorously:
/// |G''| <= n^2 max|G| <= n^2 R with R the addition-theorem bound on |F|. On an interval of width
/// w this certifies that
///   - endpoints of equal sign with min |H| > n^2 R w^2 / 8 enclose no root (H stays within
///     n^2 R w^2 / 8 of its chord), and
///   - endpoints of opposite sign with |H(b) - H(a)| > n^2 R w^2 enclose exactly one (H' cannot
///     change sign).
/// Intervals that are not certified are resampled 16 times finer, recursively; certified sign
/// changes are refined by the Illinois method to long double precision (F itself carries the
/// double rounding of evaluateSHSum, ~1e-16 R). Only below a width of ~1e-9 rad, where the
/// uncertified excursion is < 1e-17 R, does an uncertified interval get a golden-section search
/// for a hidden extremum instead. To keep theta accurate near both ends, the half circle is split
/// at pi / 2 and the far half is solved with d reversed, so each half works with angles near 0.
/// A ray exactly through the centre (eo = 0) is answered analytically: t = -d.o +- |F(d)|
/// (the glyph is point symmetric). `grazing` marks roots found in intervals that needed
/// subdivision, i.e. roots of nearly tangent pairs or thin slivers.
struct ReferenceHits
{
  std::vector<long double> t;
  std::vector<bool> grazing;
  long double eo = 0; ///< distance of the ray's line from the centre
  long evaluations = 0; ///< F evaluations spent (for sizing the tests)
};

namespace detail
{
struct HalfSolver
{
  int order;
  const double* b;
  Vec3L dd, e;
  long double eo, sigma, keepBelow, secondDerivativeBound;
  std::vector<long double>* uAlong;
  std::vector<bool>* grazing;
  long* evaluations;

  long double H(long double theta) const
  {
    ++*evaluations;
    const Vec3L w = add(scaled(dd, std::cos(theta)), scaled(e, std::sin(theta)));
    return sigma * evaluateF(order, b, w) * std::sin(theta) - eo;
  }

  void keep(long double theta, bool subdivided) const
  {
    if (theta <= keepBelow)
    {
      uAlong->push_back(eo * std::cos(theta) / std::sin(theta));
      grazing->push_back(subdivided);
    }
  }

  /// Illinois (modified regula falsi) on a bracket with H(a), H(c) of opposite signs.
  long double refine(long double a, long double c, long double ha, long double hc) const
  {
    int side = 0;
    for (int iteration = 0; iteration < 200; ++iteration)
    {
      const long double scale = std::max(std::fabs(a), std::fabs(c));
      if (c - a <= 4 * std::numeric_limits<long double>::epsilon() * scale)
        break;
      long double x = (a * hc - c * ha) / (hc - ha);
      if (!(x > a && x < c))
        x = 0.5L * (a + c);
      const long double hx = H(x);
      if (hx == 0)
        return x;
      if ((hx < 0) == (ha < 0))
      {
        a = x;
        ha = hx;
        if (side == -1)
          hc *= 0.5L;
        side = -1;
      }
      else
      {
        c = x;
        hc = hx;
        if (side == 1)
          ha *= 0.5L;
        side = 1;
      }
    }
    return 0.5L * (a + c);
  }

  /// Last resort on a tiny uncertified interval with endpoints of equal sign: the extremum of
  /// H towards zero by golden-section search, and the pair of roots if it crosses.
  void hiddenPair(long double a, long double c, long double ha, long double hc) const
  {
    const long double inv = 0.6180339887498948482045868343656381L;
    const long double s = ha < 0 ? 1.0L : -1.0L; // maximise s H
    long double lo = a, hi = c;
    long double x1 = hi - inv * (hi - lo), x2 = lo + inv * (hi - lo);
    long double f1 = s * H(x1), f2 = s * H(x2);
    for (int iteration = 0; iteration < 60; ++iteration)
    {
      if (f1 < f2)
      {
        lo = x1;
        x1 = x2;
        f1 = f2;
        x2 = lo + inv * (hi - lo);
        f2 = s * H(x2);
      }
      else
      {
        hi = x2;
        x2 = x1;
        f2 = f1;
        x1 = hi - inv * (hi - lo);
        f1 = s * H(x1);
      }
    }
    const long double xm = f1 > f2 ? x1 : x2;
    const long double hm = H(xm);
    if ((hm >= 0) == (ha >= 0))
      return;
    keep(refine(a, xm, ha, hm), true);
    keep(refine(xm, c, hm, hc), true);
  }

  void scan(const std::vector<long double>& theta, const std::vector<long double>& h,
    int level) const
  {
    constexpr int kSubdivision = 16;
    constexpr int kMaxLevel = 6; // 16^6 finer than the base sampling: widths ~1e-10 rad
    for (std::size_t i = 0; i + 1 < theta.size(); ++i)
    {
      const long double a = theta[i], c = theta[i + 1], ha = h[i], hc = h[i + 1];
      const long double w = c - a;
      const long double excursion = secondDerivativeBound * w * w;
      const bool signChange = (ha >= 0) != (hc >= 0);
      const bool certified = signChange ? std::fabs(hc - ha) > excursion
                                        : std::min(std::fabs(ha), std::fabs(hc)) > excursion / 8;
      if (certified)
      {
        if (signChange)
          keep(refine(a, c, ha, hc), level > 0);
        continue;
      }
      if (level == kMaxLevel)
      {
        if (signChange)
          keep(refine(a, c, ha, hc), true);
        else
          hiddenPair(a, c, ha, hc);
        continue;
      }
      std::vector<long double> subTheta(kSubdivision + 1), subH(kSubdivision + 1);
      subTheta[0] = a;
      subH[0] = ha;
      subTheta[kSubdivision] = c;
      subH[kSubdivision] = hc;
      for (int j = 1; j < kSubdivision; ++j)
      {
        subTheta[j] = a + w * j / kSubdivision;
        subH[j] = H(subTheta[j]);
      }
      scan(subTheta, subH, level + 1);
    }
  }
};

/// One half of the circle: theta in [thetaLo, thetaHi] for the direction dd, the point
/// o_perp + eo cot(theta) dd. Roots with theta <= keepBelow are appended as u values along dd.
inline void solveHalf(int order, const double* b, const Vec3L& dd, const Vec3L& e, long double eo,
  long double radius, long double thetaLo, long double thetaHi, long double keepBelow, int samples,
  std::vector<long double>& uAlong, std::vector<bool>& grazing, long& evaluations)
{
  const long double n = order + 1;
  std::vector<long double> theta(samples + 1), g(samples + 1), h(samples + 1);
  for (int i = 0; i <= samples; ++i)
  {
    theta[i] = thetaLo + (thetaHi - thetaLo) * i / samples;
    const Vec3L w = add(scaled(dd, std::cos(theta[i])), scaled(e, std::sin(theta[i])));
    g[i] = evaluateF(order, b, w) * std::sin(theta[i]);
    ++evaluations;
  }
  for (const long double sigma : { 1.0L, -1.0L })
  {
    // 1.01: room for the double rounding of F in the bound.
    const HalfSolver solver{ order, b, dd, e, eo, sigma, keepBelow, 1.01L * n * n * radius,
      &uAlong, &grazing, &evaluations };
    for (int i = 0; i <= samples; ++i)
      h[i] = sigma * g[i] - eo;
    solver.scan(theta, h, 0);
  }
}
} // namespace detail

inline ReferenceHits referenceHits(int order, const double* b, const Vec3L& origin,
  const Vec3L& direction, long double tmin, long double tmax, int samplesPerBand = 16)
{
  ReferenceHits result;
  const Vec3L d = scaled(direction, 1 / norm(direction));
  const long double dO = dot(d, origin);
  const Vec3L perpendicular = add(origin, scaled(d, -dO));
  const long double eo = norm(perpendicular);
  result.eo = eo;
  const long double radius = boundingRadiusReference(order, b) * (1 + 1e-12L);
  std::vector<long double> t;
  std::vector<bool> grazing;
  if (eo == 0)
  {
    const long double f = std::fabs(evaluateF(order, b, d));
    if (f > 0)
    {
      t = { -f - dO, f - dO };
      grazing = { false, false };
    }
  }
  else if (eo < radius)
  {
    const Vec3L e = scaled(perpendicular, 1 / eo);
    const long double thetaLo = std::asin(eo / radius);
    const int samples = samplesPerBand * (order + 2);
    // Half circle split at pi/2; each half reaches a few samples past pi/2 and keeps only
    // theta <= pi/2 (< for the second half, so a root at exactly pi/2 is counted once).
    const long double half = kPi / 2;
    const long double overlap = 4 * (half - thetaLo) / samples;
    std::vector<long double> uForward, uBackward;
    std::vector<bool> gForward, gBackward;
    detail::solveHalf(order, b, d, e, eo, radius, thetaLo, half + overlap, half,
      samples / 2 + 4, uForward, gForward, result.evaluations);
    detail::solveHalf(order, b, scaled(d, -1), e, eo, radius, thetaLo, half + overlap,
      std::nextafter(half, 0.0L), samples / 2 + 4, uBackward, gBackward, result.evaluations);
    for (std::size_t i = 0; i < uForward.size(); ++i)
    {
      t.push_back(uForward[i] - dO);
      grazing.push_back(gForward[i]);
    }
    for (std::size_t i = 0; i < uBackward.size(); ++i)
    {
      t.push_back(-uBackward[i] - dO);
      grazing.push_back(gBackward[i]);
    }
  }
  std::vector<std::size_t> permutation(t.size());
  for (std::size_t i = 0; i < t.size(); ++i)
    permutation[i] = i;
  std::sort(permutation.begin(), permutation.end(),
    [&](std::size_t a, std::size_t c) { return t[a] < t[c]; });
  for (std::size_t i : permutation)
    if (t[i] >= tmin && t[i] <= tmax)
    {
      result.t.push_back(t[i]);
      result.grazing.push_back(grazing[i]);
    }
  return result;
}

/// How a kernel answer compares with the reference.
///
/// Roots closer together than `resolution` (a pair around a thin sliver or a nearly tangent
/// touch, e.g. the zero cones that meet at the centre of a glyph with negative lobes) are below
/// what a polynomial solver in floating point can separate: such a root is "unresolved", its
/// miss is counted apart from the real misses, and a kernel root within `resolution` of an
/// unresolved reference root is not spurious. With resolution = 0 every root counts.
struct HitComparison
{
  int references = 0;       ///< reference roots
  int misses = 0;           ///< resolved reference roots with no kernel root within tolerance
  int spurious = 0;         ///< kernel roots that match no reference root
  int unresolvedMisses = 0; ///< unresolved reference roots with no kernel root within tolerance
  long double worstError = 0; ///< largest |t_kernel - t_reference| over matched resolved roots
  long double worstMissSeparation = 0; ///< largest neighbour separation among (all) misses
  bool sorted = true;       ///< kernel roots ascending and inside [tmin, tmax]
  std::string detail;       ///< both lists, for failure messages

  bool clean() const { return misses == 0 && spurious == 0 && sorted; }
};

template <class T>
HitComparison compareHits(const ReferenceHits& reference, const T* t, int count,
  long double tolerance, long double tmin, long double tmax, long double resolution = 0)
{
  HitComparison c;
  const std::vector<long double>& r = reference.t;
  const std::size_t n = r.size();
  c.references = int(n);
  for (int i = 0; i < count; ++i)
    if (!(t[i] >= tmin && t[i] <= tmax) || (i > 0 && !(t[i] >= t[i - 1])))
      c.sorted = false;
  std::vector<long double> separation(n, INFINITY);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (i > 0)
      separation[i] = std::min(separation[i], r[i] - r[i - 1]);
    if (i + 1 < n)
      separation[i] = std::min(separation[i], r[i + 1] - r[i]);
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    long double best = INFINITY;
    for (int j = 0; j < count; ++j)
      best = std::min(best, std::fabs((long double)t[j] - r[i]));
    if (best <= tolerance)
    {
      if (!(separation[i] < resolution))
        c.worstError = std::max(c.worstError, best);
    }
    else
    {
      c.worstMissSeparation = std::max(c.worstMissSeparation, separation[i]);
      if (separation[i] < resolution)
        ++c.unresolvedMisses;
      else
        ++c.misses;
    }
  }
  for (int j = 0; j < count; ++j)
  {
    bool matched = false;
    for (std::size_t i = 0; i < n && !matched; ++i)
    {
      const long double distance = std::fabs((long double)t[j] - r[i]);
      matched = distance <= tolerance || (separation[i] < resolution && distance <= resolution);
    }
    if (!matched)
      ++c.spurious;
  }
  c.detail = "reference {";
  char buffer[64];
  for (std::size_t i = 0; i < n; ++i)
  {
    std::snprintf(buffer, sizeof buffer, " %.12Lg%s", r[i], reference.grazing[i] ? "(g)" : "");
    c.detail += buffer;
  }
  c.detail += " }, kernel {";
  for (int j = 0; j < count; ++j)
  {
    std::snprintf(buffer, sizeof buffer, " %.12Lg", (long double)t[j]);
    c.detail += buffer;
  }
  c.detail += " }";
  return c;
}
} // namespace glyph
} // namespace sightline_test
