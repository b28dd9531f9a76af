// SPDX-License-Identifier: BSD-3-Clause
// Symmetric tensors as glyph functions: component order and multiplicities against a brute-force
// contraction of the full 3^n tensor; the tensor-to-SH map against pointwise evaluation (the SH
// side with the kernel's basis, verified against MRtrix3 and DIPY) for every even order up to
// 12, both ways; a second-order tensor against its quadratic form; bad input.
#include "sightline/math/SphericalHarmonics.h"
#include "sightline/math/SymmetricTensor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace
{
using sightline::symmetricTensorComponentCount;

/// A full 3^n symmetric tensor from unique components (brute force: every index tuple).
std::vector<double> fullTensor(int order, const std::vector<double>& unique)
{
  std::size_t size = 1;
  for (int i = 0; i < order; ++i)
    size *= 3;
  std::vector<double> full(size);
  for (std::size_t i = 0; i < size; ++i)
  {
    int count[3] = { 0, 0, 0 };
    for (std::size_t rest = i, k = 0; k < std::size_t(order); ++k, rest /= 3)
      ++count[rest % 3];
    for (int u = 0; u < symmetricTensorComponentCount(order); ++u)
    {
      const auto e = sightline::symmetricTensorExponents(order, u);
      if (e[0] == count[0] && e[1] == count[1] && e[2] == count[2])
        full[i] = unique[u];
    }
  }
  return full;
}

/// T(w) as the plain contraction T_{i1..in} w_i1 ... w_in over all 3^n entries.
double contract(int order, const std::vector<double>& full, const double w[3])
{
  double sum = 0.0;
  for (std::size_t i = 0; i < full.size(); ++i)
  {
    double product = full[i];
    for (std::size_t rest = i, k = 0; k < std::size_t(order); ++k, rest /= 3)
      product *= w[rest % 3];
    sum += product;
  }
  return sum;
}
} // namespace

TEST(SymmetricTensor, ComponentsAndMultiplicitiesMatchTheFullContraction)
{
  std::mt19937 random(12);
  std::normal_distribution<double> normal;
  for (int order = 1; order <= 8; ++order)
  {
    std::vector<double> unique(symmetricTensorComponentCount(order));
    for (double& v : unique)
      v = normal(random);
    const std::vector<double> full = fullTensor(order, unique);
    EXPECT_EQ(sightline::symmetricTensorFromFull(order, full.data()), unique) << "order " << order;
    double multiplicities = 0.0;
    for (int u = 0; u < symmetricTensorComponentCount(order); ++u)
    {
      const auto e = sightline::symmetricTensorExponents(order, u);
      EXPECT_EQ(e[0] + e[1] + e[2], order);
      multiplicities += sightline::symmetricTensorMultiplicity(e[0], e[1], e[2]);
    }
    EXPECT_DOUBLE_EQ(multiplicities, std::pow(3.0, order)) << "every entry counted once";
    for (int s = 0; s < 20; ++s)
    {
      const double w[3] = { normal(random), normal(random), normal(random) };
      EXPECT_NEAR(sightline::evaluateSymmetricTensor(order, unique.data(), w[0], w[1], w[2]),
        contract(order, full, w), 1e-10 * (1.0 + std::abs(contract(order, full, w))))
        << "order " << order;
    }
  }
  // Order 2 in the documented order xx, xy, xz, yy, yz, zz is the quadratic form w^T D w.
  const std::vector<double> d = { 3.0, 0.5, -0.2, 2.0, 0.1, 1.0 };
  const double w[3] = { 0.3, -0.4, 0.866 };
  const double quadratic = 3.0 * w[0] * w[0] + 2.0 * w[1] * w[1] + 1.0 * w[2] * w[2] +
    2.0 * (0.5 * w[0] * w[1] - 0.2 * w[0] * w[2] + 0.1 * w[1] * w[2]);
  EXPECT_NEAR(sightline::evaluateSymmetricTensor(2, d.data(), w[0], w[1], w[2]), quadratic, 1e-14);
}

