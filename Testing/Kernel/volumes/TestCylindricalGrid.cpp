// SPDX-License-Identifier: BSD-3-Clause
// Cylindrical-grid traversal (CylindricalGrid.h) against an independent reference: every
// cylinder, half-plane and height plane intersected by brute force and the pieces between
// consecutive crossings classified by converting their midpoints to (rho, phi, z) with hypot
// and atan2; and against closed forms: the chord through the domain, and the integral of a
// field constant between cylinders from cylinder chords. For random rays, rays parallel to
// the axis, through the axis, tangent to every cylinder, inside a half-plane, in a height
// plane, starting inside and through cell corners, on a full circle and on a section.
#include "sightline/volumes/CylindricalGrid.h"

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

CylindricalGrid fullCylinder()
{
  return { { 0.0, 0.25, 0.6, 1.0, 1.4 }, { -kPi, -1.7, -0.2, 0.9, 2.2, kPi }, { -1.0, -0.3, 0.2, 0.5, 1.2 } };
}

CylindricalGrid section()
{
  // A hollow cylinder rho in [0.4, 1.4], a wedge phi in [-0.6, 2.4], a slab z in [-0.7, 0.9].
  return { { 0.4, 0.7, 1.1, 1.4 }, { -0.6, 0.5, 1.6, 2.4 }, { -0.7, 0.0, 0.9 } };
}

struct Where
{
  bool inside;
  int rho, phi, z;
};

Where classify(const CylindricalGrid& g, const dvec3& x)
{
  const double rho = std::hypot(x.x, x.y);
  double phi = std::atan2(x.y, x.x);
  const double phi0 = g.azimuth.front();
  while (phi < phi0)
    phi += 2.0 * kPi;
  while (phi >= phi0 + 2.0 * kPi)
    phi -= 2.0 * kPi;
  auto index = [](const std::vector<double>& b, double v)
  { return int(std::upper_bound(b.begin(), b.end(), v) - b.begin()) - 1; };
  Where w{ false, index(g.radius, rho), index(g.azimuth, phi), index(g.height, x.z) };
  w.inside = w.rho >= 0 && w.rho < g.radialCells() && w.phi >= 0 && w.phi < g.azimuthalCells() &&
    w.z >= 0 && w.z < g.heightCells();
  return w;
}

std::vector<double> crossings(const CylindricalGrid& g, const dvec3& p, const dvec3& d, double tmin, double tmax)
{
  std::vector<double> ts{ tmin, tmax };
  const double a = d.x * d.x + d.y * d.y, b = p.x * d.x + p.y * d.y, c0 = p.x * p.x + p.y * p.y;
  for (double r : g.radius)
  {
    const double disc = b * b - a * (c0 - r * r);
    if (a > 0.0 && disc >= 0.0)
    {
      ts.push_back((-b - std::sqrt(disc)) / a);
      ts.push_back((-b + std::sqrt(disc)) / a);
    }
  }
  for (double phi : g.azimuth)
  {
    const double den = d.y * std::cos(phi) - d.x * std::sin(phi);
    if (den != 0.0)
      ts.push_back((p.x * std::sin(phi) - p.y * std::cos(phi)) / den);
  }
  for (double z : g.height)
    if (d.z != 0.0)
      ts.push_back((z - p.z) / d.z);
  if (a > 0.0)
    ts.push_back(-b / a); // the axis, where phi jumps
  std::vector<double> kept;
  for (double t : ts)
    if (std::isfinite(t) && t >= tmin && t <= tmax)
      kept.push_back(t);
  std::sort(kept.begin(), kept.end());
  return kept;
}

double value(int rho, int phi, int z)
{
  return 1.0 + 0.5 * rho + 0.25 * phi + 0.125 * z;
}

struct Stats
{
  int rays = 0, hitting = 0;
  double worst = 0.0;
};

