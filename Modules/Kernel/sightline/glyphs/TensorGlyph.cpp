// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/glyphs/TensorGlyph.h"

#include "sightline/math/SymmetricTensor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
namespace
{
// Enclosures are computed in round-to-nearest double; each is widened by this many units of
// its terms' magnitude, far above the rounding error of the few hundred operations involved
// (n <= 12: under 2^-44 relative), so "never rejects surface" holds without directed rounding.
constexpr double kRoundingSlack = 1e-12;

Interval operator*(const Interval& a, const Interval& b)
{
  const double p[4] = { a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi };
  return { std::min(std::min(p[0], p[1]), std::min(p[2], p[3])),
    std::max(std::max(p[0], p[1]), std::max(p[2], p[3])) };
}

/// x^k, tight: even powers of an interval around 0 start at 0.
Interval power(const Interval& x, int k)
{
  if (k == 0)
    return { 1.0, 1.0 };
  const double a = std::pow(x.lo, k), b = std::pow(x.hi, k);
  if (k % 2 == 1)
    return { a, b };
  if (x.lo >= 0.0)
    return { a, b };
  if (x.hi <= 0.0)
    return { b, a };
  return { 0.0, std::max(a, b) };
}

Interval absolute(const Interval& x)
{
  if (x.lo >= 0.0)
    return x;
  if (x.hi <= 0.0)
    return { -x.hi, -x.lo };
  return { 0.0, std::max(-x.lo, x.hi) };
}

/// An affine form c + l e + r u with the ray's noise symbol e and one accumulated error term
/// u (both in [-1, 1]); r >= 0.
struct Affine
{
  double c = 0.0;
  double l = 0.0;
  double r = 0.0;

  Interval range() const { return { c - std::abs(l) - r, c + std::abs(l) + r }; }
};

Affine operator+(const Affine& a, const Affine& b) { return { a.c + b.c, a.l + b.l, a.r + b.r }; }
Affine operator-(const Affine& a, const Affine& b) { return { a.c - b.c, a.l - b.l, a.r + b.r }; }
Affine operator*(double w, const Affine& a) { return { w * a.c, w * a.l, std::abs(w) * a.r }; }

Affine operator*(const Affine& a, const Affine& b)
{
  // (a.c + a.l e + a.r u)(b.c + b.l e + b.r v): e^2 in [0, 1] is centred, the rest goes to r.
  const double ll = a.l * b.l;
  return { a.c * b.c + 0.5 * ll, a.c * b.l + a.l * b.c,
    std::abs(a.c) * b.r + std::abs(b.c) * a.r + (std::abs(a.l) + a.r) * b.r + a.r * std::abs(b.l) +
      0.5 * std::abs(ll) };
}

/// s^m for s >= 0 and m >= 1 (convex, increasing) over the range of `s`, linearised by the
/// secant with the largest deviation as error (the Chebyshev approximation of a convex
/// function).
Affine convexPower(const Affine& s, double m)
{
  const Interval range = s.range();
  const double s0 = std::max(0.0, range.lo), s1 = std::max(s0, range.hi);
  const double h0 = std::pow(s0, m), h1 = std::pow(s1, m);
  if (!(s1 - s0 > 1e-14 * s1))
    return { 0.5 * (h0 + h1), 0.0, 0.5 * (h1 - h0) + kRoundingSlack * h1 };
  const double alpha = (h1 - h0) / (s1 - s0);
  // The secant lies above h; it is furthest above where h' = alpha.
  const double tangent = std::clamp(std::pow(alpha / m, 1.0 / (m - 1.0)), s0, s1);
  const double gap = std::max(0.0, h0 + alpha * (tangent - s0) - std::pow(tangent, m));
  const double beta = h0 - alpha * s0 - 0.5 * gap;
  return { alpha * s.c + beta, alpha * s.l, alpha * s.r + 0.5 * gap };
}

const TensorToSH& tensorMap(int order)
{
  // One exact map per even order, built once (thread-safe static initialisation).
  static const std::vector<TensorToSH> maps = []
  {
    std::vector<TensorToSH> all;
    for (int n = 0; n <= kMaxTensorOrder; n += 2)
      all.emplace_back(n);
    return all;
  }();
  return maps[order / 2];
}
} // namespace

CartesianGlyphFunction::CartesianGlyphFunction(int order, const double* components, double radius)
  : Order(order)
{
  if (order < 0 || order > kMaxTensorOrder || order % 2 != 0)
    throw std::invalid_argument("tensor glyph order " + std::to_string(order) +
      " is not an even number in [0, " + std::to_string(kMaxTensorOrder) + "]");
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw std::invalid_argument("tensor glyph radius must be positive and finite");
  const int count = symmetricTensorComponentCount(order);
  Weights.resize(count);
  Exponents.resize(count);
  for (int i = 0; i < count; ++i)
  {
    const std::array<int, 3> e = symmetricTensorExponents(order, i);
    Exponents[i] = { std::uint8_t(e[0]), std::uint8_t(e[1]), std::uint8_t(e[2]) };
    Weights[i] = symmetricTensorMultiplicity(e[0], e[1], e[2]) * components[i] / radius;
    WeightSum += std::abs(Weights[i]);
  }
}

