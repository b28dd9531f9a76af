// SPDX-License-Identifier: BSD-3-Clause
// The samplers against the analytic integrals of the thesis' test fields (Chapter 6), for
// every class of ray: the step function chi_0.5 projected cell by cell on grids whose radial
// breakpoints include its steps, r^2 through the linear-in-r^2 sampler and r through the
// linear-in-r sampler (both exact for those fields), against sphere chords, the thesis' closed
// form 2/3 sqrt(1 - b^2) (1 + 2 b^2), and an independent graded Gauss-Legendre quadrature.
// All to 1e-9 relative. Then the thesis' benchmark grids (the step mid-cell) converge.
#include "sightline/volumes/SphericalFields.h"
#include "sightline/volumes/SphericalGrid.h"
#include "sightline/volumes/SphericalVolume.h"

#include "volumes/SphericalRayClasses.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

using namespace sightline;

namespace
{
using sightline::kPi;

// Non-uniform in every coordinate, outer radius 1, with 1/2 (chi_0.5's step) a breakpoint.
SphericalGrid unitBall()
{
  return { { 0.0, 0.2, 0.37, 0.5, 0.71, 0.9, 1.0 }, { 0.0, 0.35, 1.1, kPi / 2, 2.4, kPi },
    { 0.0, 0.8, 1.5, 2.9, 4.0, 5.1, 2.0 * kPi } };
}

// 10-point Gauss-Legendre on [a, b].
template <class F>
double gaussLegendre(const F& f, double a, double b)
{
  static const double x[5] = { 0.1488743389816312, 0.4333953941292472, 0.6794095682990244,
    0.8650633666889845, 0.9739065285171717 };
  static const double w[5] = { 0.2955242247147529, 0.2692667193099963, 0.2190863625159820,
    0.1494513491505806, 0.0666713443086881 };
  const double m = 0.5 * (a + b), h = 0.5 * (b - a);
  double sum = 0.0;
  for (int i = 0; i < 5; ++i)
    sum += w[i] * (f(m - h * x[i]) + f(m + h * x[i]));
  return sum * h;
}

// Integral of |o + t d| over the part of [t0, t1] inside the unit ball, by quadrature graded
// geometrically towards the closest approach (where r has its kink or strong curvature).
double referenceIntegralOfRadius(const dvec3& o, const dvec3& d, double t0, double t1)
{
  double enter, leave;
  if (!sphereChord(o, d, 1.0, t0, t1, enter, leave))
    return 0.0;
  const double a = glm::dot(d, d), tc = -glm::dot(o, d) / a;
  const auto r = [&](double t) { return glm::length(o + t * d); };
  double sum = 0.0;
  // Pieces [enter, tc] and [tc, leave] (clipped), each split at tc +- L 2^-m.
  for (int side : { -1, 1 })
  {
    const double from = side < 0 ? enter : std::max(enter, tc);
    const double to = side < 0 ? std::min(leave, tc) : leave;
    if (!(to > from))
      continue;
    const double near = side < 0 ? to : from, farEnd = side < 0 ? from : to;
    double length = std::abs(farEnd - near);
    double outer = farEnd;
    for (int m = 0; m < 60 && length > 0.0; ++m)
    {
      const double inner = near + side * 0.5 * length;
      sum += side < 0 ? gaussLegendre(r, outer, inner) : gaussLegendre(r, inner, outer);
      outer = inner;
      length *= 0.5;
    }
    sum += gaussLegendre(r, std::min(near, outer), std::max(near, outer));
  }
  return sum * std::sqrt(a);
}

struct Worst
{
  double value = 0.0;
  int rays = 0, hitting = 0;
  void add(double ours, double reference, double scale)
  {
    ++rays;
    if (reference != 0.0)
      ++hitting;
    value = std::max(value, std::abs(ours - reference) / std::max(std::abs(reference), scale));
  }
};
} // namespace

