// SPDX-License-Identifier: BSD-3-Clause
// Spherical harmonics: the canonical basis, its derivatives and the four file conventions.
//
// SphericalHarmonicsReference.* compare against tables that make_sh_references.py writes before
// the tests run (CTest fixture "sh_references"), from software nobody here wrote:
//   - MRtrix3's sh2amp (its own basis: tournier07, legacy = false), lmax 2, 4, 8, 12, 16;
//   - DIPY's shipped pair func_coef.nii.gz / func_discrete.nii.gz on sphere_grad.txt
//     (MRtrix 0.2's basis: tournier07, legacy = true, as DIPY's own test reads them);
//   - DIPY's real_sh_descoteaux / real_sh_tournier, both legacy flags, lmax 2 to 16.
// Each case has the unit coefficient vectors (every basis function on its own) and random ones.
// Every reference must also reject the three other conventions, so that it can tell them apart.
//
// SphericalHarmonics.* need no external data: textbook closed forms, orthonormality by an exact
// quadrature, derivatives against finite differences that are exact for polynomials of the
// basis's degree, consistency of the evaluation entry points, float against double, and the
// small utilities.
#include "sightline/math/SphericalHarmonics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using sightline::evaluateSH;
using sightline::evaluateSHFunction;
using sightline::evaluateSHSum;
using sightline::evaluateSHWithDerivatives;
using sightline::kMaxSHOrder;
using sightline::SHBasis;
using sightline::SHConvention;
using sightline::SHConversion;
using sightline::shCoefficientCount;
using sightline::shIndex;
using sightline::shOrderFromCount;
using sightline::SymmetricMatrix3;

constexpr long double kPi = 3.141592653589793238462643383279502884L;
constexpr int kMaxCount = shCoefficientCount(kMaxSHOrder);

using Point = std::array<double, 3>;

/// (l, m) of coefficient j.
std::pair<int, int> degreeAndOrder(int j)
{
  int l = 0;
  while (shIndex(l, l) < j)
    l += 2;
  return { l, j - shIndex(l, 0) };
}

std::string describe(int j)
{
  const auto [l, m] = degreeAndOrder(j);
  return "(l=" + std::to_string(l) + ", m=" + std::to_string(m) + ")";
}

const std::vector<SHConvention>& allConventions()
{
  static const std::vector<SHConvention> conventions{
    { SHBasis::Descoteaux07, true },
    { SHBasis::Descoteaux07, false },
    { SHBasis::Tournier07, true },
    { SHBasis::Tournier07, false },
  };
  return conventions;
}

/// Seeded points: poles, axes, near-pole points, then random unit vectors.
std::vector<Point> unitPoints(unsigned seed, int randomCount)
{
  std::vector<Point> points{ { 0, 0, 1 }, { 0, 0, -1 }, { 1, 0, 0 }, { 0, -1, 0 },
    { 1e-4, -2e-4, 1 }, { 0.6, 0.8, 0 } };
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  for (int i = 0; i < randomCount; ++i)
    points.push_back({ normal(rng), normal(rng), normal(rng) });
  for (Point& p : points)
  {
    const long double r =
      std::sqrt((long double)p[0] * p[0] + (long double)p[1] * p[1] + (long double)p[2] * p[2]);
    for (double& c : p)
      c = double(c / r);
  }
  return points;
}

std::vector<double> randomCoefficients(int order, unsigned seed)
{
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<double> c(shCoefficientCount(order));
  for (double& v : c)
    v = normal(rng);
  return c;
}

// ------------------------------------------------------------------------------------------------
// Reference tables written by make_sh_references.py.

struct ReferenceCase
{
  std::string file, source, basis;
  bool legacy = false;
  int order = -1;
  std::vector<std::vector<double>> coefficients; // functions x count
  std::vector<Point> directions;
  std::vector<std::vector<double>> amplitudes; // functions x directions
};

std::string referencePath(const std::string& name)
{
  return std::string(SIGHTLINE_SH_REFERENCE_DIR) + "/" + name;
}

/// Reads a case file; returns an empty string or what is wrong with it.
std::string loadCase(const std::string& name, ReferenceCase& c)
{
  c.file = name;
  std::ifstream in(referencePath(name));
  if (!in)
    return "cannot open " + referencePath(name) +
      " (written by the fixture test SphericalHarmonics.MakeReferences)";
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#')
      lines.push_back(line);
  std::size_t i = 0;
  int functions = -1, directions = -1;
  auto readRows = [&](int rows, int columns, std::vector<std::vector<double>>& out) -> std::string
  {
    for (int r = 0; r < rows; ++r, ++i)
    {
      if (i >= lines.size())
        return "truncated";
      std::istringstream row(lines[i]);
      std::vector<double> values;
      for (double v; row >> v;)
        values.push_back(v);
      if (int(values.size()) != columns)
        return "row of " + std::to_string(values.size()) + " values, expected " +
          std::to_string(columns) + ": " + lines[i].substr(0, 80);
      out.push_back(std::move(values));
    }
    return "";
  };
  for (; i < lines.size() && lines[i] != "coefficients"; ++i)
  {
    std::istringstream header(lines[i]);
    std::string key;
    header >> key;
    if (key == "source")
      std::getline(header >> std::ws, c.source);
    else if (key == "basis")
      header >> c.basis;
    else if (key == "legacy")
    {
      int legacy = -1;
      header >> legacy;
      c.legacy = legacy == 1;
    }
    else if (key == "order")
      header >> c.order;
    else if (key == "functions")
      header >> functions;
    else if (key == "directions")
      header >> directions;
    else
      return "unknown header line: " + lines[i];
  }
  if (c.order < 0 || c.order > kMaxSHOrder || functions <= 0 || directions <= 0)
    return "incomplete header";
  ++i;
  std::string error = readRows(functions, shCoefficientCount(c.order), c.coefficients);
  if (!error.empty())
    return "coefficients: " + error;
  if (i >= lines.size() || lines[i] != "directions")
    return "missing 'directions'";
  ++i;
  std::vector<std::vector<double>> rows;
  error = readRows(directions, 3, rows);
  if (!error.empty())
    return "directions: " + error;
  for (const auto& row : rows)
    c.directions.push_back({ row[0], row[1], row[2] });
  if (i >= lines.size() || lines[i] != "amplitudes")
    return "missing 'amplitudes'";
  ++i;
  error = readRows(functions, directions, c.amplitudes);
  if (!error.empty())
    return "amplitudes: " + error;
  return "";
}