CartesianGlyphFunction CartesianGlyphFunction::fromSH(int order, const double* coefficients, double radius)
{
  if (order < 0 || order > kMaxTensorOrder || order % 2 != 0)
    throw std::invalid_argument("the tensor glyph methods support even orders up to " +
      std::to_string(kMaxTensorOrder) + ", not " + std::to_string(order));
  std::vector<double> tensor(symmetricTensorComponentCount(order));
  tensorMap(order).inverse(coefficients, tensor.data());
  return CartesianGlyphFunction(order, tensor.data(), radius);
}

double CartesianGlyphFunction::tensor(const dvec3& p) const
{
  double xp[kMaxTensorOrder + 1], yp[kMaxTensorOrder + 1], zp[kMaxTensorOrder + 1];
  xp[0] = yp[0] = zp[0] = 1.0;
  for (int k = 1; k <= Order; ++k)
  {
    xp[k] = xp[k - 1] * p.x;
    yp[k] = yp[k - 1] * p.y;
    zp[k] = zp[k - 1] * p.z;
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < Weights.size(); ++i)
    sum += Weights[i] * xp[Exponents[i][0]] * yp[Exponents[i][1]] * zp[Exponents[i][2]];
  return sum;
}

double CartesianGlyphFunction::implicit(const dvec3& p, bool positiveOnly) const
{
  const double value = tensor(p);
  const double r2 = glm::dot(p, p);
  // |p|^(n+1) = (r^2)^(n/2) sqrt(r^2): n is even.
  double radial = std::sqrt(r2);
  for (int k = 0; k < Order / 2; ++k)
    radial *= r2;
  return (positiveOnly ? value : std::abs(value)) - radial;
}

Interval CartesianGlyphFunction::implicit(const Interval box[3], bool positiveOnly) const
{
  Interval xp[kMaxTensorOrder + 1], yp[kMaxTensorOrder + 1], zp[kMaxTensorOrder + 1];
  for (int k = 0; k <= Order; ++k)
  {
    xp[k] = power(box[0], k);
    yp[k] = power(box[1], k);
    zp[k] = power(box[2], k);
  }
  Interval value{ 0.0, 0.0 };
  for (std::size_t i = 0; i < Weights.size(); ++i)
  {
    const Interval m = xp[Exponents[i][0]] * yp[Exponents[i][1]] * zp[Exponents[i][2]];
    const double w = Weights[i];
    value.lo += w >= 0.0 ? w * m.lo : w * m.hi;
    value.hi += w >= 0.0 ? w * m.hi : w * m.lo;
  }
  if (!positiveOnly)
    value = absolute(value);
  const Interval r2 = power(box[0], 2);
  const double r2lo = r2.lo + power(box[1], 2).lo + power(box[2], 2).lo;
  const double r2hi = r2.hi + power(box[1], 2).hi + power(box[2], 2).hi;
  const double radialLo = std::pow(r2lo, 0.5 * (Order + 1));
  const double radialHi = std::pow(r2hi, 0.5 * (Order + 1));
  const double slack = kRoundingSlack * (WeightSum * std::pow(r2hi, 0.5 * Order) + radialHi);
  return { value.lo - radialHi - slack, value.hi - radialLo + slack };
}

Interval CartesianGlyphFunction::implicitAffine(const dvec3& center, const dvec3& half, bool positiveOnly) const
{
  Affine xp[kMaxTensorOrder + 1], yp[kMaxTensorOrder + 1], zp[kMaxTensorOrder + 1];
  const Affine x{ center.x, half.x, 0.0 }, y{ center.y, half.y, 0.0 }, z{ center.z, half.z, 0.0 };
  xp[0] = yp[0] = zp[0] = Affine{ 1.0, 0.0, 0.0 };
  for (int k = 1; k <= Order; ++k)
  {
    xp[k] = xp[k - 1] * x;
    yp[k] = yp[k - 1] * y;
    zp[k] = zp[k - 1] * z;
  }
  Affine value;
  for (std::size_t i = 0; i < Weights.size(); ++i)
    value = value + Weights[i] * (xp[Exponents[i][0]] * yp[Exponents[i][1]] * zp[Exponents[i][2]]);
  const Affine radial = convexPower(x * x + y * y + z * z, 0.5 * (Order + 1));
  const double reach = glm::length(glm::abs(center) + glm::abs(half));
  const double slack = kRoundingSlack * (WeightSum * std::pow(reach, Order) + std::pow(reach, Order + 1));
  Interval result;
  const Interval valueRange = value.range();
  if (positiveOnly || valueRange.lo >= 0.0)
    result = (value - radial).range();
  else if (valueRange.hi <= 0.0)
    result = ((-1.0) * value - radial).range();
  else
  {
    // |T| is not affine where T changes sign: combine the ranges.
    const Interval magnitude = absolute(valueRange);
    const Interval r = radial.range();
    result = { magnitude.lo - r.hi, magnitude.hi - r.lo };
  }
  return { result.lo - slack, result.hi + slack };
}