TEST(SphericalFields, ClosedFormsAgainstQuadrature)
{
  const RadiusSquaredField r2{ 1.0 };
  const RadialStepField chi = RadialStepField::chiHalf();
  // The thesis' x-aligned rays: 2/3 sqrt(1 - b^2)(1 + 2 b^2) for r^2; chords for chi.
  for (double b : { 0.0, 0.1, 0.3, 0.49, 0.5, 0.51, 0.8, 0.999, 1.0, 1.2 })
  {
    const double y = b * 0.6, z = b * 0.8;
    const dvec3 o(-3.0, y, z), d(1.0, 0.0, 0.0);
    const double closed = 2.0 / 3.0 * std::sqrt(std::max(0.0, 1.0 - b * b)) * (1.0 + 2.0 * b * b);
    EXPECT_NEAR(r2.rayIntegral(o, d, 0.0, 6.0), closed, 1e-14) << "b = " << b;
    const double chord = 2.0 * std::sqrt(std::max(0.0, 1.0 - b * b));
    const double inner = 2.0 * std::sqrt(std::max(0.0, 0.25 - b * b));
    EXPECT_NEAR(chi.rayIntegral(o, d, 0.0, 6.0), chord + inner, 1e-14) << "b = " << b;
  }
  // Random rays, scaled directions, ends anywhere: against quadrature of the field itself.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i)
  {
    const dvec3 o(2.0 * u(rng), 2.0 * u(rng), 2.0 * u(rng));
    const dvec3 d = 1.7 * dvec3(u(rng), u(rng), u(rng));
    const double t0 = u(rng), t1 = t0 + 1.5 + u(rng);
    double enter, leave;
    double reference = 0.0;
    if (sphereChord(o, d, 1.0, t0, t1, enter, leave))
      reference = gaussLegendre([&](double t) { const dvec3 x = o + t * d; return glm::dot(x, x); }, enter, leave) *
        glm::length(d);
    EXPECT_NEAR(r2.rayIntegral(o, d, t0, t1), reference, 1e-13);
  }
  EXPECT_THROW((RadialStepField{ { 0.5, 0.4 }, { 1.0, 2.0 } }.validate()), std::invalid_argument);
  EXPECT_THROW((RadialStepField{ { 0.5 }, { 1.0, 2.0 } }.validate()), std::invalid_argument);
}

// Every ray class: chi_0.5 by cell-constant projection, r^2 by the linear-in-r^2 sampler, r by
// the linear-in-r sampler, against the exact integrals.
TEST(SphericalSamplers, ExactForTheirFieldsOnEveryRayClass)
{
  const SphericalGrid grid = unitBall();
  const SphericalTraversal traversal(grid);
  const RadialStepField chi = RadialStepField::chiHalf();
  const RadiusSquaredField r2{ 1.0 };
  const std::vector<double> chiCells =
    sampleCellMidpoints(grid, [&](double r, double, double) { return chi(r); });
  const std::vector<double> r2Nodes = sampleRadialNodes(grid, [](double r, double, double) { return r * r; });
  const std::vector<double> rNodes = sampleRadialNodes(grid, [](double r, double, double) { return r; });
  Worst step, square, linear;
  std::vector<CellSegment> segments;
  sightline_test::forEachRayClass(grid,
    [&](const char* what, const dvec3& o, const dvec3& d, double t0, double t1, bool)
    {
      traversal.traverse(o, d, t0, t1, segments);
      const double dl = glm::length(d);
      const double ourStep = projectCellConstant(grid, chiCells, segments, dl);
      const double ourSquare = projectLinearInRadiusSquared(grid, r2Nodes, segments, o, d);
      const double ourLinear = projectLinearInRadius(grid, rNodes, segments, o, d);
      // Straight from the traversal: the same cells in the same order, so the same bits.
      EXPECT_EQ(projectCellConstant(traversal, chiCells, o, d, t0, t1), ourStep) << what;
      EXPECT_EQ(projectLinearInRadiusSquared(traversal, r2Nodes, o, d, t0, t1), ourSquare) << what;
      EXPECT_EQ(projectLinearInRadius(traversal, rNodes, o, d, t0, t1), ourLinear) << what;
      const double exactStep = chi.rayIntegral(o, d, t0, t1);
      const double exactSquare = r2.rayIntegral(o, d, t0, t1);
      const double exactLinear = referenceIntegralOfRadius(o, d, t0, t1);
      // Relative to the integral, or to the field's size times the ray's span in the ball
      // (1e-300 floors rays that miss).
      step.add(ourStep, exactStep, 1e-300);
      square.add(ourSquare, exactSquare, 1e-300);
      linear.add(ourLinear, exactLinear, 1e-300);
      EXPECT_LE(std::abs(ourStep - exactStep), 1e-9 * std::abs(exactStep) + 1e-300) << what << ": chi " << ourStep << " vs " << exactStep;
      EXPECT_LE(std::abs(ourSquare - exactSquare), 1e-9 * std::abs(exactSquare) + 1e-300) << what << ": r^2 " << ourSquare << " vs " << exactSquare;
      EXPECT_LE(std::abs(ourLinear - exactLinear), 1e-9 * std::abs(exactLinear) + 1e-300) << what << ": r " << ourLinear << " vs " << exactLinear;
    });
  std::printf("%d rays (%d through the ball): worst relative error chi_0.5 %.2e, r^2 %.2e, r %.2e\n",
    step.rays, step.hitting, step.value, square.value, linear.value);
  EXPECT_GT(step.hitting, step.rays / 4);
}

