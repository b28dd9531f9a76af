// SPDX-License-Identifier: BSD-3-Clause
// Spherical-grid traversal (SphericalGrid.h) against an independent reference: every sphere,
// cone and half-plane of the grid intersected by brute force, the pieces between consecutive
// crossings classified by converting their midpoints to (r, theta, phi) with acos and atan2.
// For every class of ray the thesis singles out (through the origin, along the polar axis,
// tangent to a shell, grazing a cone, starting inside, through a cell corner, through the z
// axis, vertical) and for random rays, on a full sphere and on a section (shell, band, wedge):
// segments are ordered and inside the cell they name, their lengths sum to the chord through
// the domain, and the projections of a step function and of r^2 equal the reference integrals.
#include "sightline/volumes/EarthModel.h"
#include "sightline/volumes/SphericalGrid.h"
#include "sightline/volumes/SphericalVolume.h"

#include "volumes/SphericalRayClasses.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

using namespace sightline;

namespace
{
using sightline::kPi;

SphericalGrid fullSphere()
{
  // Non-uniform in every coordinate; the equator and both poles are breakpoints.
  return { { 0.0, 0.3, 0.55, 1.0, 1.2, 2.0 }, { 0.0, 0.4, 1.0, kPi / 2, 2.2, kPi },
    { -kPi, -2.0, -0.5, 0.0, 0.7, 1.9, kPi } };
}

SphericalGrid section()
{
  // A shell r in [0.5, 2], a band theta in [0.3, 2.0], a wedge phi in [-0.5, 2.5].
  return { { 0.5, 0.8, 1.5, 2.0 }, { 0.3, 0.9, kPi / 2, 2.0 }, { -0.5, 0.4, 1.3, 2.5 } };
}

struct Classified
{
  bool inside;
  int r, theta, phi;
};

Classified classify(const SphericalGrid& g, const dvec3& x)
{
  const double r = glm::length(x);
  const double theta = r > 0.0 ? std::acos(std::clamp(x.z / r, -1.0, 1.0)) : 0.0;
  double phi = std::atan2(x.y, x.x);
  const double phi0 = g.azimuth.front();
  while (phi < phi0)
    phi += 2.0 * kPi;
  while (phi >= phi0 + 2.0 * kPi)
    phi -= 2.0 * kPi;
  auto index = [](const std::vector<double>& b, double v)
  { return int(std::upper_bound(b.begin(), b.end(), v) - b.begin()) - 1; };
  Classified c{ false, index(g.radius, r), index(g.polar, theta), index(g.azimuth, phi) };
  if (theta >= g.polar.back() && g.polar.back() >= kPi)
    c.theta = g.polarCells() - 1; // the south pole belongs to the last band
  c.inside = c.r >= 0 && c.r < g.radialCells() && c.theta >= 0 && c.theta < g.polarCells() &&
    c.phi >= 0 && c.phi < g.azimuthalCells();
  return c;
}

/// Every t where the line meets a grid surface (extra candidates are harmless).
std::vector<double> allCrossings(const SphericalGrid& g, const dvec3& p, const dvec3& d, double tmin, double tmax)
{
  std::vector<double> ts = { tmin, tmax };
  auto quadratic = [&](double a, double b, double c)
  {
    if (std::abs(a) < 1e-300)
    {
      if (b != 0.0)
        ts.push_back(-c / b);
      return;
    }
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0.0)
      return;
    // Both roots, each polished by Newton steps in long double.
    for (double sign : { -1.0, 1.0 })
    {
      long double t = (-b + sign * std::sqrt(disc)) / (2.0 * a);
      for (int k = 0; k < 3; ++k)
      {
        const long double f = (a * t + b) * t + c, df = 2.0L * a * t + b;
        if (df != 0.0L)
          t -= f / df;
      }
      ts.push_back(double(t));
    }
  };
  for (double r : g.radius)
    quadratic(glm::dot(d, d), 2.0 * glm::dot(p, d), glm::dot(p, p) - r * r);
  for (double theta : g.polar)
  {
    const double c2 = std::cos(theta) * std::cos(theta);
    quadratic(d.z * d.z - c2 * glm::dot(d, d), 2.0 * (p.z * d.z - c2 * glm::dot(p, d)), p.z * p.z - c2 * glm::dot(p, p));
  }
  for (double phi : g.azimuth)
  {
    const double den = d.y * std::cos(phi) - d.x * std::sin(phi);
    if (den != 0.0)
      ts.push_back((p.x * std::sin(phi) - p.y * std::cos(phi)) / den);
  }
  // The equator's "cone" is the plane z = 0 (a double root the quadratic may lose to rounding),
  // and the origin and the z axis, where theta and phi jump.
  if (d.z != 0.0)
    ts.push_back(-p.z / d.z);
  ts.push_back(-glm::dot(p, d) / glm::dot(d, d));
  if (d.x * d.x + d.y * d.y > 0.0)
    ts.push_back(-(p.x * d.x + p.y * d.y) / (d.x * d.x + d.y * d.y));
  std::vector<double> kept;
  for (double t : ts)
    if (std::isfinite(t) && t >= tmin && t <= tmax)
      kept.push_back(t);
  std::sort(kept.begin(), kept.end());
  return kept;
}

