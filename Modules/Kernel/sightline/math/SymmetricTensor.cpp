// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/math/SymmetricTensor.h"

#include "sightline/math/SphericalHarmonics.h"

#include "sightline/math/LinearSolve.h"
#include "sightline/math/SphereSampling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
namespace
{
void checkTensorOrder(int order, bool even)
{
  if (order < 0 || order > kMaxTensorOrder || (even && order % 2 != 0))
    throw std::invalid_argument("symmetric tensor order " + std::to_string(order) + " is not " +
      (even ? "an even number" : "a number") + " in [0, " + std::to_string(kMaxTensorOrder) + "]");
}

double factorial(int n)
{
  double f = 1.0;
  for (int i = 2; i <= n; ++i)
    f *= i;
  return f;
}

/// All monomials x^a y^b z^c of one direction, in the unique-component order.
void monomials(int order, double x, double y, double z, double* out)
{
  int index = 0;
  for (int a = order; a >= 0; --a)
    for (int b = order - a; b >= 0; --b)
    {
      const int c = order - a - b;
      out[index++] = std::pow(x, a) * std::pow(y, b) * std::pow(z, c);
    }
}
/// Position of (a, b, c) in the unique order: the groups of larger a first, then b descending.
int uniqueIndex(int order, int a, int b)
{
  int index = 0;
  for (int larger = order; larger > a; --larger)
    index += order - larger + 1;
  return index + order - a - b;
}
} // namespace

std::array<int, 3> symmetricTensorExponents(int order, int index)
{
  checkTensorOrder(order, false);
  if (index < 0 || index >= symmetricTensorComponentCount(order))
    throw std::invalid_argument("symmetric tensor component " + std::to_string(index) +
      " does not exist at order " + std::to_string(order));
  for (int a = order; a >= 0; --a)
  {
    const int inThisA = order - a + 1;
    if (index < inThisA)
      return { a, order - a - index, index };
    index -= inThisA;
  }
  return { 0, 0, order }; // not reached
}

double symmetricTensorMultiplicity(int a, int b, int c)
{
  return factorial(a + b + c) / (factorial(a) * factorial(b) * factorial(c));
}

double evaluateSymmetricTensor(int order, const double* components, double x, double y, double z)
{
  checkTensorOrder(order, false);
  double sum = 0.0;
  int index = 0;
  for (int a = order; a >= 0; --a)
    for (int b = order - a; b >= 0; --b)
    {
      const int c = order - a - b;
      sum += symmetricTensorMultiplicity(a, b, c) * components[index++] * std::pow(x, a) *
        std::pow(y, b) * std::pow(z, c);
    }
  return sum;
}

std::vector<double> symmetricPartFromFull(int order, const double* full)
{
  checkTensorOrder(order, false);
  std::size_t size = 1;
  for (int i = 0; i < order; ++i)
    size *= 3;
  std::vector<double> unique(symmetricTensorComponentCount(order), 0.0);
  for (std::size_t i = 0; i < size; ++i)
  {
    int count[3] = { 0, 0, 0 };
    for (std::size_t rest = i, k = 0; k < std::size_t(order); ++k, rest /= 3)
      ++count[rest % 3];
    unique[uniqueIndex(order, count[0], count[1])] += full[i];
  }
  for (std::size_t index = 0; index < unique.size(); ++index)
  {
    const std::array<int, 3> e = symmetricTensorExponents(order, int(index));
    unique[index] /= symmetricTensorMultiplicity(e[0], e[1], e[2]);
  }
  return unique;
}

std::vector<double> stiffnessFromVoigt(const double* voigt)
{
  static const int pair[3][3] = { { 0, 5, 4 }, { 5, 1, 3 }, { 4, 3, 2 } };
  std::vector<double> full(81);
  for (int l = 0; l < 3; ++l)
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
          full[i + 3 * j + 9 * k + 27 * l] = voigt[6 * pair[i][j] + pair[k][l]];
  return full;
}