/// Largest error of one way of evaluating, relative to each function's largest |amplitude|.
struct CaseErrors
{
  double sumDouble = 0, basisDouble = 0, functionDouble = 0, sumFloat = 0;
  double worst() const { return std::max({ sumDouble, basisDouble, functionDouble, sumFloat }); }
};

/// Evaluates every function of the case with `convention` and compares with the reference.
/// With `failAbove` > 0, records a test failure for each comparison above it (double paths) or
/// above `failAboveFloat` (float path).
CaseErrors compareCase(const ReferenceCase& c, const SHConvention& convention,
  double failAbove = 0, double failAboveFloat = 0)
{
  CaseErrors errors;
  const int n = shCoefficientCount(c.order);
  const SHConversion conversion = SHConversion::toCanonical(convention, c.order);
  std::vector<double> canonical(n), basis(n);
  std::vector<float> coefficientsFloat(n), canonicalFloat(n);
  int failures = 0;
  for (std::size_t f = 0; f < c.coefficients.size(); ++f)
  {
    const std::vector<double>& coefficients = c.coefficients[f];
    conversion.apply(coefficients.data(), canonical.data());
    for (int j = 0; j < n; ++j)
      coefficientsFloat[j] = float(coefficients[j]);
    conversion.apply(coefficientsFloat.data(), canonicalFloat.data());
    // Name the function: a unit vector is one basis function of the file's convention.
    int unit = -1, nonzero = 0;
    for (int j = 0; j < n; ++j)
      if (coefficients[j] != 0)
      {
        ++nonzero;
        unit = coefficients[j] == 1 ? j : -1;
      }
    const std::string name = nonzero == 1 && unit >= 0
      ? "basis function " + describe(unit)
      : "function " + std::to_string(f);
    double scale = 0;
    for (double a : c.amplitudes[f])
      scale = std::max(scale, std::fabs(a));
    scale = std::max(scale, 1e-300);
    for (std::size_t d = 0; d < c.directions.size(); ++d)
    {
      // The kernel evaluates polynomials meant for the unit sphere: normalise (DIPY's shipped
      // directions have 5 decimals; every reference treats directions as unit vectors).
      const Point& p = c.directions[d];
      const long double r =
        std::sqrt((long double)p[0] * p[0] + (long double)p[1] * p[1] + (long double)p[2] * p[2]);
      const double x = double(p[0] / r), y = double(p[1] / r), z = double(p[2] / r);
      const double reference = c.amplitudes[f][d];

      const double sum = evaluateSHSum(c.order, canonical.data(), x, y, z);
      evaluateSH(c.order, x, y, z, basis.data());
      long double dot = 0;
      for (int j = 0; j < n; ++j)
        dot += (long double)canonical[j] * basis[j];
      const double value =
        evaluateSHFunction(c.order, canonical.data(), x, y, z, false).value;
      const float sumFloat =
        evaluateSHSum(c.order, canonicalFloat.data(), float(x), float(y), float(z));

      const double eSum = std::fabs(sum - reference) / scale;
      const double eBasis = std::fabs(double(dot) - reference) / scale;
      const double eFunction = std::fabs(value - reference) / scale;
      const double eFloat = std::fabs(double(sumFloat) - reference) / scale;
      errors.sumDouble = std::max(errors.sumDouble, eSum);
      errors.basisDouble = std::max(errors.basisDouble, eBasis);
      errors.functionDouble = std::max(errors.functionDouble, eFunction);
      errors.sumFloat = std::max(errors.sumFloat, eFloat);
      if (failAbove > 0 &&
        (std::max({ eSum, eBasis, eFunction }) > failAbove || eFloat > failAboveFloat) &&
        ++failures <= 5)
        ADD_FAILURE() << c.file << " (" << c.source << "), " << convention.name() << ", "
                      << name << ", direction (" << p[0] << ", " << p[1] << ", " << p[2]
                      << "): reference " << reference << ", evaluateSHSum " << sum
                      << ", dot(evaluateSH) " << double(dot) << ", evaluateSHFunction " << value
                      << ", float " << sumFloat << " (relative errors " << eSum << ", "
                      << eBasis << ", " << eFunction << ", float " << eFloat << "; limits "
                      << failAbove << ", float " << failAboveFloat << ")";
    }
  }
  if (failures > 5)
    ADD_FAILURE() << c.file << ": " << failures - 5 << " more failures";
  return errors;
}