// The thesis' benchmark grids: N uniform breakpoints per axis, so chi_0.5's step lies inside a
// cell. The projection error then falls as the grid is refined (first order in the cell size).
TEST(SphericalSamplers, ThesisGridsConverge)
{
  const RadialStepField chi = RadialStepField::chiHalf();
  double previous = 1e300;
  for (int n : { 8, 16, 32, 64 })
  {
    SphericalGrid grid;
    for (int i = 0; i < n; ++i)
    {
      grid.radius.push_back(double(i) / (n - 1));
      grid.polar.push_back(kPi * i / (n - 1));
      grid.azimuth.push_back(2.0 * kPi * i / (n - 1));
    }
    const SphericalTraversal traversal(grid);
    const std::vector<double> cells = sampleCellMidpoints(grid, [&](double r, double, double) { return chi(r); });
    std::vector<CellSegment> segments;
    double sumSquares = 0.0;
    int rays = 0;
    for (int iy = 0; iy < 64; ++iy)
      for (int iz = 0; iz < 64; ++iz)
      {
        const dvec3 o(-2.0, (iy + 0.5) / 32.0 - 1.0, (iz + 0.5) / 32.0 - 1.0), d(1.0, 0.0, 0.0);
        traversal.traverse(o, d, 0.0, 4.0, segments);
        const double error = projectCellConstant(grid, cells, segments, 1.0) - chi.rayIntegral(o, d, 0.0, 4.0);
        sumSquares += error * error;
        ++rays;
      }
    const double rms = std::sqrt(sumSquares / rays);
    std::printf("N = %d: RMS error of chi_0.5 projections %.3e\n", n, rms);
    EXPECT_LT(rms, 0.75 * previous);
    previous = rms;
  }
}

TEST(SphericalSamplers, BadNodeCounts)
{
  const SphericalGrid grid = unitBall();
  std::vector<CellSegment> segments;
  EXPECT_THROW(projectLinearInRadius(grid, std::vector<double>(3), segments, dvec3(0.0), dvec3(1.0, 0.0, 0.0)),
    std::invalid_argument);
  EXPECT_THROW(projectLinearInRadiusSquared(grid, std::vector<double>(3), segments, dvec3(0.0), dvec3(1.0, 0.0, 0.0)),
    std::invalid_argument);
  const SphericalTraversal traversal(grid);
  EXPECT_THROW(projectLinearInRadius(traversal, std::vector<double>(3), dvec3(-2.0, 0.0, 0.0), dvec3(1.0, 0.0, 0.0), 0.0, 4.0),
    std::invalid_argument);
  EXPECT_THROW(projectLinearInRadiusSquared(traversal, std::vector<double>(3), dvec3(-2.0, 0.0, 0.0), dvec3(1.0, 0.0, 0.0), 0.0, 4.0),
    std::invalid_argument);
  EXPECT_THROW(projectCellConstant(traversal, std::vector<double>(3), dvec3(-2.0, 0.0, 0.0), dvec3(1.0, 0.0, 0.0), 0.0, 4.0),
    std::invalid_argument);
}