void checkRay(const CylindricalTraversal& traversal, const dvec3& p, const dvec3& d, double tmin,
  double tmax, Stats& stats, const char* what, bool onBoundary = false)
{
  const CylindricalGrid& g = traversal.grid();
  std::vector<CellSegment> segments;
  traversal.traverse(p, d, tmin, tmax, segments);
  const std::vector<double> ts = crossings(g, p, d, tmin, tmax);
  double length = 0.0, integral = 0.0;
  for (std::size_t i = 0; i + 1 < ts.size(); ++i)
  {
    if (!(ts[i + 1] > ts[i]))
      continue;
    const Where w = classify(g, p + 0.5 * (ts[i] + ts[i + 1]) * d);
    if (!w.inside)
      continue;
    length += ts[i + 1] - ts[i];
    integral += value(w.rho, w.phi, w.z) * (ts[i + 1] - ts[i]);
  }
  double ourLength = 0.0, ourIntegral = 0.0, previous = tmin;
  for (const CellSegment& s : segments)
  {
    ASSERT_GT(s.t1, s.t0) << what;
    ASSERT_GE(s.t0, previous - 1e-12 * (1.0 + std::abs(previous))) << what << ": out of order";
    previous = s.t1;
    ourLength += s.t1 - s.t0;
    ourIntegral += value(s.r, s.phi, s.theta) * (s.t1 - s.t0);
    if (s.t1 - s.t0 > 1e-7 && !onBoundary)
    {
      const Where w = classify(g, p + 0.5 * (s.t0 + s.t1) * d);
      EXPECT_TRUE(w.inside && w.rho == s.r && w.phi == s.phi && w.z == s.theta)
        << what << ": segment [" << s.t0 << ", " << s.t1 << "] names (" << s.r << ", " << s.phi << ", "
        << s.theta << "), its midpoint is in (" << w.rho << ", " << w.phi << ", " << w.z << ")";
    }
  }
  ++stats.rays;
  stats.hitting += length > 0.0;
  // Near-tangent rays: the crossing is a near-double root (see TestSphericalGrid.cpp).
  const double floor = 3e-8 * (tmax - tmin);
  const double e1 = std::abs(ourLength - length), e2 = std::abs(ourIntegral - integral);
  if (!onBoundary && (e1 > floor || e2 > 3.0 * floor))
    stats.worst = std::max(stats.worst, std::max(e1, e2) / std::max(length, 1e-300));
  EXPECT_LE(e1, std::max(1e-9 * length, floor)) << what << ": length " << ourLength << " against " << length;
  if (!onBoundary)
  {
    EXPECT_LE(e2, std::max(1e-9 * integral, 3.0 * floor)) << what << ": integral " << ourIntegral << " against " << integral;
  }
}

void checkAllRayClasses(const CylindricalGrid& grid, const char* name)
{
  const CylindricalTraversal traversal(grid);
  std::mt19937 rng(5);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto direction = [&] { return glm::normalize(dvec3(n(rng), n(rng), n(rng))); };
  Stats stats;
  const double far = 4.0;
  for (int i = 0; i < 300; ++i)
  {
    const dvec3 d = direction(), target = 1.5 * dvec3(u(rng), u(rng), u(rng));
    checkRay(traversal, target - far * d, d, 0.0, 2.0 * far, stats, "random");
  }
  for (int i = 0; i < 60; ++i) // ending or starting anywhere
  {
    const dvec3 d = direction(), target = 1.5 * dvec3(u(rng), u(rng), u(rng));
    const double a = far * (1.0 + u(rng)), b = far * (1.0 + u(rng));
    checkRay(traversal, target - far * d, d, std::min(a, b), std::max(a, b), stats, "ending anywhere");
  }
  for (int i = 0; i < 30; ++i) // parallel to the axis, and the axis itself
  {
    const dvec3 o(1.3 * u(rng), 1.3 * u(rng), -far);
    checkRay(traversal, o, dvec3(0, 0, 1), 0.0, 2.0 * far, stats, "parallel to the axis");
  }
  checkRay(traversal, dvec3(0, 0, far), dvec3(0, 0, -1), 0.0, 2.0 * far, stats, "the axis");
  for (int i = 0; i < 40; ++i) // through the axis
  {
    const dvec3 d = direction(), axisPoint(0.0, 0.0, u(rng));
    checkRay(traversal, axisPoint - far * d, d, 0.0, 2.0 * far, stats, "through the axis");
  }
  for (double r : grid.radius) // tangent to every cylinder
  {
    if (r == 0.0)
      continue;
    const double phi = 0.37;
    const dvec3 foot(r * std::cos(phi), r * std::sin(phi), 0.1);
    const dvec3 d = glm::normalize(dvec3(-std::sin(phi), std::cos(phi), 0.3));
    checkRay(traversal, foot - far * d, d, 0.0, 2.0 * far, stats, "tangent to a cylinder");
  }
  for (double phi : grid.azimuth) // inside a half-plane (not a section's edge: in or out is a
  {                                 // convention there)
    if (!grid.fullCircle())
      break;
    const dvec3 d = glm::normalize(dvec3(std::cos(phi), std::sin(phi), 0.4));
    checkRay(traversal, 0.05 * dvec3(std::cos(phi), std::sin(phi), 0.0) - far * d, d, 0.0, 2.0 * far, stats,
      "in a half-plane", true);
  }
  for (std::size_t k = 1; k + 1 < grid.height.size(); ++k) // in an inner height plane
  {
    const double z = grid.height[k];
    const dvec3 d = glm::normalize(dvec3(n(rng), n(rng), 0.0));
    checkRay(traversal, dvec3(0.2, -0.1, z) - far * d, d, 0.0, 2.0 * far, stats, "in a height plane", true);
  }
  for (int i = 0; i < 40; ++i) // starting inside
  {
    const double rho = 0.5 * (grid.radius[1] + grid.radius[2]), phi = 0.5 * (grid.azimuth[1] + grid.azimuth[2]);
    const dvec3 o(rho * std::cos(phi), rho * std::sin(phi), 0.5 * (grid.height[0] + grid.height[1]));
    checkRay(traversal, o, direction(), 0.0, far, stats, "starting inside");
  }
  for (int i = 0; i < 60; ++i) // through cell corners
  {
    const double rho = grid.radius[1 + rng() % (grid.radius.size() - 1)];
    const double phi = grid.azimuth[rng() % grid.azimuth.size()];
    const double z = grid.height[rng() % grid.height.size()];
    const dvec3 corner(rho * std::cos(phi), rho * std::sin(phi), z), d = direction();
    checkRay(traversal, corner - far * d, d, 0.0, 2.0 * far, stats, "through a corner");
  }
  std::printf("%s: %d rays (%d crossing), worst relative error beyond the tangency floor %.2e\n", name,
    stats.rays, stats.hitting, stats.worst);
  EXPECT_GT(stats.hitting, stats.rays / 3);
}
} // namespace

