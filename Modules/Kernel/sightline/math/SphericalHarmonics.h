// SPDX-License-Identifier: BSD-3-Clause
// Real, even-band spherical harmonics evaluated in Cartesian form (no trigonometric functions):
// Y_l^m(x, y, z) = N_lm * d^m/dz^m P_l(z) * Re/Im (x + i y)^|m|, a polynomial in x, y, z that
// equals the usual basis on the unit sphere. Value, gradient and Hessian of the polynomial come
// from the same recurrences, in float or double.
//
// The kernel works in one canonical basis; every convention users bring (DIPY's descoteaux07,
// MRtrix3's tournier07, each with its legacy variant) differs from it by a signed permutation
// with scale factors, so coefficients are converted once when a glyph set is built.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace sightline
{
/// Largest band the basis evaluates. Recurrences are fully normalised, so they stay accurate
/// well past the k = 12 that diffusion data use.
constexpr int kMaxSHOrder = 16;

/// Number of coefficients of the even bands 0, 2, ..., order: (order + 1)(order + 2) / 2.
constexpr int shCoefficientCount(int order)
{
  return (order + 1) * (order + 2) / 2;
}
/// The even order whose coefficient count is `count`, or -1 when there is none.
int shOrderFromCount(std::size_t count);
/// Position of (l, m) in a coefficient vector: l(l+1)/2 + m (DIPY's and MRtrix3's order).
constexpr int shIndex(int l, int m)
{
  return l * (l + 1) / 2 + m;
}

/// The SH conventions found in diffusion MRI files.
enum class SHBasis
{
  /// Canonical kernel basis: orthonormal, no Condon-Shortley phase, m > 0 holds cos(m phi),
  /// m < 0 holds sin(|m| phi). MRtrix3's basis is this one with the Condon-Shortley sign
  /// (-1)^m on odd m, i.e. Tournier07 with legacy=false.
  Canonical,
  /// Descoteaux et al. 2007 as DIPY defines it (`descoteaux07`); legacy=true is DIPY's default.
  Descoteaux07,
  /// Tournier et al. 2007 / MRtrix3 (`tournier07`); legacy=true is MRtrix 0.2 (no sqrt(2)).
  Tournier07,
};

struct SHConvention
{
  SHBasis basis = SHBasis::Descoteaux07;
  bool legacy = true;

  /// Parses "descoteaux07", "tournier07" or "canonical" (case-insensitive); throws
  /// std::invalid_argument naming the unknown basis.
  static SHConvention fromName(const std::string& name, bool legacy);
  std::string name() const;
};

/// How coefficients of a convention map to the canonical basis:
///   canonical[target[j]] += factor[j] * coefficient[j].
struct SHConversion
{
  std::vector<int> target;
  std::vector<double> factor;

  /// The conversion for all even bands up to `order`.
  static SHConversion toCanonical(const SHConvention& convention, int order);
  /// Applies the conversion; `canonical` has the same length as `coefficients`.
  template <class In, class Out>
  void apply(const In* coefficients, Out* canonical) const
  {
    for (std::size_t j = 0; j < target.size(); ++j)
      canonical[j] = Out(0);
    for (std::size_t j = 0; j < target.size(); ++j)
      canonical[target[j]] += Out(factor[j] * double(coefficients[j]));
  }
};

/// Symmetric 3x3 matrix stored as xx, xy, xz, yy, yz, zz.
template <class T>
using SymmetricMatrix3 = std::array<T, 6>;

/// Evaluates the canonical basis for bands 0, 2, ..., order at the point (x, y, z), normally
/// on the unit sphere. `values` receives shCoefficientCount(order) entries.
template <class T>
void evaluateSH(int order, T x, T y, T z, T* values);

/// The basis polynomials with their gradients (3 per function, d/dx d/dy d/dz) and, when
/// `hessians` is not null, their Hessians. Derivatives are those of the Cartesian polynomials,
/// not of a homogenised basis: they differ only in the radial direction, which the normal and
/// bounding-box formulas project away.
template <class T>
void evaluateSHWithDerivatives(int order, T x, T y, T z, T* values, std::array<T, 3>* gradients,
  SymmetricMatrix3<T>* hessians = nullptr);

/// The function sum_j coefficients[j] Y_j (canonical basis) and its derivatives at one point.
template <class T>
struct SHFunctionValue
{
  T value = T(0);
  std::array<T, 3> gradient{};
  SymmetricMatrix3<T> hessian{};
};
template <class T>
SHFunctionValue<T> evaluateSHFunction(int order, const T* coefficients, T x, T y, T z,
  bool withHessian);

/// Value only, without storing the basis (the hot path of the ray-glyph test).
template <class T>
T evaluateSHSum(int order, const T* coefficients, T x, T y, T z);
} // namespace sightline