/// Loads `name`, checks that its convention matches the reference within the tolerances and
/// that every other convention is off by more than `rejectBelow`. Returns the worst errors.
CaseErrors checkReference(const std::string& name, const SHConvention& expected,
  double tolerance, double floatTolerance, double rejectBelow = 1e-2)
{
  ReferenceCase c;
  const std::string error = loadCase(name, c);
  if (!error.empty())
  {
    ADD_FAILURE() << name << ": " << error;
    return {};
  }
  EXPECT_EQ(SHConvention::fromName(c.basis, c.legacy).basis, expected.basis) << name;
  EXPECT_EQ(c.legacy, expected.legacy) << name;
  const CaseErrors errors = compareCase(c, expected, tolerance, floatTolerance);
  for (const SHConvention& other : allConventions())
  {
    if (other.basis == expected.basis && other.legacy == expected.legacy)
      continue;
    EXPECT_GT(compareCase(c, other).worst(), rejectBelow)
      << name << " cannot tell " << other.name() << " from " << expected.name();
  }
  return errors;
}

void report(const std::string& what, const CaseErrors& e)
{
  std::cout << "[ errors   ] " << what << ": relative max |error| evaluateSHSum " << e.sumDouble
            << ", dot(evaluateSH) " << e.basisDouble << ", evaluateSHFunction "
            << e.functionDouble << ", float evaluateSHSum " << e.sumFloat << std::endl;
}

void merge(CaseErrors& into, const CaseErrors& e)
{
  into.sumDouble = std::max(into.sumDouble, e.sumDouble);
  into.basisDouble = std::max(into.basisDouble, e.basisDouble);
  into.functionDouble = std::max(into.functionDouble, e.functionDouble);
  into.sumFloat = std::max(into.sumFloat, e.sumFloat);
}

// Tolerances, relative to the largest |amplitude| of each function over the case's directions.
// DIPY evaluates scipy's sph_harm in double, but from theta = arccos(z): near a pole the angle
// carries a rounding error of about eps / sin(theta), which reaches 1e-12 at the near-pole test
// directions (sin(theta) = 1.4e-3; an mpmath evaluation at 40 digits agrees with the kernel there,
// not with DIPY). With |z| <= 0.999 the two agree to 1.5e-14.
constexpr double kDipyTolerance = 1e-11;
// sh2amp computes in single precision (its float64 output differs by about 7e-8).
constexpr double kMRtrixTolerance = 1e-6;
// DIPY's func_coef/func_discrete are float32 and sphere_grad.txt has 5 decimals (|d| = 1 +- 4e-6).
constexpr double kFuncCoefTolerance = 5e-5;
// The float path against any of them. Rounding the direction to float alone moves a band-l
// function by up to eps_float * l(l+1)/2 * max|Y| (the slope of P_l at the poles): 8e-6 at l = 16.
constexpr double kFloatTolerance = 2e-5;

TEST(SphericalHarmonicsReference, MRtrix3Sh2amp)
{
  // MRtrix3's basis is DIPY's tournier07 with legacy = false, Condon-Shortley phase included.
  for (int order : { 2, 4, 8, 12, 16 })
  {
    const std::string name = "mrtrix3_sh2amp_lmax" + std::to_string(order) + ".txt";
    report(name, checkReference(name, { SHBasis::Tournier07, false }, kMRtrixTolerance,
                   std::max(kMRtrixTolerance, kFloatTolerance)));
  }
}

TEST(SphericalHarmonicsReference, DipyFuncCoefOnSphereGrad)
{
  // dipy.data.mrtrix_spherical_functions: "coefficients associated with the mrtrix spherical
  // harmonic basis of order 8 ... obtained by using the dwi2SH command of mrtrix" (0.2), which
  // DIPY's test_real_sym_sh_mrtrix evaluates with real_sh_tournier(legacy=True).
  report("dipy_func_coef.txt", checkReference("dipy_func_coef.txt",
                                 { SHBasis::Tournier07, true }, kFuncCoefTolerance,
                                 kFuncCoefTolerance));
}

void checkDipyBasis(const std::string& basis, bool legacy)
{
  CaseErrors worst;
  for (int order = 2; order <= kMaxSHOrder; order += 2)
  {
    const std::string name = "dipy_" + basis + (legacy ? "_legacy" : "_nonlegacy") + "_lmax" +
      std::to_string(order) + ".txt";
    merge(worst, checkReference(name, SHConvention::fromName(basis, legacy), kDipyTolerance,
                   kFloatTolerance));
  }
  report("dipy real_sh " + basis + (legacy ? " legacy" : " non-legacy") + " lmax 2..16", worst);
}

TEST(SphericalHarmonicsReference, DipyDescoteaux07Legacy)
{
  checkDipyBasis("descoteaux07", true);
}
TEST(SphericalHarmonicsReference, DipyDescoteaux07NonLegacy)
{
  checkDipyBasis("descoteaux07", false);
}
TEST(SphericalHarmonicsReference, DipyTournier07Legacy)
{
  checkDipyBasis("tournier07", true);
}
TEST(SphericalHarmonicsReference, DipyTournier07NonLegacy)
{
  checkDipyBasis("tournier07", false);
}

// ------------------------------------------------------------------------------------------------
// Without external data.

