// SPDX-License-Identifier: BSD-3-Clause
// Small dense linear algebra shared by the kernel's basis changes (internal header).
#pragma once

#include <cmath>
#include <stdexcept>
#include <vector>

namespace sightline
{
namespace detail
{
/// Solves M X = B in place of B for a symmetric positive definite n x n matrix M (row-major) by
/// Cholesky; B is n x columns, row-major. Throws std::runtime_error when M is not positive
/// definite (the sample directions do not determine the unknowns).
inline void solveSymmetric(std::vector<double> M, std::vector<double>& B, int n, int columns)
{
  for (int j = 0; j < n; ++j)
  {
    double d = M[j * n + j];
    for (int k = 0; k < j; ++k)
      d -= M[j * n + k] * M[j * n + k];
    if (!(d > 0.0))
      throw std::runtime_error("least squares: the samples do not determine the unknowns");
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
      double s = B[i * columns + c];
      for (int k = 0; k < i; ++k)
        s -= M[i * n + k] * B[k * columns + c];
      B[i * columns + c] = s / M[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) // L^T x = y
    {
      double s = B[i * columns + c];
      for (int k = i + 1; k < n; ++k)
        s -= M[k * n + i] * B[k * columns + c];
      B[i * columns + c] = s / M[i * n + i];
    }
  }
}

/// Least squares X minimising |A X - B| for A (rows x n) and B (rows x columns), both
/// row-major, through the normal equations; X is n x columns.
inline std::vector<double> leastSquares(
  const std::vector<double>& A, const std::vector<double>& B, int rows, int n, int columns)
{
  std::vector<double> normal(std::size_t(n) * n, 0.0), rhs(std::size_t(n) * columns, 0.0);
  for (int r = 0; r < rows; ++r)
  {
    const double* a = A.data() + std::size_t(r) * n;
    const double* b = B.data() + std::size_t(r) * columns;
    for (int i = 0; i < n; ++i)
    {
      for (int j = 0; j < n; ++j)
        normal[std::size_t(i) * n + j] += a[i] * a[j];
      for (int j = 0; j < columns; ++j)
        rhs[std::size_t(i) * columns + j] += a[i] * b[j];
    }
  }
  solveSymmetric(std::move(normal), rhs, n, columns);
  return rhs;
}
} // namespace detail
} // namespace sightline
