// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/volumes/SphericalFields.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
RadialStepField RadialStepField::chiHalf()
{
  return RadialStepField{ { 0.5, 1.0 }, { 2.0, 1.0 } };
}

void RadialStepField::validate() const
{
  if (radii.empty())
    throw std::invalid_argument("RadialStepField: no shells");
  if (radii.size() != values.size())
    throw std::invalid_argument("RadialStepField: " + std::to_string(radii.size()) + " radii but " +
      std::to_string(values.size()) + " values");
  for (std::size_t i = 0; i < radii.size(); ++i)
  {
    if (!std::isfinite(radii[i]) || !std::isfinite(values[i]))
      throw std::invalid_argument("RadialStepField: shell " + std::to_string(i) + " is not finite");
    if (radii[i] <= (i == 0 ? 0.0 : radii[i - 1]))
      throw std::invalid_argument("RadialStepField: radius " + std::to_string(i) +
        " is not positive and larger than the one before");
  }
}

double RadialStepField::operator()(double r) const
{
  for (std::size_t i = 0; i < radii.size(); ++i)
    if (r <= radii[i])
      return values[i];
  return 0.0;
}

double RadialStepField::rayIntegral(
  const dvec3& origin, const dvec3& direction, double t0, double t1) const
{
  // Inside shell i the field is values[i]; the chord of sphere i holds the chords of the
  // smaller spheres, so the integral telescopes over chord lengths.
  double sum = 0.0;
  double innerLength = 0.0;
  for (std::size_t i = 0; i < radii.size(); ++i)
  {
    double enter, leave;
    const double length = sphereChord(origin, direction, radii[i], t0, t1, enter, leave)
      ? leave - enter
      : 0.0;
    sum += values[i] * (length - innerLength);
    innerLength = length;
  }
  return sum * glm::length(direction);
}

double RadiusSquaredField::rayIntegral(
  const dvec3& origin, const dvec3& direction, double t0, double t1) const
{
  double enter, leave;
  if (!sphereChord(origin, direction, outerRadius, t0, t1, enter, leave))
    return 0.0;
  // |o + t d|^2 = |p|^2 + a u^2 with u = t - t_closest: integrate in u.
  const double a = glm::dot(direction, direction);
  const double closest = -glm::dot(origin, direction) / a;
  const dvec3 foot = origin + closest * direction;
  const double p2 = glm::dot(foot, foot);
  const double u0 = enter - closest, u1 = leave - closest;
  const double integral = p2 * (u1 - u0) + a * (u1 * u1 * u1 - u0 * u0 * u0) / 3.0;
  return integral * std::sqrt(a);
}

std::vector<double> sampleCellMidpoints(const SphericalGrid& grid, const SphericalFunction& field)
{
  grid.validate();
  std::vector<double> values(grid.cellCount());
  for (int k = 0; k < grid.azimuthalCells(); ++k)
    for (int j = 0; j < grid.polarCells(); ++j)
      for (int i = 0; i < grid.radialCells(); ++i)
        values[grid.cellIndex(i, j, k)] = field(0.5 * (grid.radius[i] + grid.radius[i + 1]),
          0.5 * (grid.polar[j] + grid.polar[j + 1]), 0.5 * (grid.azimuth[k] + grid.azimuth[k + 1]));
  return values;
}
} // namespace sightline
