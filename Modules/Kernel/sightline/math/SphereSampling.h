// SPDX-License-Identifier: BSD-3-Clause
// Spherical Fibonacci directions, the kernel's one way to sample the sphere (internal header).
#pragma once

#include "sightline/math/Math.h"

#include <algorithm>
#include <cmath>

namespace sightline
{
namespace detail
{
/// Direction `index` of `count` spherical Fibonacci points over the whole sphere, or over the
/// upper hemisphere only (z > 0), enough for point-symmetric functions such as SH glyphs.
inline dvec3 fibonacciDirection(int index, int count, bool hemisphere = false)
{
  const double golden = 4.0 * kPi / (std::sqrt(5.0) + 1.0);
  const double z = 1.0 - (2.0 * index + 1.0) / (hemisphere ? 2.0 * count : double(count));
  const double radius = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = golden * index;
  return dvec3(radius * std::cos(phi), radius * std::sin(phi), z);
}
} // namespace detail
} // namespace sightline