// Numerical stress: the same grid and rays scaled by 1e-6 and 1e6 (relative precision must not
// depend on units), and rays that start 1e3 radii away (the closest-approach form keeps the
// chords accurate; the error may grow with the distance, but stays far below 1e-9 here).
TEST(SphericalSamplers, ScaleAndDistanceStress)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double scale : { 1e-6, 1.0, 1e6 })
    for (double distance : { 2.0, 1e3 })
    {
      SphericalGrid grid = unitBall();
      for (double& r : grid.radius)
        r *= scale;
      const SphericalTraversal traversal(grid);
      const RadialStepField chi{ { 0.5 * scale, scale }, { 2.0, 1.0 } };
      const std::vector<double> cells = sampleCellMidpoints(grid, [&](double r, double, double) { return chi(r); });
      std::vector<CellSegment> segments;
      double worst = 0.0;
      int hits = 0;
      for (int i = 0; i < 300; ++i)
      {
        const dvec3 d = glm::normalize(dvec3(u(rng), u(rng), u(rng)));
        const dvec3 target = scale * dvec3(u(rng), u(rng), u(rng));
        const dvec3 o = target - distance * scale * d;
        traversal.traverse(o, d, 0.0, 2.0 * distance * scale, segments);
        const double ours = projectCellConstant(grid, cells, segments, 1.0);
        const double exact = chi.rayIntegral(o, d, 0.0, 2.0 * distance * scale);
        if (exact > 0.0)
        {
          ++hits;
          worst = std::max(worst, std::abs(ours - exact) / exact);
        }
      }
      std::printf("scale %g, origins %g radii away: %d rays through the ball, worst relative error %.2e\n",
        scale, distance, hits, worst);
      EXPECT_GT(hits, 50);
      EXPECT_LT(worst, 1e-9);
    }
}

// Point data: the field r given at the grid's points is reproduced exactly by trilinear
// interpolation in (r, theta, phi); with extinction equal to the value, a pixel's opacity is
// 1 - exp(-integral of r). The midpoint rule converges to it at second order in the sample
// distance, on spherical and (with rho) cylindrical grids.
TEST(SphericalVolume, PointDataConvergesAtSecondOrder)
{
  const SphericalGrid sphereGrid = unitBall();
  const SphericalTraversal sphere(sphereGrid);
  std::vector<double> sphereValues;
  for (double phi : sphereGrid.azimuth)
    for (double theta : sphereGrid.polar)
      for (double r : sphereGrid.radius)
      {
        (void)phi;
        (void)theta;
        sphereValues.push_back(r);
      }
  const CylindricalGrid cylinderGrid{ { 0.0, 0.3, 0.7, 1.0 }, { 0.0, 2.0, 4.0, 2.0 * kPi }, { -1.0, 0.0, 1.0 } };
  const CylindricalTraversal cylinder(cylinderGrid);
  std::vector<double> cylinderValues;
  for (double z : cylinderGrid.height)
    for (double phi : cylinderGrid.azimuth)
      for (double rho : cylinderGrid.radius)
      {
        (void)z;
        (void)phi;
        cylinderValues.push_back(rho);
      }
  // Extinction = value on [0, 1], white.
  TransferTable transfer;
  transfer.minimum = 0.0;
  transfer.maximum = 1.0;
  transfer.entries = { TransferSample{ vec3(1.0f), 0.0 }, TransferSample{ vec3(1.0f), 1.0 } };
  CameraParameters parameters;
  parameters.position = dvec3(0.3, -0.2, 5.0);
  parameters.focalPoint = dvec3(0.0);
  parameters.parallelProjection = true;
  parameters.parallelScale = 1.1;
  const Camera camera = Camera::fromParameters(parameters, 24, 24);
  SphericalVolumeOptions untilOpaque; // no early termination: every sample counts
  untilOpaque.minimumTransmittance = 0.0;
  for (const bool cylindrical : { false, true })
  {
    double previous = 0.0;
    for (double distance : { 0.1, 0.05, 0.025 })
    {
      Framebuffer fb;
      if (cylindrical)
        renderCylindricalVolumePoints(cylinder, cylinderValues, transfer, distance, camera, fb, untilOpaque);
      else
        renderSphericalVolumePoints(sphere, sphereValues, transfer, distance, camera, fb, untilOpaque);
      double worst = 0.0;
      for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x)
        {
          const DoubleRay ray = camera.doublePrimaryRay(x + 0.5, y + 0.5); // the ray the renderer traces
          const dvec3 o(ray.origin), d(ray.direction);
          double depth;
          if (cylindrical)
          {
            // Integral of rho along the ray inside the cylinder, |z| <= 1: graded quadrature.
            double t0 = ray.tnear, t1 = ray.tfar;
            const double a = (-1.0 - o.z) / d.z, b = (1.0 - o.z) / d.z;
            t0 = std::max(t0, std::min(a, b));
            t1 = std::min(t1, std::max(a, b));
            const double dxy = d.x * d.x + d.y * d.y, tc = -(o.x * d.x + o.y * d.y) / dxy;
            const double c = std::hypot(o.x + tc * d.x, o.y + tc * d.y);
            depth = 0.0;
            if (c < 1.0)
            {
              const double h = std::sqrt((1.0 - c) * (1.0 + c) / dxy);
              const double e = std::max(t0, tc - h), l = std::min(t1, tc + h);
              for (int piece = 0; piece < 400 && l > e; ++piece)
                depth += gaussLegendre([&](double t) { return std::hypot(o.x + t * d.x, o.y + t * d.y); },
                  e + (l - e) * piece / 400.0, e + (l - e) * (piece + 1) / 400.0);
            }
          }
          else
            depth = referenceIntegralOfRadius(o, d, ray.tnear, ray.tfar);
          const double alpha = 1.0 - std::exp(-depth);
          worst = std::max(worst, std::abs(double(fb.Color[fb.index(x, y)].a) - alpha));
        }
      std::printf("%s point data, sample distance %.3f: worst opacity error %.2e\n",
        cylindrical ? "cylindrical" : "spherical", distance, worst);
      EXPECT_LT(worst, 2e-3);
      if (previous > 1e-6) // float colour storage floors the error near 1e-7
      {
        EXPECT_LT(worst, 0.4 * previous) << "not second order";
      }
      previous = worst;
    }
  }
  Framebuffer fb;
  EXPECT_THROW(renderSphericalVolumePoints(sphere, { 1.0 }, transfer, 0.1, camera, fb), std::invalid_argument);
  EXPECT_THROW(renderSphericalVolumePoints(sphere, sphereValues, transfer, 0.0, camera, fb), std::invalid_argument);
}

