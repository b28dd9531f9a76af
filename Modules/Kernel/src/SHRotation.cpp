#include "sightline/SHRotation.h"

#include "sightline/SphericalHarmonics.h"

#include <glm/gtc/constants.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
namespace
{
/// Solves the symmetric positive definite system M x = b in place (Cholesky), M n x n.
void solveSymmetric(std::vector<double> M, std::vector<double>& b, int n, int columns)
{
  for (int j = 0; j < n; ++j)
  {
    double d = M[j * n + j];
    for (int k = 0; k < j; ++k)
      d -= M[j * n + k] * M[j * n + k];
    if (!(d > 0.0))
      throw std::runtime_error("SH rotation: sample directions do not determine the band");
    M[j * n + j] = std::sqrt(d);
    for (int i = j + 1; i < n; ++i)
    {
      double s = M[i * n + j];
      for (int k = 0; k < j; ++k)
        s -= M[i * n + k] * M[j * n + k];
      M[i * n + j] = s / M[j * n + j];
    }
  }
  for (int c = 0; c < columns; ++c)
  {
    for (int i = 0; i < n; ++i) // L y = b
    {
      double s = b[i * columns + c];
      for (int k = 0; k < i; ++k)
        s -= M[i * n + k] * b[k * columns + c];
      b[i * columns + c] = s / M[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) // L^T x = y
    {
      double s = b[i * columns + c];
      for (int k = i + 1; k < n; ++k)
        s -= M[k * n + i] * b[k * columns + c];
      b[i * columns + c] = s / M[i * n + i];
    }
  }
}
} // namespace

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
  const double golden = glm::pi<double>() * (3.0 - std::sqrt(5.0));
  std::vector<double> plain(std::size_t(samples) * count), turned(std::size_t(samples) * count);
  const glm::dmat3 inverse = glm::transpose(rotation);
  for (int s = 0; s < samples; ++s)
  {
    const double z = 1.0 - (2.0 * s + 1.0) / samples;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const dvec3 w(r * std::cos(golden * s), r * std::sin(golden * s), z);
    const dvec3 v = inverse * w;
    evaluateSH<double>(order, w.x, w.y, w.z, plain.data() + std::size_t(s) * count);
    evaluateSH<double>(order, v.x, v.y, v.z, turned.data() + std::size_t(s) * count);
  }
  for (int l = 0; l <= order; l += 2)
  {
    const int n = 2 * l + 1, first = shIndex(l, -l);
    // Normal equations: (A^T A) X = A^T B with A = Y_l(w_s), B = Y_l(R^T w_s).
    std::vector<double> normal(std::size_t(n) * n, 0.0), rhs(std::size_t(n) * n, 0.0);
    for (int s = 0; s < samples; ++s)
    {
      const double* a = plain.data() + std::size_t(s) * count + first;
      const double* b = turned.data() + std::size_t(s) * count + first;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
        {
          normal[i * n + j] += a[i] * a[j];
          rhs[i * n + j] += a[i] * b[j];
        }
    }
    // Column j of X holds the coefficients of the turned Y_{l, first + j}.
    solveSymmetric(normal, rhs, n, n);
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
