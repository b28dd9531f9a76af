// SPDX-License-Identifier: BSD-3-Clause
// The classes of rays the spherical-grid thesis singles out, for the kernel tests: random rays
// from outside, rays ending or starting anywhere, through the origin, along and parallel to the
// polar axis, tangent to every shell, grazing and along every cone, starting inside, through
// cell corners and through the z axis. Each ray is handed to `visit(name, origin, direction,
// tmin, tmax, onBoundary)`; `onBoundary` marks rays lying in a cone, whose cell is a matter of
// rounding.
#pragma once

#include "sightline/volumes/SphericalGrid.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace sightline_test
{
template <class Visit>
void forEachRayClass(const sightline::SphericalGrid& grid, Visit visit)
{
  using sightline::dvec3;
  std::mt19937 rng(61);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto direction = [&] { return glm::normalize(dvec3(n(rng), n(rng), n(rng))); };
  const double far = 4.0;
  for (int i = 0; i < 300; ++i) // random rays from outside
  {
    const dvec3 d = direction();
    const dvec3 target = 1.5 * dvec3(u(rng), u(rng), u(rng));
    visit("random", target - far * d, d, 0.0, 2.0 * far, false);
  }
  for (int i = 0; i < 100; ++i) // random rays that end, or start, anywhere (before or after
  {                              // their closest approach to the origin)
    const dvec3 d = direction();
    const dvec3 target = 1.5 * dvec3(u(rng), u(rng), u(rng));
    const double a = far * (1.0 + u(rng)), b = far * (1.0 + u(rng));
    visit("ending anywhere", target - far * d, d, std::min(a, b), std::max(a, b), false);
  }
  for (int i = 0; i < 60; ++i) // through the origin
  {
    const dvec3 d = direction();
    visit("through the origin", -far * d, d, 0.0, 2.0 * far, false);
  }
  for (double sign : { 1.0, -1.0 }) // along the polar axis, and parallel to it
  {
    visit("polar axis", dvec3(0, 0, -sign * far), dvec3(0, 0, sign), 0.0, 2.0 * far, false);
    visit("vertical", dvec3(0.3, -0.2, -sign * far), dvec3(0, 0, sign), 0.0, 2.0 * far, false);
  }
  for (double r : grid.radius) // tangent to every shell
  {
    const dvec3 d = direction();
    const dvec3 normal = glm::normalize(glm::cross(d, direction()));
    visit("tangent to a shell", r * normal - far * d, d, 0.0, 2.0 * far, false);
  }
  for (double theta : grid.polar) // grazing every cone along a tangent line
  {
    const dvec3 g(std::sin(theta), 0.0, std::cos(theta));
    visit("grazing a cone", 1.1 * g - dvec3(0, far, 0), dvec3(0, 1, 0), 0.0, 2.0 * far, false);
    visit("along a cone's generator", dvec3(0.0), g, -far, far, true);
  }
  // The middle of the second cell along an axis (of the first where there is only one).
  auto middle = [](const std::vector<double>& b)
  {
    const std::size_t i = std::min<std::size_t>(1, b.size() - 2);
    return 0.5 * (b[i] + b[i + 1]);
  };
  for (int i = 0; i < 40; ++i) // starting inside the domain
  {
    const dvec3 d = direction();
    const double r = middle(grid.radius);
    const double theta = middle(grid.polar);
    const double phi = middle(grid.azimuth);
    const dvec3 o = r * dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    visit("starting inside", o, d, 0.0, far, false);
  }
  for (int i = 0; i < 60; ++i) // through cell corners
  {
    const double r = grid.radius[1 + rng() % (grid.radius.size() - 1)];
    const double theta = grid.polar[rng() % grid.polar.size()];
    const double phi = grid.azimuth[rng() % grid.azimuth.size()];
    const dvec3 corner = r * dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    const dvec3 d = direction();
    visit("through a corner", corner - far * d, d, 0.0, 2.0 * far, false);
  }
  for (int i = 0; i < 30; ++i) // through the z axis off the origin
  {
    const dvec3 axisPoint(0.0, 0.0, u(rng));
    dvec3 d = direction();
    visit("through the z axis", axisPoint - far * d, d, 0.0, 2.0 * far, false);
  }
}
} // namespace sightline_test
