// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/math/SphericalHarmonics.h"

#include "sightline/math/LegendreTables.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

namespace sightline
{
namespace
{
using detail::kTableSize;
using detail::LegendreTables;

const LegendreTables& tables()
{
  return detail::legendreTables();
}

/// S[l][m] for all l <= order (odd l included: the recurrence passes through them).
template <class T>
void legendreTable(int order, T z, T (*S)[kTableSize + 2])
{
  const LegendreTables& t = tables();
  for (int m = 0; m <= order; ++m)
  {
    S[m][m] = T(t.start[m]);
    if (m + 1 <= order)
      S[m + 1][m] = T(std::sqrt(double(2 * m + 3))) * z * S[m][m];
    for (int l = m + 2; l <= order; ++l)
      S[l][m] = T(t.a[l][m]) * z * S[l - 1][m] - T(t.b[l][m]) * S[l - 2][m];
  }
  // Entries with m > l are zero; derivatives read up to m + 2.
  for (int l = 0; l <= order; ++l)
    for (int m = l + 1; m <= l + 2; ++m)
      S[l][m] = T(0);
}

/// Re and Im of (x + i y)^m for m = 0..order.
template <class T>
void azimuthalPowers(int order, T x, T y, T* A, T* B)
{
  A[0] = T(1);
  B[0] = T(0);
  for (int m = 1; m <= order; ++m)
  {
    A[m] = x * A[m - 1] - y * B[m - 1];
    B[m] = x * B[m - 1] + y * A[m - 1];
  }
}

/// Walks column m of the Legendre recurrence, S_l^m for l = m..order, keeping only the two
/// previous values, and calls visit(l, S_l^m) for the even bands (the only ones glyphs have).
template <class T, class Visit>
inline void forEachEvenBandOfColumn(int order, int m, T z, Visit&& visit)
{
  const LegendreTables& t = tables();
  T previous = T(t.start[m]); // S_m^m
  T current = previous;
  if (m % 2 == 0)
    visit(m, current);
  if (m + 1 <= order)
  {
    current = T(std::sqrt(double(2 * m + 3))) * z * previous;
    if ((m + 1) % 2 == 0)
      visit(m + 1, current);
  }
  for (int l = m + 2; l <= order; ++l)
  {
    const T next = T(t.a[l][m]) * z * current - T(t.b[l][m]) * previous;
    previous = current;
    current = next;
    if (l % 2 == 0)
      visit(l, current);
  }
}

void checkOrder(int order)
{
  if (order < 0 || order > kMaxSHOrder || order % 2 != 0)
    throw std::invalid_argument("spherical harmonics order " + std::to_string(order) +
      " is not an even number in [0, " + std::to_string(kMaxSHOrder) + "]");
}
} // namespace

int shOrderFromCount(std::size_t count)
{
  for (int order = 0; order <= kMaxSHOrder; order += 2)
    if (std::size_t(shCoefficientCount(order)) == count)
      return order;
  return -1;
}

SHConvention SHConvention::fromName(const std::string& name, bool legacy)
{
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
    [](unsigned char c) { return char(std::tolower(c)); });
  if (lower == "descoteaux07")
    return { SHBasis::Descoteaux07, legacy };
  if (lower == "tournier07")
    return { SHBasis::Tournier07, legacy };
  if (lower == "canonical")
    return { SHBasis::Canonical, false };
  throw std::invalid_argument("unknown spherical harmonics basis '" + name +
    "' (expected descoteaux07, tournier07 or canonical)");
}

std::string SHConvention::name() const
{
  switch (basis)
  {
    case SHBasis::Canonical:
      return "canonical";
    case SHBasis::Descoteaux07:
      return legacy ? "descoteaux07 (legacy)" : "descoteaux07";
    case SHBasis::Tournier07:
      return legacy ? "tournier07 (legacy)" : "tournier07";
  }
  return "unknown";
}

