// SPDX-License-Identifier: BSD-3-Clause
// Analytic fields on spherical domains with exact ray integrals: the thesis' test cases
// (Chapter 6: radial step functions such as chi_0.5 = 2 for r <= 1/2, 1 for r <= 1, and the
// field r^2 inside a ball), used by the tests, the benchmark and the VTK source that samples
// fields onto grids. Exact integrals come from sphere chords alone, so they are an independent
// reference for the cell traversal.
#pragma once

#include "sightline/math/Math.h"
#include "sightline/volumes/SphericalGrid.h"

#include <functional>
#include <vector>

namespace sightline
{
/// A field of the radius alone that is constant between shells: `values[i]` for r in
/// (radii[i-1], radii[i]] (radii[-1] = 0, the first value includes the centre), 0 beyond the
/// last radius.
struct RadialStepField
{
  std::vector<double> radii;  ///< strictly increasing, > 0
  std::vector<double> values; ///< one per radius

  /// The thesis' chi_0.5: 2 for r <= 1/2, 1 for 1/2 < r <= 1, 0 beyond.
  static RadialStepField chiHalf();
  /// Throws std::invalid_argument for sizes that differ, an empty field, NaN, radii not
  /// strictly increasing or not positive.
  void validate() const;
  double operator()(double r) const;
  /// Exact integral of the field along origin + t direction, t in [t0, t1], measured in
  /// distance (so scaled by |direction|).
  double rayIntegral(const dvec3& origin, const dvec3& direction, double t0, double t1) const;
};

/// r^2 inside a ball of radius `outerRadius`, 0 outside.
struct RadiusSquaredField
{
  double outerRadius = 1.0;

  double operator()(double r) const { return r <= outerRadius ? r * r : 0.0; }
  /// Exact integral along the ray, as RadialStepField::rayIntegral. Through the centre of the
  /// unit ball at distance b from the centre it is 2/3 sqrt(1 - b^2) (1 + 2 b^2) (thesis, 6.3).
  double rayIntegral(const dvec3& origin, const dvec3& direction, double t0, double t1) const;
};

/// A field given in spherical coordinates: value(r, theta, phi).
using SphericalFunction = std::function<double(double r, double theta, double phi)>;

/// Cell values (ordered as SphericalGrid::cellIndex) sampled at each cell's coordinate midpoint.
std::vector<double> sampleCellMidpoints(const SphericalGrid& grid, const SphericalFunction& field);
} // namespace sightline
