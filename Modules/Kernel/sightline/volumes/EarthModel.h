// SPDX-License-Identifier: BSD-3-Clause
// The Preliminary Reference Earth Model (PREM; A. M. Dziewonski and D. L. Anderson, "Preliminary
// reference Earth model", Physics of the Earth and Planetary Interiors 25 (1981) 297-356, Table
// 1): density as a piecewise cubic in the normalised radius x = r / 6371 km, one polynomial per
// layer, discontinuous at the layer boundaries. Used to build layered-Earth spherical grids.
#pragma once

#include <string>
#include <vector>

namespace sightline
{
struct EarthLayer
{
  std::string name;
  double innerRadiusKm, outerRadiusKm;
  double density[4]; ///< g/cm^3: c0 + c1 x + c2 x^2 + c3 x^3, x = r / 6371 km
};

/// PREM's density layers from the centre out (the 1 s reference period's isotropic values).
const std::vector<EarthLayer>& premLayers();

/// PREM density (g/cm^3) at a radius in km, 0 <= r <= 6371; at a boundary, the outer layer's.
/// Throws std::invalid_argument outside [0, 6371] or for NaN.
double premDensity(double radiusKm);

/// Mass (kg) of PREM inside a radius (km): the exact integral of 4 pi r^2 rho(r).
double premMass(double radiusKm);
} // namespace sightline