SHConversion SHConversion::toCanonical(const SHConvention& convention, int order)
{
  checkOrder(order);
  SHConversion conversion;
  const int count = shCoefficientCount(order);
  conversion.target.resize(count);
  conversion.factor.resize(count);
  const double sqrt2 = std::sqrt(2.0);
  for (int l = 0; l <= order; l += 2)
    for (int m = -l; m <= l; ++m)
    {
      const int j = shIndex(l, m);
      // Condon-Shortley phase that scipy's sph_harm (used by DIPY) carries on |m|.
      const double phase = (std::abs(m) % 2 == 1) ? -1.0 : 1.0;
      int target = j;
      double factor = 1.0;
      switch (convention.basis)
      {
        case SHBasis::Canonical:
          break;
        case SHBasis::Tournier07:
          // MRtrix3: sqrt(2) Re Y_l^m for m > 0, sqrt(2) Im Y_l^|m| for m < 0; MRtrix 0.2
          // (legacy) leaves out the sqrt(2). Y_l^m carries the Condon-Shortley phase here too
          // (MRtrix3's Legendre::Plm_sph negates odd m, as DIPY's scipy-based real_sh_tournier
          // does): MRtrix3's sh2amp and DIPY agree, and differ from the canonical basis by
          // (-1)^m (see Testing/Kernel/TestSphericalHarmonics.cpp).
          factor = (m != 0 && convention.legacy) ? phase / sqrt2 : phase;
          break;
        case SHBasis::Descoteaux07:
          // sqrt(2) Im Y_l^m for m > 0 (a sin term), sqrt(2) Re Y_l^m for m < 0 (a cos term);
          // DIPY's legacy variant uses Y_l^|m| for m < 0, which drops a (-1)^m.
          target = shIndex(l, -m);
          if (m > 0)
            factor = phase;
          else if (m < 0)
            factor = convention.legacy ? phase : 1.0;
          break;
      }
      conversion.target[j] = target;
      conversion.factor[j] = factor;
    }
  return conversion;
}

template <class T>
void evaluateSH(int order, T x, T y, T z, T* values)
{
  checkOrder(order);
  T S[kTableSize + 2][kTableSize + 2];
  T A[kTableSize], B[kTableSize];
  legendreTable(order, z, S);
  azimuthalPowers(order, x, y, A, B);
  for (int l = 0; l <= order; l += 2)
  {
    T* band = values + shIndex(l, 0);
    band[0] = S[l][0];
    for (int m = 1; m <= l; ++m)
    {
      band[m] = S[l][m] * A[m];
      band[-m] = S[l][m] * B[m];
    }
  }
}

template <class T>
void evaluateSHWithDerivatives(int order, T x, T y, T z, T* values, std::array<T, 3>* gradients,
  SymmetricMatrix3<T>* hessians)
{
  checkOrder(order);
  const LegendreTables& t = tables();
  T S[kTableSize + 2][kTableSize + 2];
  T A[kTableSize], B[kTableSize];
  legendreTable(order, z, S);
  azimuthalPowers(order, x, y, A, B);
  for (int l = 0; l <= order; l += 2)
  {
    for (int m = 0; m <= l; ++m)
    {
      // Y = S(z) C(x, y) with C = A_m (cos part) or B_m (sin part); (x + i y)^m gives
      // dA_m/dx = m A_{m-1}, dA_m/dy = -m B_{m-1}, dB_m/dx = m B_{m-1}, dB_m/dy = m A_{m-1}.
      const T s = S[l][m];
      const T ds = T(t.up[l][m]) * S[l][m + 1];
      const T dds = m + 1 <= l ? T(t.up[l][m]) * T(t.up[l][m + 1]) * S[l][m + 2] : T(0);
      const T mm = T(m);
      const T mm1 = T(m) * T(m - 1);
      for (int part = 0; part < (m == 0 ? 1 : 2); ++part)
      {
        const bool cosine = part == 0;
        const int j = shIndex(l, cosine ? m : -m);
        const T c = cosine ? A[m] : B[m];
        T cx = 0, cy = 0, cxx = 0, cxy = 0, cyy = 0;
        if (m >= 1)
        {
          cx = cosine ? mm * A[m - 1] : mm * B[m - 1];
          cy = cosine ? -mm * B[m - 1] : mm * A[m - 1];
        }
        if (m >= 2)
        {
          cxx = cosine ? mm1 * A[m - 2] : mm1 * B[m - 2];
          cxy = cosine ? -mm1 * B[m - 2] : mm1 * A[m - 2];
          cyy = -cxx;
        }
        values[j] = s * c;
        gradients[j] = { s * cx, s * cy, ds * c };
        if (hessians)
          hessians[j] = { s * cxx, s * cxy, ds * cx, s * cyy, ds * cy, dds * c };
      }
    }
  }
}