/// Textbook real harmonics without the Condon-Shortley phase, cos(m phi) for m > 0 and
/// sin(|m| phi) for m < 0 (what the header documents for the canonical basis).
TEST(SphericalHarmonics, CanonicalBasisMatchesClosedForms)
{
  const long double pi = kPi;
  for (const Point& p : unitPoints(11, 40))
  {
    const long double x = p[0], y = p[1], z = p[2];
    double Y[kMaxCount];
    evaluateSH(kMaxSHOrder, p[0], p[1], p[2], Y);
    const long double expected[] = {
      0.5L / std::sqrt(pi),                                     // (0, 0)
      std::sqrt(15 / (4 * pi)) * x * y,                         // (2, -2)
      std::sqrt(15 / (4 * pi)) * y * z,                         // (2, -1)
      std::sqrt(5 / (16 * pi)) * (3 * z * z - 1),               // (2, 0)
      std::sqrt(15 / (4 * pi)) * x * z,                         // (2, 1)
      std::sqrt(15 / (16 * pi)) * (x * x - y * y),              // (2, 2)
      // l = 4, m = 0 and |m| = 4 (cos 4 phi and sin 4 phi written out).
      3 / (16 * std::sqrt(pi)) * (35 * z * z * z * z - 30 * z * z + 3),
      3 / 16.0L * std::sqrt(35 / pi) * (x * x * (x * x - 3 * y * y) - y * y * (3 * x * x - y * y)),
      3 / 4.0L * std::sqrt(35 / pi) * x * y * (x * x - y * y),
      // l = 4, |m| = 1.
      3 / 4.0L * std::sqrt(5 / (2 * pi)) * x * z * (7 * z * z - 3),
      3 / 4.0L * std::sqrt(5 / (2 * pi)) * y * z * (7 * z * z - 3),
    };
    const int index[] = { shIndex(0, 0), shIndex(2, -2), shIndex(2, -1), shIndex(2, 0),
      shIndex(2, 1), shIndex(2, 2), shIndex(4, 0), shIndex(4, 4), shIndex(4, -4),
      shIndex(4, 1), shIndex(4, -1) };
    for (std::size_t k = 0; k < std::size(index); ++k)
      EXPECT_NEAR(Y[index[k]], double(expected[k]), 1e-14)
        << describe(index[k]) << " at (" << p[0] << ", " << p[1] << ", " << p[2] << ")";
  }
  // Zonal harmonics at a pole and on the equator: P_l(-1) = 1 for even l,
  // P_l(0) = (-1)^(l/2) (l-1)!! / l!!.
  double pole[kMaxCount], equator[kMaxCount];
  evaluateSH(kMaxSHOrder, 0.0, 0.0, -1.0, pole);
  evaluateSH(kMaxSHOrder, 0.6, -0.8, 0.0, equator);
  for (int l = 0; l <= kMaxSHOrder; l += 2)
  {
    const long double norm = std::sqrt((2 * l + 1) / (4 * pi));
    long double p0 = 1;
    for (int i = 1; i < l; i += 2)
      p0 *= (long double)i / (i + 1);
    EXPECT_NEAR(pole[shIndex(l, 0)], double(norm), 1e-14) << "l=" << l;
    EXPECT_NEAR(equator[shIndex(l, 0)], double(norm * ((l / 2) % 2 ? -p0 : p0)), 1e-14)
      << "l=" << l;
    for (int m = 1; m <= l; ++m) // (1 - z^2)^(m/2) vanishes at the poles
    {
      EXPECT_EQ(pole[shIndex(l, m)], 0.0) << describe(shIndex(l, m));
      EXPECT_EQ(pole[shIndex(l, -m)], 0.0) << describe(shIndex(l, -m));
    }
  }
}

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n in long double).
void gaussLegendre(int n, std::vector<long double>& nodes, std::vector<long double>& weights)
{
  nodes.resize(n);
  weights.resize(n);
  for (int i = 0; i < n; ++i)
  {
    long double x = std::cos(kPi * (i + 0.75L) / (n + 0.5L));
    long double derivative = 0;
    for (int iteration = 0; iteration < 100; ++iteration)
    {
      long double p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k)
      {
        const long double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (x * p1 - p0) / (x * x - 1);
      const long double step = p1 / derivative;
      x -= step;
      if (std::fabs(step) < 1e-19L)
        break;
    }
    nodes[i] = x;
    weights[i] = 2 / ((1 - x * x) * derivative * derivative);
  }
}

/// The products Y_i Y_j (degree <= 32) integrate exactly with 20 Gauss-Legendre nodes in z
/// (exact to degree 39) times 40 uniform azimuths (exact for trigonometric degree < 40).
TEST(SphericalHarmonics, CanonicalBasisIsOrthonormal)
{
  std::vector<long double> nodes, weights;
  gaussLegendre(20, nodes, weights);
  long double weightSum = 0;
  for (long double w : weights)
    weightSum += w;
  ASSERT_NEAR(double(weightSum), 2.0, 1e-15);
  const int azimuths = 40;
  std::vector<long double> gram(kMaxCount * kMaxCount, 0.0L);
  double Y[kMaxCount];
  for (std::size_t i = 0; i < nodes.size(); ++i)
    for (int k = 0; k < azimuths; ++k)
    {
      const long double phi = 2 * kPi * k / azimuths, z = nodes[i];
      const long double s = std::sqrt(1 - z * z);
      evaluateSH(kMaxSHOrder, double(s * std::cos(phi)), double(s * std::sin(phi)), double(z), Y);
      const long double w = weights[i] * 2 * kPi / azimuths;
      for (int a = 0; a < kMaxCount; ++a)
        for (int b = 0; b <= a; ++b)
          gram[a * kMaxCount + b] += w * Y[a] * Y[b];
    }
  double worst = 0;
  for (int a = 0; a < kMaxCount; ++a)
    for (int b = 0; b <= a; ++b)
    {
      const double error = std::fabs(double(gram[a * kMaxCount + b]) - (a == b ? 1.0 : 0.0));
      worst = std::max(worst, error);
      EXPECT_LT(error, 1e-13) << "<Y" << describe(a) << ", Y" << describe(b) << ">";
    }
  std::cout << "[ errors   ] max |<Y_i, Y_j> - delta_ij| up to l = 16: " << worst << std::endl;
}