/// Integral of |p + t d|^2 over [a, b].
double integralOfRadiusSquared(const dvec3& p, const dvec3& d, double a, double b)
{
  const double dd = glm::dot(d, d), pd = glm::dot(p, d), pp = glm::dot(p, p);
  auto antiderivative = [&](double t) { return pp * t + pd * t * t + dd * t * t * t / 3.0; };
  return antiderivative(b) - antiderivative(a);
}

double stepValue(const SphericalGrid& g, int r, int theta, int phi)
{
  return 1.0 + 0.5 * r + 0.25 * theta + 0.125 * phi + 0.01 * double(g.cellIndex(r, theta, phi) % 7);
}

struct RayCheck
{
  int rays = 0, hitting = 0, nearTangent = 0;
  double worstLength = 0.0, worstStep = 0.0, worstRadiusSquared = 0.0;
};

/// `onBoundary`: the ray lies in a cone, so which of the two cells it is in is a matter of
/// rounding; then only the chord and r^2 (which do not depend on it) are compared.
/// Errors must be under 1e-9 relative, or under an absolute floor of 3e-8 x the ray's span x
/// the integrand's size (such rays are counted): where a ray touches a sphere or a cone, the
/// crossing is a near-double root whose position rounding alone moves by ~sqrt(1e-16) of the
/// radius, in any implementation (the reference included).
void checkRay(const SphericalTraversal& traversal, const dvec3& p, const dvec3& d, double tmin,
  double tmax, RayCheck& stats, const char* what, bool onBoundary = false)
{
  const SphericalGrid& g = traversal.grid();
  std::vector<CellSegment> segments;
  traversal.traverse(p, d, tmin, tmax, segments);
  // Reference pieces.
  const std::vector<double> ts = allCrossings(g, p, d, tmin, tmax);
  double length = 0.0, step = 0.0, radiusSquared = 0.0;
  for (std::size_t i = 0; i + 1 < ts.size(); ++i)
  {
    if (!(ts[i + 1] > ts[i]))
      continue;
    const Classified c = classify(g, p + 0.5 * (ts[i] + ts[i + 1]) * d);
    if (!c.inside)
      continue;
    length += ts[i + 1] - ts[i];
    step += stepValue(g, c.r, c.theta, c.phi) * (ts[i + 1] - ts[i]);
    radiusSquared += integralOfRadiusSquared(p, d, ts[i], ts[i + 1]);
  }
  double ourLength = 0.0, ourStep = 0.0, ourRadiusSquared = 0.0, previous = tmin;
  for (const CellSegment& s : segments)
  {
    ASSERT_GT(s.t1, s.t0) << what;
    ASSERT_GE(s.t0, previous - 1e-12 * (1.0 + std::abs(previous))) << what << ": segments out of order";
    previous = s.t1;
    ourLength += s.t1 - s.t0;
    ourStep += stepValue(g, s.r, s.theta, s.phi) * (s.t1 - s.t0);
    ourRadiusSquared += integralOfRadiusSquared(p, d, s.t0, s.t1);
    if (s.t1 - s.t0 > 1e-7 && !onBoundary)
    {
      const Classified c = classify(g, p + 0.5 * (s.t0 + s.t1) * d);
      EXPECT_TRUE(c.inside && c.r == s.r && c.theta == s.theta && c.phi == s.phi)
        << what << ": segment [" << s.t0 << ", " << s.t1 << "] names cell (" << s.r << ", " << s.theta
        << ", " << s.phi << "), its midpoint is in (" << c.r << ", " << c.theta << ", " << c.phi << ")";
    }
  }
  ++stats.rays;
  stats.hitting += length > 0.0;
  const double scale = tmax - tmin;
  const double outer = g.radius.back();
  // Relative error, or 0 when the difference is under the tangency floor (counted apart).
  bool usedFloor = false;
  auto relative = [&](double ours, double reference, double size)
  {
    const double difference = std::abs(ours - reference);
    const double raw = difference / std::max(std::abs(reference), 1e-300);
    if (raw < 1e-9)
      return raw;
    if (difference <= 3e-8 * scale * size)
    {
      usedFloor = true;
      return 0.0;
    }
    return raw;
  };
  const double e1 = relative(ourLength, length, 1.0);
  const double e2 = onBoundary ? 0.0 : relative(ourStep, step, 5.0);
  const double e3 = relative(ourRadiusSquared, radiusSquared, outer * outer);
  stats.nearTangent += usedFloor;
  if (!usedFloor)
  {
    stats.worstLength = std::max(stats.worstLength, e1);
    stats.worstStep = std::max(stats.worstStep, e2);
    stats.worstRadiusSquared = std::max(stats.worstRadiusSquared, e3);
  }
  EXPECT_LT(e1, 1e-9) << what << ": chord " << ourLength << " against " << length;
  EXPECT_LT(e2, 1e-9) << what << ": step-function projection " << ourStep << " against " << step;
  EXPECT_LT(e3, 1e-9) << what << ": r^2 projection " << ourRadiusSquared << " against " << radiusSquared;
}