std::vector<double> symmetricTensorFromFull(int order, const double* full, double tolerance)
{
  checkTensorOrder(order, false);
  std::size_t size = 1;
  for (int i = 0; i < order; ++i)
    size *= 3;
  double largest = 0.0;
  for (std::size_t i = 0; i < size; ++i)
    largest = std::max(largest, std::abs(full[i]));
  // Each full entry's exponents (how many of its indices are 0, 1, 2) name its unique component.
  std::vector<double> unique(symmetricTensorComponentCount(order), 0.0);
  std::vector<bool> seen(unique.size(), false);
  for (std::size_t i = 0; i < size; ++i)
  {
    int count[3] = { 0, 0, 0 };
    for (std::size_t rest = i, k = 0; k < std::size_t(order); ++k, rest /= 3)
      ++count[rest % 3];
    const int index = uniqueIndex(order, count[0], count[1]);
    if (!seen[index])
    {
      unique[index] = full[i];
      seen[index] = true;
    }
    else if (std::abs(full[i] - unique[index]) > tolerance * largest)
      throw std::invalid_argument("the tensor is not symmetric: entry " + std::to_string(i) +
        " differs from an entry that permutes its indices by " +
        std::to_string(std::abs(full[i] - unique[index])));
  }
  return unique;
}

TensorToSH::TensorToSH(int order)
  : Order(order)
{
  checkTensorOrder(order, true);
  // Both bases span the same space on the sphere; least squares over more directions than
  // unknowns recovers the exact change of basis (to rounding), in either direction.
  const int count = symmetricTensorComponentCount(order);
  const int samples = 4 * count + 64;
  std::vector<double> tensor(std::size_t(samples) * count), sh(std::size_t(samples) * count);
  for (int s = 0; s < samples; ++s)
  {
    const dvec3 w = detail::fibonacciDirection(s, samples);
    const double x = w.x, y = w.y, z = w.z;
    double* t = tensor.data() + std::size_t(s) * count;
    monomials(order, x, y, z, t);
    for (int i = 0; i < count; ++i)
    {
      const std::array<int, 3> e = symmetricTensorExponents(order, i);
      t[i] *= symmetricTensorMultiplicity(e[0], e[1], e[2]);
    }
    evaluateSH<double>(order, x, y, z, sh.data() + std::size_t(s) * count);
  }
  // sh-coefficients X with Y X = M (M: the tensor's monomial columns), and the reverse.
  const std::vector<double> forwardT = detail::leastSquares(sh, tensor, samples, count, count);
  // The monomial columns differ in scale by the multiplicities (up to 34650 at order 12):
  // equilibrate them before the normal equations, which square the condition number.
  std::vector<double> scale(count, 0.0);
  for (int s = 0; s < samples; ++s)
    for (int i = 0; i < count; ++i)
      scale[i] += tensor[std::size_t(s) * count + i] * tensor[std::size_t(s) * count + i];
  for (double& v : scale)
    v = 1.0 / std::sqrt(v);
  for (int s = 0; s < samples; ++s)
    for (int i = 0; i < count; ++i)
      tensor[std::size_t(s) * count + i] *= scale[i];
  std::vector<double> backwardT = detail::leastSquares(tensor, sh, samples, count, count);
  for (int i = 0; i < count; ++i)
    for (int j = 0; j < count; ++j)
      backwardT[std::size_t(i) * count + j] *= scale[i];
  Forward = forwardT;             // row j (SH coefficient) x column i (tensor component)
  Backward = std::move(backwardT); // row i (tensor component) x column j (SH coefficient)
}

void TensorToSH::apply(const double* tensor, double* sh) const
{
  // T(w) = sum_i t_i m_i(w) and m_i = sum_j Forward[j][i] Y_j: sh_j = sum_i Forward[j][i] t_i.
  const int count = symmetricTensorComponentCount(Order);
  for (int j = 0; j < count; ++j)
  {
    double sum = 0.0;
    for (int i = 0; i < count; ++i)
      sum += Forward[std::size_t(j) * count + i] * tensor[i];
    sh[j] = sum;
  }
}