namespace
{
/// F and its gradient in one pass of the recurrences, without the basis arrays (what a
/// glyph's normal needs at every hit). Column m's coefficient weights w_m = sum_l b_lm S_l^m
/// give F = sum w_m C_m and, through dC_m/dx = m C_(m-1) and dC_m/dy, the x and y derivatives;
/// dS_l^(m-1)/dz = up S_l^m, so column m also gathers the z derivative of column m - 1.
template <class T>
SHFunctionValue<T> valueAndGradient(int order, const T* coefficients, T x, T y, T z)
{
  checkOrder(order);
  const LegendreTables& t = tables();
  SHFunctionValue<T> result;
  T A = T(1), B = T(0);                  // Re, Im of (x + i y)^m
  T previousA = T(0), previousB = T(0); // of (x + i y)^(m-1)
  for (int m = 0; m <= order; ++m)
  {
    if (m > 0)
    {
      previousA = A;
      previousB = B;
      A = x * previousA - y * previousB;
      B = x * previousB + y * previousA;
    }
    T weightA = T(0), weightB = T(0);   // column m's value weights
    T slopeA = T(0), slopeB = T(0);     // column m - 1's z-derivative weights
    forEachEvenBandOfColumn(order, m, z, [&](int l, T s)
    {
      weightA += coefficients[shIndex(l, m)] * s;
      if (m > 0)
      {
        weightB += coefficients[shIndex(l, -m)] * s;
        const T up = T(t.up[l][m - 1]);
        slopeA += coefficients[shIndex(l, m - 1)] * up * s;
        if (m > 1)
          slopeB += coefficients[shIndex(l, -(m - 1))] * up * s;
      }
    });
    result.value += weightA * A + weightB * B;
    if (m > 0)
    {
      const T mm = T(m);
      result.gradient[0] += mm * (weightA * previousA + weightB * previousB);
      result.gradient[1] += mm * (weightB * previousA - weightA * previousB);
      result.gradient[2] += slopeA * previousA + slopeB * previousB;
    }
  }
  return result;
}
} // namespace

template <class T>
SHFunctionValue<T> evaluateSHFunction(int order, const T* coefficients, T x, T y, T z,
  bool withHessian)
{
  if (!withHessian)
    return valueAndGradient(order, coefficients, x, y, z);
  const int count = shCoefficientCount(order);
  T values[shCoefficientCount(kMaxSHOrder)];
  std::array<T, 3> gradients[shCoefficientCount(kMaxSHOrder)];
  SymmetricMatrix3<T> hessians[shCoefficientCount(kMaxSHOrder)];
  evaluateSHWithDerivatives(order, x, y, z, values, gradients, withHessian ? hessians : nullptr);
  SHFunctionValue<T> result;
  for (int j = 0; j < count; ++j)
  {
    const T c = coefficients[j];
    result.value += c * values[j];
    for (int i = 0; i < 3; ++i)
      result.gradient[i] += c * gradients[j][i];
    if (withHessian)
      for (int i = 0; i < 6; ++i)
        result.hessian[i] += c * hessians[j][i];
  }
  return result;
}

template <class T>
T evaluateSHSum(int order, const T* coefficients, T x, T y, T z)
{
  // Walk m outwards, keeping only the two previous Legendre values of each column.
  T sum = T(0);
  T A = T(1), B = T(0);
  for (int m = 0; m <= order; ++m)
  {
    if (m > 0)
    {
      const T nextA = x * A - y * B;
      B = x * B + y * A;
      A = nextA;
    }
    // Accumulate the (cos, sin) coefficient pair weighted by S_l^m over even l >= m.
    T weightA = T(0), weightB = T(0);
    forEachEvenBandOfColumn(order, m, z, [&](int band, T s)
    {
      if (m == 0)
        weightA += coefficients[shIndex(band, 0)] * s;
      else
      {
        weightA += coefficients[shIndex(band, m)] * s;
        weightB += coefficients[shIndex(band, -m)] * s;
      }
    });
    sum += weightA * A + weightB * B;
  }
  return sum;
}

template void evaluateSH<float>(int, float, float, float, float*);
template void evaluateSH<double>(int, double, double, double, double*);
template void evaluateSHWithDerivatives<float>(
  int, float, float, float, float*, std::array<float, 3>*, SymmetricMatrix3<float>*);
template void evaluateSHWithDerivatives<double>(
  int, double, double, double, double*, std::array<double, 3>*, SymmetricMatrix3<double>*);
template SHFunctionValue<float> evaluateSHFunction<float>(int, const float*, float, float, float, bool);
template SHFunctionValue<double> evaluateSHFunction<double>(
  int, const double*, double, double, double, bool);
template float evaluateSHSum<float>(int, const float*, float, float, float);
template double evaluateSHSum<double>(int, const double*, double, double, double);
} // namespace sightline