/// Every ray class on `grid`; at least `minimumHitPercent` of the rays must cross the domain.
void checkAllRayClassesWith(const SphericalGrid& grid, const char* name, int minimumHitPercent)
{
  const SphericalTraversal traversal(grid);
  RayCheck stats;
  sightline_test::forEachRayClass(grid,
    [&](const char* what, const dvec3& p, const dvec3& d, double tmin, double tmax, bool onBoundary)
    { checkRay(traversal, p, d, tmin, tmax, stats, what, onBoundary); });
  std::printf("%s: %d rays (%d crossing the domain, %d within the tangency floor), worst relative "
              "errors of the others: chord %.2e, step function %.2e, r^2 %.2e\n",
    name, stats.rays, stats.hitting, stats.nearTangent, stats.worstLength, stats.worstStep,
    stats.worstRadiusSquared);
  EXPECT_GT(100 * stats.hitting, minimumHitPercent * stats.rays);
}

void checkAllRayClasses(const SphericalGrid& grid, const char* name)
{
  checkAllRayClassesWith(grid, name, 33);
}
} // namespace

TEST(SphericalGrid, FullSphereEveryRayClass)
{
  checkAllRayClasses(fullSphere(), "full sphere");
}

TEST(SphericalGrid, SectionEveryRayClass)
{
  checkAllRayClasses(section(), "shell x band x wedge");
}