namespace
{
/// The ray's chord through the unit ball, clipped to [tmin, tmax]; false when empty.
bool unitBallChord(const dvec3& o, const dvec3& d, double& tmin, double& tmax, double radius = 1.0)
{
  const double b = glm::dot(o, d);
  const dvec3 closest = o - b * d; // cancellation-free distance of the centre from the line
  const double disc = radius * radius - glm::dot(closest, closest);
  if (!(disc >= 0.0))
    return false;
  const double h = std::sqrt(disc);
  tmin = std::max(tmin, -b - h);
  tmax = std::min(tmax, -b + h);
  return tmin <= tmax;
}
} // namespace

bool marchTensorGlyph(const CartesianGlyphFunction& glyph, const dvec3& o, const dvec3& d,
  double tmin, double tmax, const TensorMarchingOptions& options, bool positiveOnly, double& tHit)
{
  if (!unitBallChord(o, d, tmin, tmax))
    return false;
  const double coarse = options.stepSize;
  const double fine = options.stepSize * options.centreStepFactor;
  // The part of the ray inside the centre ball gets the fine steps.
  double c0 = tmax, c1 = tmax;
  if (fine < coarse)
  {
    double a = tmin, b = tmax;
    if (unitBallChord(o, d, a, b, options.centreRadius))
    {
      c0 = a;
      c1 = b;
    }
  }
  double ta = tmin;
  double fa = glyph.implicit(o + ta * d, positiveOnly);
  if (fa > 0.0)
  {
    tHit = ta; // starts inside (the glyph touches the bounding sphere, or tmin is inside)
    return true;
  }
  while (ta < tmax)
  {
    double tb;
    if (ta >= c0 && ta < c1)
      tb = ta + fine;
    else
    {
      tb = ta + coarse;
      if (ta < c0 && tb > c0)
        tb = c0;
    }
    tb = std::min(tb, tmax);
    double fb = glyph.implicit(o + tb * d, positiveOnly);
    if (fb > 0.0)
    {
      for (int i = 0; i < options.bisectionSteps; ++i)
      {
        const double tm = 0.5 * (ta + tb);
        const double fm = glyph.implicit(o + tm * d, positiveOnly);
        if (fm > 0.0)
        {
          tb = tm;
          fb = fm;
        }
        else
        {
          ta = tm;
          fa = fm;
        }
      }
      tHit = options.linearInterpolation ? ta - fa * (tb - ta) / (fb - fa) : tb;
      return true;
    }
    ta = tb;
    fa = fb;
  }
  return false;
}

bool subdivideTensorGlyph(const CartesianGlyphFunction& glyph, const dvec3& o, const dvec3& d,
  double tmin, double tmax, const IntervalSubdivisionOptions& options, bool positiveOnly,
  double& tHit, SubdivisionStatistics* statistics)
{
  if (!unitBallChord(o, d, tmin, tmax))
    return false;
  // Depth-first, nearer half first, so the first unrejected short segment is the nearest hit.
  struct Segment
  {
    double a, b;
  };
  Segment stack[64];
  int top = 0;
  stack[top++] = { tmin, tmax };
  const double tolerance = std::max(options.tolerance, 1e-12);
  while (top > 0)
  {
    const Segment s = stack[--top];
    Interval value;
    if (options.arithmetic == EnclosureArithmetic::ReducedAffine)
    {
      const double mid = 0.5 * (s.a + s.b), half = 0.5 * (s.b - s.a);
      value = glyph.implicitAffine(o + mid * d, half * d, positiveOnly);
    }
    else
    {
      Interval box[3];
      for (int axis = 0; axis < 3; ++axis)
      {
        const double pa = o[axis] + s.a * d[axis], pb = o[axis] + s.b * d[axis];
        box[axis] = { std::min(pa, pb), std::max(pa, pb) };
      }
      value = glyph.implicit(box, positiveOnly);
    }
    if (statistics)
      ++statistics->evaluations;
    if (value.lo > 0.0 || value.hi < 0.0) // NaN never rejects
    {
      if (statistics)
        ++statistics->rejected;
      continue;
    }
    if (s.b - s.a <= tolerance || top >= 62)
    {
      tHit = 0.5 * (s.a + s.b);
      return true;
    }
    const double mid = 0.5 * (s.a + s.b);
    stack[top++] = { mid, s.b };
    stack[top++] = { s.a, mid };
  }
  return false;
}
} // namespace sightline