/// Each convention is a signed permutation of the canonical basis, scaled by 1/sqrt(2) for
/// m != 0 in MRtrix 0.2's (tournier07 legacy); lower orders are prefixes of higher ones.
TEST(SphericalHarmonics, ConversionsAreSignedPermutations)
{
  std::vector<SHConvention> conventions = allConventions();
  conventions.push_back({ SHBasis::Canonical, false });
  for (const SHConvention& convention : conventions)
  {
    const SHConversion full = SHConversion::toCanonical(convention, kMaxSHOrder);
    for (int order = 0; order <= kMaxSHOrder; order += 2)
    {
      const SHConversion conversion = SHConversion::toCanonical(convention, order);
      const int n = shCoefficientCount(order);
      ASSERT_EQ(int(conversion.target.size()), n);
      ASSERT_EQ(int(conversion.factor.size()), n);
      std::vector<int> hits(n, 0);
      for (int j = 0; j < n; ++j)
      {
        const auto [l, m] = degreeAndOrder(j);
        const int target = conversion.target[j];
        ASSERT_GE(target, 0);
        ASSERT_LT(target, n);
        ++hits[target];
        // Same band, same |m|.
        const auto [tl, tm] = degreeAndOrder(target);
        EXPECT_EQ(tl, l) << convention.name() << " " << describe(j);
        EXPECT_EQ(std::abs(tm), std::abs(m)) << convention.name() << " " << describe(j);
        const double magnitude =
          convention.basis == SHBasis::Tournier07 && convention.legacy && m != 0
          ? 1 / std::sqrt(2.0)
          : 1.0;
        EXPECT_DOUBLE_EQ(std::fabs(conversion.factor[j]), magnitude)
          << convention.name() << " " << describe(j);
        EXPECT_EQ(conversion.target[j], full.target[j]);
        EXPECT_EQ(conversion.factor[j], full.factor[j]);
      }
      for (int t = 0; t < n; ++t)
        EXPECT_EQ(hits[t], 1) << convention.name() << " canonical " << describe(t);
    }
  }
}

/// Fornberg's weights for the derivatives 0..2 at 0 on the nodes -K..K (unit spacing): a
/// (2K+1)-point rule is exact for polynomials of degree <= 2K.
std::array<std::vector<long double>, 3> centralWeights(int K)
{
  const int n = 2 * K + 1;
  std::vector<long double> x(n);
  for (int i = 0; i < n; ++i)
    x[i] = i - K;
  std::vector<std::vector<std::vector<long double>>> c(
    3, std::vector<std::vector<long double>>(n, std::vector<long double>(n, 0)));
  c[0][0][0] = 1;
  long double c1 = 1;
  for (int i = 1; i < n; ++i)
  {
    long double c2 = 1;
    for (int j = 0; j < i; ++j)
    {
      const long double c3 = x[i] - x[j];
      c2 *= c3;
      for (int d = std::min(i, 2); d >= 0; --d)
      {
        const long double previous = d > 0 ? c[d - 1][i - 1][j] : 0;
        c[d][i][j] = (x[i] * c[d][i - 1][j] - d * previous) / c3;
      }
    }
    for (int d = std::min(i, 2); d >= 0; --d)
    {
      const long double previous = d > 0 ? c[d - 1][i - 1][i - 1] : 0;
      c[d][i][i] = c1 / c2 * (d * previous - x[i - 1] * c[d][i - 1][i - 1]);
    }
    c1 = c2;
  }
  std::array<std::vector<long double>, 3> weights;
  for (int d = 0; d < 3; ++d)
    weights[d] = c[d][n - 1];
  return weights;
}

/// Points on and off the unit sphere (the derivatives are those of the Cartesian polynomials).
std::vector<Point> derivativePoints()
{
  std::vector<Point> points = unitPoints(21, 12);
  points.push_back({ 0.3, -0.4, 0.5 });
  points.push_back({ -0.7, 0.2, 0.8 });
  points.push_back({ 0.0, 0.0, 0.0 });
  return points;
}

/// Directions for directional derivatives: u^T H u along x, y, z and the three diagonals
/// determines all six Hessian entries.
const std::array<Point, 7>& derivativeDirections()
{
  static const double s = 1 / std::sqrt(2.0);
  static const std::array<Point, 7> directions{ { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
    { s, s, 0 }, { s, 0, -s }, { 0, s, s }, { 0.48, -0.6, 0.64 } } };
  return directions;
}

