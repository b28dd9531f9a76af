// SPDX-License-Identifier: BSD-3-Clause
// Totally symmetric Cartesian tensors of even order n (3 x ... x 3, n indices) as glyph
// functions: T(w) = T_{i1..in} w_i1 ... w_in, a homogeneous polynomial of degree n. On the unit
// sphere these polynomials span exactly the even SH bands 0, 2, ..., n (Peters et al. 2023,
// Sec. 3.1), so a tensor glyph is an SH glyph: TensorToSH is the exact linear map between the
// two, and the SH kernel renders tensors (Hlawitschka et al., higher-order tensor glyphs).
//
// Unique components: one per monomial x^a y^b z^c with a + b + c = n, ordered by a descending,
// then b descending (order 2: xx, xy, xz, yy, yz, zz). A full tensor holds each unique value
// n! / (a! b! c!) times (Hlawitschka et al., Eq. 5).
#pragma once

#include "sightline/math/Math.h"

#include <array>
#include <vector>

namespace sightline
{
constexpr int kMaxTensorOrder = 12;

/// Number of unique components of a symmetric tensor of order n: (n + 1)(n + 2) / 2.
constexpr int symmetricTensorComponentCount(int order)
{
  return (order + 1) * (order + 2) / 2;
}

/// The exponents (a, b, c) of x, y, z of unique component `index` of an order-n tensor.
std::array<int, 3> symmetricTensorExponents(int order, int index);

/// How often unique component (a, b, c) occurs in the full 3^n tensor: n! / (a! b! c!).
double symmetricTensorMultiplicity(int a, int b, int c);

/// T(w) for unique components (any w; a unit w gives the glyph radius in that direction).
double evaluateSymmetricTensor(int order, const double* components, double x, double y, double z);

/// Unique components from a full tensor of 3^n values (index i1 + 3 i2 + 9 i3 + ..., any
/// consistent order: the tensor is symmetric). Throws std::invalid_argument when the full tensor
/// is not symmetric to within `tolerance` times its largest entry.
std::vector<double> symmetricTensorFromFull(int order, const double* full, double tolerance = 1e-6);

/// The totally symmetric part of any full tensor of 3^n values (the mean over index
/// permutations, as unique components). T(w) = full_{i1..in} w_i1 ... w_in depends on this part
/// only, so it is the glyph of a tensor with fewer symmetries, e.g. a stiffness tensor C_ijkl
/// (minor and major symmetry only: its glyph is the longitudinal modulus C_ijkl w_i w_j w_k w_l).
std::vector<double> symmetricPartFromFull(int order, const double* full);

/// The full 3x3x3x3 tensor (81 values, index i + 3 j + 9 k + 27 l) of a 6x6 Voigt matrix
/// (row-major, pairs ordered 11, 22, 33, 23, 13, 12), the way elastic constants are published.
std::vector<double> stiffnessFromVoigt(const double* voigt);

/// How the components of a tensor are stored in an array.
enum class TensorLayout
{
  /// symmetricTensorComponentCount(n) unique components in the order above (n = 2: FSL's).
  SymmetricUnique,
  /// All 3^n entries, index i1 + 3 i2 + 9 i3 + ...; drawn as the totally symmetric part.
  Full,
  /// VTK's six symmetric components XX, YY, ZZ, XY, YZ, XZ (vtkTensorGlyph's order).
  VTKSymmetric,
  /// A 6x6 Voigt stiffness matrix, row-major, pairs 11, 22, 33, 23, 13, 12 (order 4).
  Voigt,
};

/// The layout a component count most likely means: 6 VTK's symmetric tensor, 36 Voigt, 9, 81
/// and 729 full tensors, anything else unique components.
TensorLayout guessTensorLayout(int components);

/// The even order a tensor of `components` values in `layout` has, or -1 when the count
/// fits no order the glyphs draw (unique: orders 0..kMaxTensorOrder; full: 2, 4, 6).
int tensorOrderInLayout(TensorLayout layout, int components);

/// Unique components (symmetricTensorComponentCount(order) values) of a tensor of that order
/// given in `layout`; `values` holds the layout's components.
void uniqueTensorComponents(TensorLayout layout, int order, const double* values, double* unique);

/// Eigen-decomposition of the symmetric 3x3 matrix with unique components xx, xy, xz, yy,
/// yz, zz (cyclic Jacobi rotations): `values[i]` belongs to the unit eigenvector in column i
/// of `vectors`, in no particular order.
void symmetricEigenDecomposition(const double unique[6], double values[3], dmat3& vectors);

/// The exact linear map between the unique components of an even-order tensor and the
/// canonical SH coefficients of the same function on the sphere (bands 0..n), both ways.
class TensorToSH
{
public:
  /// Throws std::invalid_argument for an odd order or one outside [0, kMaxTensorOrder].
  explicit TensorToSH(int order);

  int order() const { return Order; }
  /// symmetricTensorComponentCount(order) tensor components to as many SH coefficients.
  void apply(const double* tensor, double* sh) const;
  /// The inverse: canonical SH coefficients (bands 0..order) to unique tensor components.
  void inverse(const double* sh, double* tensor) const;

private:
  int Order;
  std::vector<double> Forward; ///< count x count, row-major: sh = Forward tensor
  std::vector<double> Backward;
};
} // namespace sightline