TEST(SymmetricTensor, TensorToSHIsExactBothWaysUpToOrderTwelve)
{
  std::mt19937 random(2024);
  std::normal_distribution<double> normal;
  for (int order = 0; order <= sightline::kMaxTensorOrder; order += 2)
  {
    const int count = symmetricTensorComponentCount(order);
    ASSERT_EQ(count, sightline::shCoefficientCount(order));
    const sightline::TensorToSH map(order);
    std::vector<double> tensor(count), sh(count), back(count);
    for (double& v : tensor)
      v = normal(random);
    map.apply(tensor.data(), sh.data());
    double largest = 0.0;
    for (int s = 0; s < 200; ++s)
    {
      const sightline::dvec3 w =
        glm::normalize(sightline::dvec3(normal(random), normal(random), normal(random)));
      const double expected = sightline::evaluateSymmetricTensor(order, tensor.data(), w.x, w.y, w.z);
      largest = std::max(largest, std::abs(expected));
      EXPECT_NEAR(sightline::evaluateSHSum<double>(order, sh.data(), w.x, w.y, w.z), expected,
        1e-9 * (1.0 + std::abs(expected)))
        << "order " << order;
    }
    map.inverse(sh.data(), back.data());
    for (int i = 0; i < count; ++i)
      EXPECT_NEAR(back[i], tensor[i], 1e-8 * (1.0 + std::abs(tensor[i]))) << "order " << order;
  }
}

TEST(SymmetricTensor, RefusesBadInput)
{
  EXPECT_THROW(sightline::TensorToSH(3), std::invalid_argument);
  EXPECT_THROW(sightline::TensorToSH(14), std::invalid_argument);
  EXPECT_THROW(sightline::symmetricTensorExponents(2, 6), std::invalid_argument);
  std::vector<double> notSymmetric(9, 0.0);
  notSymmetric[1] = 1.0; // T_01 = 1 but T_10 = 0
  EXPECT_THROW(sightline::symmetricTensorFromFull(2, notSymmetric.data()), std::invalid_argument);
}

// The glyph of a full tensor that is not totally symmetric is that of its symmetric part:
// T(w) = full_{i1..in} w_i1 ... w_in is unchanged.
TEST(SymmetricTensor, SymmetricPartKeepsTheContraction)
{
  std::mt19937 rng(31);
  std::normal_distribution<double> normal;
  for (int order : { 2, 4, 6 })
  {
    std::size_t size = 1;
    for (int i = 0; i < order; ++i)
      size *= 3;
    std::vector<double> full(size);
    for (double& v : full)
      v = normal(rng);
    const std::vector<double> unique = sightline::symmetricPartFromFull(order, full.data());
    for (int k = 0; k < 20; ++k)
    {
      const double w[3] = { normal(rng), normal(rng), normal(rng) };
      double contraction = 0.0;
      for (std::size_t i = 0; i < size; ++i)
      {
        double term = full[i];
        for (std::size_t rest = i, j = 0; j < std::size_t(order); ++j, rest /= 3)
          term *= w[rest % 3];
        contraction += term;
      }
      EXPECT_NEAR(sightline::evaluateSymmetricTensor(order, unique.data(), w[0], w[1], w[2]),
        contraction, 1e-10 * (1.0 + std::abs(contraction)));
    }
  }
}