// Along a line every basis function is a polynomial of degree <= l <= 16 in t, so the 17-point
// rule (K = 8) is exact and only rounding remains: about eps * sum |w_k| |Y(t_k)| / h^d.
constexpr int kStencilHalfWidth = 8;
constexpr double kStep = 1.0 / 64; // nodes within 1/8 of the point
// Relative to (l + 1)^d * max|Y| on the stencil, the natural size of a d-th derivative.
constexpr double kGradientTolerance = 1e-11;
constexpr double kHessianTolerance = 1e-9;

TEST(SphericalHarmonics, DerivativesMatchExactFiniteDifferences)
{
  const auto weights = centralWeights(kStencilHalfWidth);
  // The rule itself: exact on t^k, k <= 16.
  for (int k = 0; k <= 2 * kStencilHalfWidth; ++k)
    for (int d = 1; d <= 2; ++d)
    {
      long double sum = 0, magnitude = 0;
      for (int i = -kStencilHalfWidth; i <= kStencilHalfWidth; ++i)
      {
        const long double term = weights[d][i + kStencilHalfWidth] * std::pow((long double)i, k);
        sum += term;
        magnitude += std::fabs(term);
      }
      const long double exact = k == d ? (d == 1 ? 1 : 2) : 0;
      ASSERT_NEAR(double(sum), double(exact), 1e-15 * double(magnitude))
        << "t^" << k << ", derivative " << d;
    }

  double worstGradient = 0, worstHessian = 0;
  for (int order = 0; order <= kMaxSHOrder; order += 2)
  {
    const int n = shCoefficientCount(order);
    std::vector<double> values(n), sample(n);
    std::vector<std::array<double, 3>> gradients(n);
    std::vector<SymmetricMatrix3<double>> hessians(n);
    for (const Point& p : derivativePoints())
    {
      evaluateSHWithDerivatives(order, p[0], p[1], p[2], values.data(), gradients.data(),
        hessians.data());
      for (const Point& u : derivativeDirections())
      {
        std::vector<long double> first(n, 0), second(n, 0), magnitude(n, 0);
        for (int i = -kStencilHalfWidth; i <= kStencilHalfWidth; ++i)
        {
          const double t = i * kStep;
          evaluateSH(order, p[0] + t * u[0], p[1] + t * u[1], p[2] + t * u[2], sample.data());
          for (int j = 0; j < n; ++j)
          {
            first[j] += weights[1][i + kStencilHalfWidth] * sample[j];
            second[j] += weights[2][i + kStencilHalfWidth] * sample[j];
            magnitude[j] = std::max(magnitude[j], (long double)std::fabs(sample[j]));
          }
        }
        for (int j = 0; j < n; ++j)
        {
          const int l = degreeAndOrder(j).first;
          const double fdFirst = double(first[j] / kStep);
          const double fdSecond = double(second[j] / (kStep * kStep));
          const auto& g = gradients[j];
          const auto& H = hessians[j]; // xx, xy, xz, yy, yz, zz
          const double analyticFirst = g[0] * u[0] + g[1] * u[1] + g[2] * u[2];
          const double analyticSecond = H[0] * u[0] * u[0] + H[3] * u[1] * u[1] +
            H[5] * u[2] * u[2] + 2 * (H[1] * u[0] * u[1] + H[2] * u[0] * u[2] + H[4] * u[1] * u[2]);
          const double scale1 = double(magnitude[j]) * (l + 1) + 1e-300;
          const double scale2 = double(magnitude[j]) * (l + 1) * (l + 1) + 1e-300;
          const double e1 = std::fabs(analyticFirst - fdFirst) / scale1;
          const double e2 = std::fabs(analyticSecond - fdSecond) / scale2;
          worstGradient = std::max(worstGradient, e1);
          worstHessian = std::max(worstHessian, e2);
          EXPECT_LT(e1, kGradientTolerance)
            << "order " << order << " " << describe(j) << " at (" << p[0] << ", " << p[1] << ", "
            << p[2] << ") along (" << u[0] << ", " << u[1] << ", " << u[2]
            << "): gradient . u = " << analyticFirst << ", finite differences " << fdFirst;
          EXPECT_LT(e2, kHessianTolerance)
            << "order " << order << " " << describe(j) << " at (" << p[0] << ", " << p[1] << ", "
            << p[2] << ") along (" << u[0] << ", " << u[1] << ", " << u[2]
            << "): u^T H u = " << analyticSecond << ", finite differences " << fdSecond;
        }
      }
    }
  }
  std::cout << "[ errors   ] derivatives vs 17-point finite differences, orders 0..16: gradient "
            << worstGradient << ", Hessian " << worstHessian
            << " (relative to (l+1)^d max|Y| on the stencil)" << std::endl;
}