TEST(SphericalGrid, ForEachCellStopsWhereTheVisitorSays)
{
  // The visitor sees the segments of traverse(), in order, and nothing after it returns false.
  for (const SphericalGrid& grid : { fullSphere(), section() })
  {
    const SphericalTraversal traversal(grid);
    std::vector<CellSegment> all;
    int rays = 0;
    sightline_test::forEachRayClass(grid,
      [&](const char* what, const dvec3& p, const dvec3& d, double tmin, double tmax, bool)
      {
        traversal.traverse(p, d, tmin, tmax, all);
        const std::size_t stop = all.size() / 2;
        std::vector<CellSegment> seen;
        traversal.forEachCell(p, d, tmin, tmax,
          [&](int r, int theta, int phi, double t0, double t1)
          {
            seen.push_back({ r, theta, phi, t0, t1 });
            return seen.size() <= stop;
          });
        ASSERT_EQ(seen.size(), all.empty() ? 0 : stop + 1) << what;
        for (std::size_t i = 0; i < seen.size(); ++i)
        {
          EXPECT_EQ(seen[i].r, all[i].r) << what;
          EXPECT_EQ(seen[i].theta, all[i].theta) << what;
          EXPECT_EQ(seen[i].phi, all[i].phi) << what;
          EXPECT_EQ(seen[i].t0, all[i].t0) << what;
          EXPECT_EQ(seen[i].t1, all[i].t1) << what;
        }
        rays += !all.empty();
      });
    EXPECT_GT(rays, 100);
  }
}

TEST(SphericalGrid, CoarseAndNarrowAzimuths)
{
  // Points are placed among the azimuth half-planes by sign tests, which need neighbours under
  // pi / 2 apart: a whole circle in one or two wedges, a narrow wedge (its gap 6 radians) and a
  // wide one, each with wedge edges off the axes, against the atan2 reference.
  const std::vector<std::vector<double>> azimuths = { { 0.3, 0.3 + 2.0 * kPi },
    { -1.0, 2.0, -1.0 + 2.0 * kPi }, { 1.0, 1.2 }, { -2.5, 0.1, 2.9 } };
  for (const std::vector<double>& azimuth : azimuths)
  {
    // The equator as the one polar breakpoint: a ray through the origin changes band there, so
    // no piece has the origin (where the reference's theta is a convention) as its midpoint.
    const SphericalGrid grid{ { 0.0, 0.5, 1.0 }, { 0.0, kPi / 2, kPi }, azimuth };
    checkAllRayClassesWith(grid, "coarse or narrow azimuths", 10);
  }
}

TEST(SphericalGrid, PolarGridInAPlane)
{
  // 2-D polar: theta spans [0, pi] in one band, rays in the plane z = 0.
  const SphericalGrid grid{ { 0.0, 0.5, 0.7, 1.6 }, { 0.0, kPi }, { 0.0, 0.5, 2.0, 4.0, 2.0 * kPi } };
  const SphericalTraversal traversal(grid);
  std::mt19937 rng(62);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi), u(-1.0, 1.0);
  RayCheck stats;
  for (int i = 0; i < 200; ++i)
  {
    const double a = angle(rng);
    const dvec3 dir(std::cos(a), std::sin(a), 0.0);
    const dvec3 target(u(rng), u(rng), 0.0);
    checkRay(traversal, target - 3.0 * dir, dir, 0.0, 6.0, stats, "polar");
  }
  EXPECT_GT(stats.hitting, 150);
}