TEST(CylindricalGrid, FullCylinderEveryRayClass)
{
  checkAllRayClasses(fullCylinder(), "full cylinder");
}

TEST(CylindricalGrid, SectionEveryRayClass)
{
  checkAllRayClasses(section(), "hollow x wedge x slab");
}

// A field constant between cylinders, integrated from cylinder chords clipped to the slab.
TEST(CylindricalGrid, ShellFieldAgainstCylinderChords)
{
  const CylindricalGrid grid{ { 0.0, 0.3, 0.8, 1.0 }, { 0.0, 1.0, 2.5, 4.0, 2.0 * kPi }, { -0.5, 0.1, 0.5 } };
  const double shellValue[3] = { 3.0, 2.0, 1.0 };
  std::vector<double> values(grid.cellCount());
  for (int k = 0; k < grid.heightCells(); ++k)
    for (int j = 0; j < grid.azimuthalCells(); ++j)
      for (int i = 0; i < grid.radialCells(); ++i)
        values[grid.cellIndex(i, j, k)] = shellValue[i];
  const CylindricalTraversal traversal(grid);
  auto chord = [](const dvec3& p, const dvec3& d, double r, double t0, double t1)
  {
    const double a = d.x * d.x + d.y * d.y;
    if (a == 0.0)
      return std::hypot(p.x, p.y) < r ? t1 - t0 : 0.0;
    const double tc = -(p.x * d.x + p.y * d.y) / a, c = std::hypot(p.x + tc * d.x, p.y + tc * d.y);
    if (c >= r)
      return 0.0;
    const double h = std::sqrt((r - c) * (r + c) / a);
    return std::max(0.0, std::min(t1, tc + h) - std::max(t0, tc - h));
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<CellSegment> segments;
  double worst = 0.0;
  for (int i = 0; i < 500; ++i)
  {
    const dvec3 p(2.0 * u(rng), 2.0 * u(rng), 2.0 * u(rng)), d(u(rng), u(rng), 0.3 * u(rng));
    double t0 = -10.0, t1 = 10.0;
    if (d.z != 0.0) // the slab
    {
      const double a = (-0.5 - p.z) / d.z, b = (0.5 - p.z) / d.z;
      t0 = std::max(t0, std::min(a, b));
      t1 = std::min(t1, std::max(a, b));
    }
    double exact = 0.0;
    if (t1 > t0)
    {
      const double l1 = chord(p, d, 0.3, t0, t1), l2 = chord(p, d, 0.8, t0, t1), l3 = chord(p, d, 1.0, t0, t1);
      exact = (3.0 * l1 + 2.0 * (l2 - l1) + 1.0 * (l3 - l2)) * glm::length(d);
    }
    traversal.traverse(p, d, -10.0, 10.0, segments);
    const double ours = projectCellConstant(grid, values, segments, glm::length(d));
    worst = std::max(worst, std::abs(ours - exact) / std::max(exact, 1e-300));
    EXPECT_LE(std::abs(ours - exact), 1e-9 * exact + 1e-300) << ours << " against " << exact;
  }
  std::printf("shell field: worst relative error %.2e\n", worst);
  EXPECT_THROW(projectCellConstant(grid, std::vector<double>(3), segments, 1.0), std::invalid_argument);
}

TEST(CylindricalGrid, BadGrids)
{
  const auto fails = [](CylindricalGrid g, const char* fragment)
  {
    try
    {
      CylindricalTraversal t(std::move(g));
      ADD_FAILURE() << "no error for " << fragment;
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  fails({ { 0.0, 0.5, 0.4 }, { 0.0, 1.0 }, { 0.0, 1.0 } }, "increasing");
  fails({ { -0.1, 0.5 }, { 0.0, 1.0 }, { 0.0, 1.0 } }, "below 0");
  fails({ { 0.0, 0.5 }, { 0.0, 7.0 }, { 0.0, 1.0 } }, "2 pi");
  fails({ { 0.0, 0.5 }, { 0.0, 1.0 }, { 0.0 } }, "at least 2");
  fails({ { 0.0, NAN }, { 0.0, 1.0 }, { 0.0, 1.0 } }, "finite");
}