/// evaluateSH, evaluateSHWithDerivatives (with and without Hessians), evaluateSHFunction and
/// evaluateSHSum agree: the sums are the coefficient-weighted sums of the basis.
template <class T>
void checkEntryPointsAgree(double tolerance)
{
  for (int order = 0; order <= kMaxSHOrder; order += 2)
  {
    const int n = shCoefficientCount(order);
    const std::vector<double> coefficientsDouble = randomCoefficients(order, 31 + order);
    std::vector<T> coefficients(coefficientsDouble.begin(), coefficientsDouble.end());
    std::vector<T> values(n), valuesOnly(n), valuesNoHessian(n);
    std::vector<std::array<T, 3>> gradients(n), gradientsNoHessian(n);
    std::vector<SymmetricMatrix3<T>> hessians(n);
    std::vector<Point> points = unitPoints(41 + order, 20);
    points.push_back({ 0.3, -0.4, 0.5 });
    points.push_back({ 1.1, 0.2, -0.3 });
    for (const Point& p : points)
    {
      const T x = T(p[0]), y = T(p[1]), z = T(p[2]);
      evaluateSH(order, x, y, z, valuesOnly.data());
      evaluateSHWithDerivatives(order, x, y, z, values.data(), gradients.data(), hessians.data());
      evaluateSHWithDerivatives(
        order, x, y, z, valuesNoHessian.data(), gradientsNoHessian.data());
      long double value = 0, magnitude = 0;
      std::array<long double, 3> gradient{}, gradientMagnitude{};
      std::array<long double, 6> hessian{}, hessianMagnitude{};
      for (int j = 0; j < n; ++j)
      {
        EXPECT_EQ(values[j], valuesOnly[j]) << "order " << order << " " << describe(j);
        EXPECT_EQ(valuesNoHessian[j], valuesOnly[j]) << "order " << order << " " << describe(j);
        for (int i = 0; i < 3; ++i)
          EXPECT_EQ(gradientsNoHessian[j][i], gradients[j][i]) << "order " << order;
        value += (long double)coefficients[j] * values[j];
        magnitude += std::fabs((long double)coefficients[j] * values[j]);
        for (int i = 0; i < 3; ++i)
        {
          gradient[i] += (long double)coefficients[j] * gradients[j][i];
          gradientMagnitude[i] += std::fabs((long double)coefficients[j] * gradients[j][i]);
        }
        for (int i = 0; i < 6; ++i)
        {
          hessian[i] += (long double)coefficients[j] * hessians[j][i];
          hessianMagnitude[i] += std::fabs((long double)coefficients[j] * hessians[j][i]);
        }
      }
      const std::string where = "order " + std::to_string(order) + " at (" +
        std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " + std::to_string(p[2]) + ")";
      const T sum = evaluateSHSum(order, coefficients.data(), x, y, z);
      EXPECT_NEAR(double(sum), double(value), tolerance * double(magnitude) + 1e-300)
        << "evaluateSHSum " << where;
      for (bool withHessian : { false, true })
      {
        const auto f = evaluateSHFunction(order, coefficients.data(), x, y, z, withHessian);
        EXPECT_NEAR(double(f.value), double(value), tolerance * double(magnitude) + 1e-300)
          << "evaluateSHFunction " << where;
        for (int i = 0; i < 3; ++i)
          EXPECT_NEAR(double(f.gradient[i]), double(gradient[i]),
            tolerance * double(gradientMagnitude[i]) + 1e-300)
            << "evaluateSHFunction gradient " << i << " " << where;
        for (int i = 0; i < 6; ++i)
          EXPECT_NEAR(double(f.hessian[i]), withHessian ? double(hessian[i]) : 0.0,
            tolerance * double(hessianMagnitude[i]) + 1e-300)
            << "evaluateSHFunction Hessian " << i << " " << where;
      }
    }
  }
}

TEST(SphericalHarmonics, EntryPointsAgreeDouble)
{
  checkEntryPointsAgree<double>(1e-13);
}

TEST(SphericalHarmonics, EntryPointsAgreeFloat)
{
  checkEntryPointsAgree<float>(1e-5);
}

/// Single precision against double at l = 12 and 16: basis values, derivatives and sums.
TEST(SphericalHarmonics, FloatMatchesDouble)
{
  // Relative to the largest d-th derivative of the band-l zonal harmonic, sqrt((2l+1)/(4 pi))
  // times P_l(1) = 1, P_l'(1) = l(l+1)/2, P_l''(1) = (l-1)l(l+1)(l+2)/8 (the same point in both
  // precisions, so only arithmetic differs), and to sum |c_j Y_j| for the sums: 1e-5 is about 170
  // float ulps, what 16 steps of the three-term recurrences cost (about 3e-6 seen).
  constexpr double tolerance = 1e-5;
  double worst[4] = { 0, 0, 0, 0 };
  for (int order : { 12, 16 })
  {
    const int n = shCoefficientCount(order);
    const std::vector<double> coefficients = randomCoefficients(order, 51 + order);
    const std::vector<float> coefficientsFloat(coefficients.begin(), coefficients.end());
    std::vector<double> vd(n);
    std::vector<float> vf(n);
    std::vector<std::array<double, 3>> gd(n);
    std::vector<std::array<float, 3>> gf(n);
    std::vector<SymmetricMatrix3<double>> hd(n);
    std::vector<SymmetricMatrix3<float>> hf(n);
    for (const Point& p : unitPoints(61 + order, 200))
    {
      const float x = float(p[0]), y = float(p[1]), z = float(p[2]);
      // Same point in both precisions.
      evaluateSHWithDerivatives(order, double(x), double(y), double(z), vd.data(), gd.data(),
        hd.data());
      evaluateSHWithDerivatives(order, x, y, z, vf.data(), gf.data(), hf.data());
      long double magnitude = 0;
      for (int j = 0; j < n; ++j)
      {
        const double l = degreeAndOrder(j).first;
        const double size = std::sqrt((2 * l + 1) / (4 * double(kPi)));
        const double size1 = size * std::max(1.0, l * (l + 1) / 2);
        const double size2 = size * std::max(1.0, (l - 1) * l * (l + 1) * (l + 2) / 8);
        const double e = std::fabs(double(vf[j]) - vd[j]) / size;
        worst[0] = std::max(worst[0], e);
        EXPECT_LT(e, tolerance) << "order " << order << " " << describe(j);
        for (int i = 0; i < 3; ++i)
        {
          const double e1 = std::fabs(double(gf[j][i]) - gd[j][i]) / size1;
          worst[1] = std::max(worst[1], e1);
          EXPECT_LT(e1, tolerance) << "gradient " << i << " order " << order << " " << describe(j);
        }
        for (int i = 0; i < 6; ++i)
        {
          const double e2 = std::fabs(double(hf[j][i]) - hd[j][i]) / size2;
          worst[2] = std::max(worst[2], e2);
          EXPECT_LT(e2, tolerance) << "Hessian " << i << " order " << order << " " << describe(j);
        }
        magnitude += std::fabs(coefficients[j] * vd[j]);
      }
      const double sumDouble = evaluateSHSum(order, coefficients.data(), double(x), double(y),
        double(z));
      const float sumFloat = evaluateSHSum(order, coefficientsFloat.data(), x, y, z);
      worst[3] = std::max(worst[3], std::fabs(double(sumFloat) - sumDouble) / double(magnitude));
      EXPECT_NEAR(double(sumFloat), sumDouble, tolerance * double(magnitude))
        << "evaluateSHSum order " << order;
    }
  }
  std::cout << "[ errors   ] float vs double, l = 12 and 16: values " << worst[0] << ", gradients "
            << worst[1] << ", Hessians " << worst[2] << ", evaluateSHSum " << worst[3] << std::endl;
}