// The shading gradients: the field x (a Cartesian coordinate) sampled at cell centres has the
// gradient (1, 0, 0); central differences in the curvilinear coordinates recover it to second
// order in the cell size away from the axis, the seam and the section edges.
TEST(SphericalVolume, CellGradientsOfALinearField)
{
  SphericalGrid sphere;
  for (int i = 0; i <= 24; ++i)
    sphere.radius.push_back(0.5 + i / 24.0);
  for (int i = 0; i <= 36; ++i)
    sphere.polar.push_back(kPi * i / 36.0);
  for (int i = 0; i <= 72; ++i)
    sphere.azimuth.push_back(2.0 * kPi * i / 72.0);
  CylindricalGrid cylinder{ sphere.radius, sphere.azimuth, { -1.0, -0.5, 0.0, 0.5, 1.0 } };
  for (const bool cylindrical : { false, true })
  {
    const std::vector<dvec3> centres = cylindrical ? cellCentres(cylinder) : cellCentres(sphere);
    std::vector<double> values;
    for (const dvec3& c : centres)
      values.push_back(c.x);
    const std::vector<dvec3> gradients =
      cylindrical ? cylindricalCellGradients(cylinder, values) : sphericalCellGradients(sphere, values);
    double worst = 0.0;
    for (std::size_t c = 0; c < centres.size(); ++c)
    {
      const double r = glm::length(centres[c]), rho = std::hypot(centres[c].x, centres[c].y);
      const bool interior = cylindrical ? (rho > 0.6 && rho < 1.4) : (r > 0.6 && r < 1.4 && rho > 0.3 * r);
      if (interior)
        worst = std::max(worst, glm::length(gradients[c] - dvec3(1.0, 0.0, 0.0)));
    }
    std::printf("%s gradients of x: worst interior error %.2e\n", cylindrical ? "cylindrical" : "spherical", worst);
    EXPECT_LT(worst, 0.02);
  }
}