// Copper's elastic constants (Kittel): the Voigt matrix becomes C_ijkl with minor and major
// symmetry, and the longitudinal modulus is C11 along [100] and (C11 + 2 C12 + 4 C44) / 3 along
// [111].
TEST(SymmetricTensor, StiffnessFromVoigtGivesTheLongitudinalModulus)
{
  const double c11 = 168.4, c12 = 121.4, c44 = 75.4;
  double voigt[36] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      voigt[6 * i + j] = i == j ? c11 : c12;
  voigt[21] = voigt[28] = voigt[35] = c44;
  const std::vector<double> c = sightline::stiffnessFromVoigt(voigt);
  auto at = [&](int i, int j, int k, int l) { return c[i + 3 * j + 9 * k + 27 * l]; };
  EXPECT_EQ(at(0, 0, 0, 0), c11);
  EXPECT_EQ(at(0, 0, 1, 1), c12);
  EXPECT_EQ(at(0, 1, 0, 1), c44);
  EXPECT_EQ(at(0, 1, 1, 0), c44);
  EXPECT_EQ(at(1, 0, 0, 1), c44);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
        {
          EXPECT_EQ(at(i, j, k, l), at(j, i, k, l));
          EXPECT_EQ(at(i, j, k, l), at(k, l, i, j));
        }
  const std::vector<double> unique = sightline::symmetricPartFromFull(4, c.data());
  EXPECT_NEAR(sightline::evaluateSymmetricTensor(4, unique.data(), 1, 0, 0), c11, 1e-12);
  const double s = 1.0 / std::sqrt(3.0);
  EXPECT_NEAR(sightline::evaluateSymmetricTensor(4, unique.data(), s, s, s),
    (c11 + 2 * c12 + 4 * c44) / 3, 1e-10);
}

TEST(SymmetricTensor, LayoutsGiveTheSameUniqueComponents)
{
  EXPECT_EQ(sightline::guessTensorLayout(6), sightline::TensorLayout::VTKSymmetric);
  EXPECT_EQ(sightline::guessTensorLayout(36), sightline::TensorLayout::Voigt);
  EXPECT_EQ(sightline::guessTensorLayout(81), sightline::TensorLayout::Full);
  EXPECT_EQ(sightline::guessTensorLayout(15), sightline::TensorLayout::SymmetricUnique);
  EXPECT_EQ(sightline::tensorOrderInLayout(sightline::TensorLayout::SymmetricUnique, 91), 12);
  EXPECT_EQ(sightline::tensorOrderInLayout(sightline::TensorLayout::Full, 729), 6);
  EXPECT_EQ(sightline::tensorOrderInLayout(sightline::TensorLayout::VTKSymmetric, 15), -1);
  EXPECT_EQ(sightline::tensorOrderInLayout(sightline::TensorLayout::Voigt, 36), 4);

  const double unique[6] = { 1.0, 0.2, 0.3, 2.0, 0.4, 3.0 }; // xx, xy, xz, yy, yz, zz
  const double vtk[6] = { 1.0, 2.0, 3.0, 0.2, 0.4, 0.3 };     // XX, YY, ZZ, XY, YZ, XZ
  const double full[9] = { 1.0, 0.2, 0.3, 0.2, 2.0, 0.4, 0.3, 0.4, 3.0 };
  double fromVTK[6], fromFull[6];
  sightline::uniqueTensorComponents(sightline::TensorLayout::VTKSymmetric, 2, vtk, fromVTK);
  sightline::uniqueTensorComponents(sightline::TensorLayout::Full, 2, full, fromFull);
  for (int i = 0; i < 6; ++i)
  {
    EXPECT_DOUBLE_EQ(fromVTK[i], unique[i]);
    EXPECT_NEAR(fromFull[i], unique[i], 1e-15);
  }
}

TEST(SymmetricTensor, EigenDecompositionReconstructsTheMatrix)
{
  const double unique[6] = { 4.0, -1.0, 0.5, 3.0, 0.25, -2.0 };
  double values[3];
  sightline::dmat3 vectors;
  sightline::symmetricEigenDecomposition(unique, values, vectors);
  const sightline::dmat3 a(glm::dvec3(unique[0], unique[1], unique[2]),
    glm::dvec3(unique[1], unique[3], unique[4]), glm::dvec3(unique[2], unique[4], unique[5]));
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_NEAR(glm::length(vectors[i]), 1.0, 1e-12);
    const glm::dvec3 residual = a * vectors[i] - values[i] * vectors[i];
    EXPECT_LT(glm::length(residual), 1e-12);
  }
  EXPECT_NEAR(values[0] + values[1] + values[2], 5.0, 1e-12); // the trace
}
