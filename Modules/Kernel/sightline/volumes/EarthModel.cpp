// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/volumes/EarthModel.h"

#include "sightline/math/Math.h"

#include <cmath>
#include <stdexcept>

namespace sightline
{
namespace
{
constexpr double kEarthRadiusKm = 6371.0;
} // namespace

const std::vector<EarthLayer>& premLayers()
{
  static const std::vector<EarthLayer> layers = {
    { "inner core", 0.0, 1221.5, { 13.0885, 0.0, -8.8381, 0.0 } },
    { "outer core", 1221.5, 3480.0, { 12.5815, -1.2638, -3.6426, -5.5281 } },
    { "lower mantle", 3480.0, 5701.0, { 7.9565, -6.4761, 5.5283, -3.0807 } },
    { "transition zone 1", 5701.0, 5771.0, { 5.3197, -1.4836, 0.0, 0.0 } },
    { "transition zone 2", 5771.0, 5971.0, { 11.2494, -8.0298, 0.0, 0.0 } },
    { "transition zone 3", 5971.0, 6151.0, { 7.1089, -3.8045, 0.0, 0.0 } },
    { "low-velocity zone and lid", 6151.0, 6346.6, { 2.6910, 0.6924, 0.0, 0.0 } },
    { "lower crust", 6346.6, 6356.0, { 2.900, 0.0, 0.0, 0.0 } },
    { "upper crust", 6356.0, 6368.0, { 2.600, 0.0, 0.0, 0.0 } },
    { "ocean", 6368.0, 6371.0, { 1.020, 0.0, 0.0, 0.0 } },
  };
  return layers;
}

double premDensity(double radiusKm)
{
  if (!(radiusKm >= 0.0 && radiusKm <= kEarthRadiusKm))
    throw std::invalid_argument("sightline::premDensity: radius " + std::to_string(radiusKm) +
      " km is outside [0, 6371]");
  const double x = radiusKm / kEarthRadiusKm;
  for (const EarthLayer& layer : premLayers())
    if (radiusKm < layer.outerRadiusKm || layer.outerRadiusKm == kEarthRadiusKm)
    {
      const double* c = layer.density;
      return c[0] + x * (c[1] + x * (c[2] + x * c[3]));
    }
  return 0.0; // not reached
}

double premMass(double radiusKm)
{
  if (!(radiusKm >= 0.0 && radiusKm <= kEarthRadiusKm))
    throw std::invalid_argument("sightline::premMass: radius " + std::to_string(radiusKm) +
      " km is outside [0, 6371]");
  // 4 pi R^3 integral of x^2 rho(x) dx, per layer, in closed form; g/cm^3 km^3 = 1e12 kg.
  double mass = 0.0;
  for (const EarthLayer& layer : premLayers())
  {
    const double a = layer.innerRadiusKm / kEarthRadiusKm;
    const double b = std::min(radiusKm, layer.outerRadiusKm) / kEarthRadiusKm;
    if (!(b > a))
      break;
    auto antiderivative = [&](double x)
    {
      const double* c = layer.density;
      return c[0] * x * x * x / 3.0 + c[1] * std::pow(x, 4) / 4.0 + c[2] * std::pow(x, 5) / 5.0 +
        c[3] * std::pow(x, 6) / 6.0;
    };
    mass += antiderivative(b) - antiderivative(a);
  }
  return 4.0 * kPi * std::pow(kEarthRadiusKm, 3) * mass * 1e12;
}
} // namespace sightline