void TensorToSH::inverse(const double* sh, double* tensor) const
{
  const int count = symmetricTensorComponentCount(Order);
  for (int i = 0; i < count; ++i)
  {
    double sum = 0.0;
    for (int j = 0; j < count; ++j)
      sum += Backward[std::size_t(i) * count + j] * sh[j];
    tensor[i] = sum;
  }
}
} // namespace sightline

namespace sightline
{
namespace
{
/// 3^n: the entries of a full tensor of order n.
long long fullTensorEntryCount(int order)
{
  long long count = 1;
  for (int i = 0; i < order; ++i)
    count *= 3;
  return count;
}
} // namespace

TensorLayout guessTensorLayout(int components)
{
  if (components == 6)
    return TensorLayout::VTKSymmetric;
  if (components == 36)
    return TensorLayout::Voigt;
  if (tensorOrderInLayout(TensorLayout::Full, components) > 0)
    return TensorLayout::Full;
  return TensorLayout::SymmetricUnique;
}

int tensorOrderInLayout(TensorLayout layout, int components)
{
  switch (layout)
  {
    case TensorLayout::SymmetricUnique:
      for (int n = 0; n <= kMaxTensorOrder; n += 2)
        if (symmetricTensorComponentCount(n) == components)
          return n;
      return -1;
    case TensorLayout::Full:
      // Order 8 would be 6561 entries per point: not a layout anyone stores.
      for (int n = 2; n <= 6; n += 2)
        if (fullTensorEntryCount(n) == components)
          return n;
      return -1;
    case TensorLayout::VTKSymmetric:
      return components == 6 ? 2 : -1;
    case TensorLayout::Voigt:
      return components == 36 ? 4 : -1;
  }
  return -1;
}

void uniqueTensorComponents(TensorLayout layout, int order, const double* values, double* unique)
{
  switch (layout)
  {
    case TensorLayout::SymmetricUnique:
      std::copy(values, values + symmetricTensorComponentCount(order), unique);
      return;
    case TensorLayout::Full:
    {
      const std::vector<double> part = symmetricPartFromFull(order, values);
      std::copy(part.begin(), part.end(), unique);
      return;
    }
    case TensorLayout::VTKSymmetric: // XX, YY, ZZ, XY, YZ, XZ to xx, xy, xz, yy, yz, zz
    {
      const double xx = values[0], yy = values[1], zz = values[2];
      const double xy = values[3], yz = values[4], xz = values[5];
      unique[0] = xx;
      unique[1] = xy;
      unique[2] = xz;
      unique[3] = yy;
      unique[4] = yz;
      unique[5] = zz;
      return;
    }
    case TensorLayout::Voigt:
    {
      const std::vector<double> full = stiffnessFromVoigt(values);
      const std::vector<double> part = symmetricPartFromFull(4, full.data());
      std::copy(part.begin(), part.end(), unique);
      return;
    }
  }
}

void symmetricEigenDecomposition(const double unique[6], double values[3], dmat3& vectors)
{
  double a[3][3] = { { unique[0], unique[1], unique[2] }, { unique[1], unique[3], unique[4] },
    { unique[2], unique[4], unique[5] } };
  double v[3][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  for (int sweep = 0; sweep < 50; ++sweep)
  {
    const double offDiagonal = std::abs(a[0][1]) + std::abs(a[0][2]) + std::abs(a[1][2]);
    const double diagonal = std::abs(a[0][0]) + std::abs(a[1][1]) + std::abs(a[2][2]);
    if (offDiagonal <= 1e-300 || offDiagonal <= 1e-16 * diagonal)
      break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q)
      {
        if (a[p][q] == 0.0)
          continue;
        // The rotation in the (p, q) plane that zeroes a[p][q] (Golub & Van Loan, Alg. 8.4.1).
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k)
        {
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k)
        {
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k)
        {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  for (int i = 0; i < 3; ++i)
  {
    values[i] = a[i][i];
    vectors[i] = dvec3(v[0][i], v[1][i], v[2][i]); // GLM: vectors[i] is column i
  }
}
} // namespace sightline
