// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/math/SHRotation.h"

#include "sightline/math/SphericalHarmonics.h"

#include "sightline/math/LinearSolve.h"
#include "sightline/math/SphereSampling.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
SHRotation::SHRotation(int order, const glm::dmat3& rotation)
  : Order(order)
{
  if (order < 0 || order > kMaxSHOrder || order % 2 != 0)
    throw std::invalid_argument("SH rotation: order " + std::to_string(order) +
      " is not an even number in [0, " + std::to_string(kMaxSHOrder) + "]");
  const glm::dmat3 shouldBeIdentity = glm::transpose(rotation) * rotation;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!(std::abs(shouldBeIdentity[i][j] - (i == j ? 1.0 : 0.0)) < 1e-6))
        throw std::invalid_argument("SH rotation: the matrix is not orthogonal (R^T R differs "
                                    "from the identity by more than 1e-6)");

  // Band by band, the rotated basis functions Y_lm(R^T w) lie in the span of the band's
  // Y_lm'(w); least squares over many directions gives the (exact) coefficients of that span.
  const int count = shCoefficientCount(order);
  const int samples = 4 * (order + 1) * (order + 1) + 64;
  std::vector<double> plain(std::size_t(samples) * count), turned(std::size_t(samples) * count);
  const glm::dmat3 inverse = glm::transpose(rotation);
  for (int s = 0; s < samples; ++s)
  {
    const dvec3 w = detail::fibonacciDirection(s, samples);
    const dvec3 v = inverse * w;
    evaluateSH<double>(order, w.x, w.y, w.z, plain.data() + std::size_t(s) * count);
    evaluateSH<double>(order, v.x, v.y, v.z, turned.data() + std::size_t(s) * count);
  }
  for (int l = 0; l <= order; l += 2)
  {
    const int n = 2 * l + 1, first = shIndex(l, -l);
    // Least squares A X = B with A = Y_l(w_s), B = Y_l(R^T w_s): column j of X holds the
    // coefficients of the turned Y_{l, first + j}.
    std::vector<double> a(std::size_t(samples) * n), b(std::size_t(samples) * n);
    for (int s = 0; s < samples; ++s)
      for (int i = 0; i < n; ++i)
      {
        a[std::size_t(s) * n + i] = plain[std::size_t(s) * count + first + i];
        b[std::size_t(s) * n + i] = turned[std::size_t(s) * count + first + i];
      }
    const std::vector<double> rhs = detail::leastSquares(a, b, samples, n, n);
    Blocks.insert(Blocks.end(), rhs.begin(), rhs.end());
  }
}

void SHRotation::apply(const double* coefficients, double* rotated) const
{
  // G = sum_j c_j Y_j(R^T w) = sum_j c_j sum_i X_ij Y_i(w): rotated_i = sum_j X_ij c_j.
  std::size_t block = 0;
  for (int l = 0; l <= Order; l += 2)
  {
    const int n = 2 * l + 1, first = shIndex(l, -l);
    const double* X = Blocks.data() + block;
    for (int i = 0; i < n; ++i)
    {
      double sum = 0.0;
      for (int j = 0; j < n; ++j)
        sum += X[i * n + j] * coefficients[first + j];
      rotated[first + i] = sum;
    }
    block += std::size_t(n) * n;
  }
}
} // namespace sightline