TEST(SphericalGrid, SamplersAndBadGrids)
{
  const SphericalGrid grid = fullSphere();
  const SphericalTraversal traversal(grid);
  std::vector<CellSegment> segments;
  // Straight through the centre along x: chord 4 (radius 2).
  traversal.traverse(dvec3(-3, 0.01, 0.02), dvec3(2, 0, 0), 0.0, 10.0, segments);
  std::vector<double> ones(grid.cellCount(), 1.0);
  EXPECT_NEAR(projectCellConstant(grid, ones, segments, 2.0), 2.0 * std::sqrt(4.0 - 0.0005), 1e-12);
  // Emission-absorption in a homogeneous medium: opacity 1 - exp(-k L).
  auto transfer = [](double) { return TransferSample{ vec3(1.0f, 0.5f, 0.25f), 0.3 }; };
  const vec4 rgba = emissionAbsorption(grid, ones, transfer, segments, 2.0);
  const double chord = 2.0 * std::sqrt(4.0 - 0.0005);
  EXPECT_NEAR(rgba.a, 1.0 - std::exp(-0.3 * chord), 1e-6);
  EXPECT_NEAR(rgba.r, rgba.a, 1e-6);
  EXPECT_NEAR(rgba.g, 0.5 * rgba.a, 1e-6);
  // Early termination: a dense medium stops at the first cells.
  auto opaque = [](double) { return TransferSample{ vec3(1.0f), 1e6 }; };
  EXPECT_NEAR(emissionAbsorption(grid, ones, opaque, segments, 2.0).a, 1.0, 1e-3);
  EXPECT_THROW(projectCellConstant(grid, { 1.0 }, segments, 1.0), std::invalid_argument);

  auto bad = [](SphericalGrid g) { EXPECT_THROW(SphericalTraversal{ g }, std::invalid_argument); };
  SphericalGrid g = fullSphere();
  g.radius = { 0.0, 1.0, 0.5 };
  bad(g); // not monotonic
  g = fullSphere();
  g.radius[0] = -0.1;
  bad(g); // r < 0
  g = fullSphere();
  g.polar.back() = 3.5;
  bad(g); // theta beyond pi
  g = fullSphere();
  g.azimuth = { 0.0, 7.0 };
  bad(g); // phi over 2 pi
  g = fullSphere();
  g.azimuth = { 0.0 };
  bad(g); // one breakpoint
  g = fullSphere();
  g.polar[2] = std::nan("");
  bad(g);
}