TEST(SphericalHarmonics, OrderFromCount)
{
  for (std::size_t count = 0; count <= 400; ++count)
  {
    int expected = -1;
    for (int order = 0; order <= kMaxSHOrder; order += 2)
      if (std::size_t((order + 1) * (order + 2) / 2) == count)
        expected = order;
    EXPECT_EQ(shOrderFromCount(count), expected) << count << " coefficients";
  }
  EXPECT_EQ(shOrderFromCount(15), 4);
  EXPECT_EQ(shOrderFromCount(45), 8);
  EXPECT_EQ(shOrderFromCount(153), 16);
  EXPECT_EQ(shOrderFromCount(171), -1); // order 18: past kMaxSHOrder
  EXPECT_EQ(shOrderFromCount(std::numeric_limits<std::size_t>::max()), -1);
}

TEST(SphericalHarmonics, IndexLayout)
{
  // DIPY's and MRtrix3's order: bands one after another, m = -l..l inside a band.
  int j = 0;
  for (int l = 0; l <= kMaxSHOrder; l += 2)
    for (int m = -l; m <= l; ++m, ++j)
      EXPECT_EQ(shIndex(l, m), j) << "l=" << l << " m=" << m;
  EXPECT_EQ(j, shCoefficientCount(kMaxSHOrder));
  EXPECT_EQ(shCoefficientCount(0), 1);
  EXPECT_EQ(shCoefficientCount(8), 45);
  EXPECT_EQ(shCoefficientCount(16), 153);
}

TEST(SphericalHarmonics, ConventionNames)
{
  const SHConvention d = SHConvention::fromName("descoteaux07", false);
  EXPECT_EQ(d.basis, SHBasis::Descoteaux07);
  EXPECT_FALSE(d.legacy);
  const SHConvention t = SHConvention::fromName("Tournier07", true);
  EXPECT_EQ(t.basis, SHBasis::Tournier07);
  EXPECT_TRUE(t.legacy);
  EXPECT_EQ(SHConvention::fromName("DESCOTEAUX07", true).basis, SHBasis::Descoteaux07);
  EXPECT_EQ(SHConvention::fromName("canonical", true).basis, SHBasis::Canonical);
  EXPECT_NE(d.name(), SHConvention::fromName("descoteaux07", true).name());
  EXPECT_NE(t.name(), SHConvention::fromName("tournier07", false).name());

  for (const std::string name : { "mrtrix", "descoteaux", "tournier07 ", "", "dipy-basis" })
  {
    try
    {
      SHConvention::fromName(name, true);
      ADD_FAILURE() << "'" << name << "' was accepted";
    }
    catch (const std::invalid_argument& error)
    {
      EXPECT_NE(std::string(error.what()).find("'" + name + "'"), std::string::npos)
        << error.what();
    }
    catch (...)
    {
      ADD_FAILURE() << "'" << name << "' threw something other than std::invalid_argument";
    }
  }
}

TEST(SphericalHarmonics, RejectsInvalidOrders)
{
  double values[kMaxCount + 64];
  std::array<double, 3> gradients[kMaxCount + 64];
  for (int order : { -2, 1, 3, 15, kMaxSHOrder + 2 })
  {
    EXPECT_THROW(evaluateSH(order, 0.0, 0.0, 1.0, values), std::invalid_argument) << order;
    EXPECT_THROW(evaluateSHWithDerivatives(order, 0.0, 0.0, 1.0, values, gradients),
      std::invalid_argument)
      << order;
    EXPECT_THROW(SHConversion::toCanonical({ SHBasis::Tournier07, false }, order),
      std::invalid_argument)
      << order;
  }
}
} // namespace