TEST(SphericalVolume, HomogeneousShellsAgainstClosedForms)
{
  // Extinction k in the shell 1.2 <= r < 2 and none inside: each pixel's opacity is
  // 1 - exp(-k (chord(2) - chord(1.2))), chord(R) = 2 sqrt(R^2 - b^2) for a ray passing the
  // centre at distance b. With an opaque sphere of radius 1.2 drawn "by OpenGL" (a depth
  // limit), only the front part of the shell remains: half of that path.
  const SphericalGrid grid = fullSphere();
  const SphericalTraversal traversal(grid);
  std::vector<double> values(grid.cellCount());
  for (int ip = 0; ip < grid.azimuthalCells(); ++ip)
    for (int it = 0; it < grid.polarCells(); ++it)
      for (int ir = 0; ir < grid.radialCells(); ++ir)
        values[grid.cellIndex(ir, it, ip)] = grid.radius[std::size_t(ir)] >= 1.2 ? 1.0 : 0.0;
  const double k = 0.7;
  auto transfer = [&](double v) { return TransferSample{ vec3(0.2f, 0.6f, 1.0f), v * k }; };
  CameraParameters parameters;
  parameters.position = dvec3(0.3, -0.2, 9.0);
  parameters.focalPoint = dvec3(0.0);
  parameters.viewAngle = 30.0;
  const Camera camera = Camera::fromParameters(parameters, 64, 48);
  auto chord = [](double radius, double b2) { return b2 < radius * radius ? 2.0 * std::sqrt(radius * radius - b2) : 0.0; };

  Framebuffer fb;
  const SphericalVolumeStatistics stats = renderSphericalVolume(traversal, values, transfer, camera, fb);
  std::vector<float> core(fb.pixelCount(), 1.0f);
  int checked = 0;
  for (int y = 0; y < camera.height(); ++y)
    for (int x = 0; x < camera.width(); ++x)
    {
      const DoubleRay ray = camera.doublePrimaryRay(x + 0.5, y + 0.5); // the ray the renderer traces
      const dvec3 o(ray.origin), d(ray.direction);
      const double tc = -glm::dot(o, d);
      const double b2 = glm::dot(o + tc * d, o + tc * d);
      const double path = chord(2.0, b2) - chord(1.2, b2);
      const std::size_t i = fb.index(x, y);
      EXPECT_NEAR(fb.Color[i].a, 1.0 - std::exp(-k * path), 1e-6) << x << ", " << y;
      if (path > 0.0)
      {
        ++checked;
        EXPECT_NEAR(fb.Color[i].b, 1.0f, 1e-5f); // not premultiplied
      }
      if (b2 < 1.44)
        core[i] = float(camera.windowDepth(o + (tc - std::sqrt(1.44 - b2)) * d));
    }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(stats.cellsVisited, 0u);

  SphericalVolumeOptions options;
  options.depthLimit = &core;
  renderSphericalVolume(traversal, values, transfer, camera, fb, options);
  for (int y = 0; y < camera.height(); ++y)
    for (int x = 0; x < camera.width(); ++x)
    {
      const DoubleRay ray = camera.doublePrimaryRay(x + 0.5, y + 0.5); // the ray the renderer traces
      const dvec3 o(ray.origin), d(ray.direction);
      const double tc = -glm::dot(o, d);
      const double b2 = glm::dot(o + tc * d, o + tc * d);
      const double path = b2 < 1.44 ? 0.5 * (chord(2.0, b2) - chord(1.2, b2)) : chord(2.0, b2);
      // The depth limit is a float window depth: a few 1e-5 of path.
      EXPECT_NEAR(fb.Color[fb.index(x, y)].a, 1.0 - std::exp(-k * path), 2e-4) << x << ", " << y;
    }
  EXPECT_THROW(renderSphericalVolume(traversal, { 1.0 }, transfer, camera, fb), std::invalid_argument);
}

TEST(EarthModel, PremDensityAndMassMatchThePublishedValues)
{
  // Values printed in Dziewonski and Anderson (1981): centre 13.0885 g/cm^3; either side of
  // the core-mantle boundary 9.9035 and 5.5665; the Earth's mass 5.974e24 kg (the model's),
  // moment of inertia aside. Layers are contiguous.
  EXPECT_NEAR(premDensity(0.0), 13.0885, 1e-12);
  EXPECT_NEAR(premDensity(3479.999), 9.9035, 5e-4);
  EXPECT_NEAR(premDensity(3480.0), 5.5665, 5e-4);
  EXPECT_NEAR(premDensity(6371.0), 1.02, 1e-12);
  const auto& layers = premLayers();
  for (std::size_t i = 1; i < layers.size(); ++i)
    EXPECT_EQ(layers[i].innerRadiusKm, layers[i - 1].outerRadiusKm);
  const double mass = premMass(6371.0);
  EXPECT_NEAR(mass / 5.974e24, 1.0, 1e-3);
  // The closed form against a midpoint sum of 4 pi r^2 rho over 1 m shells.
  double sum = 0.0;
  const int n = 6371000;
  for (int i = 0; i < n; i += 1)
  {
    const double r = (i + 0.5) * 1e-3; // km
    sum += 4.0 * kPi * r * r * premDensity(r);
  }
  EXPECT_NEAR(sum * 1e-3 * 1e12 / mass, 1.0, 1e-9);
  EXPECT_THROW(premDensity(-1.0), std::invalid_argument);
  EXPECT_THROW(premDensity(std::nan("")), std::invalid_argument);
  EXPECT_THROW(premMass(7000.0), std::invalid_argument);
}
