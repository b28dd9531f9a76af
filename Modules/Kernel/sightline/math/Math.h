// SPDX-License-Identifier: BSD-3-Clause
// Small math vocabulary shared by the kernel: GLM vectors, rays and boxes.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace sightline
{
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using dvec2 = glm::dvec2;
using dvec3 = glm::dvec3;
using dvec4 = glm::dvec4;
using dmat3 = glm::dmat3;
using dmat4 = glm::dmat4;

constexpr float kInfinity = std::numeric_limits<float>::infinity();

/// pi in the arithmetic of T (long double keeps the extra digits where a kernel needs them).
template <typename T>
constexpr T kPiOf = T(3.141592653589793238462643383279502884L);
constexpr double kPi = kPiOf<double>;
constexpr double kTwoPi = 2.0 * kPi;

/// A ray o + t d for t in [tnear, tfar]. Directions handed out by the kernel are unit length,
/// so t is a world-space distance.
struct Ray
{
  vec3 origin{ 0.0f };
  vec3 direction{ 0.0f, 0.0f, -1.0f };
  float tnear = 0.0f;
  float tfar = kInfinity;
};

/// The same ray in double precision: what primary, shadow and volume rays are generated in and
/// what primitives intersect, so that a ray far from the world origin keeps the precision it
/// has relative to the primitives it meets (float would round its origin by 2^-24 |origin|).
/// Converts implicitly from Ray (the float ray's exact value).
struct DoubleRay
{
  dvec3 origin{ 0.0 };
  dvec3 direction{ 0.0, 0.0, -1.0 };
  double tnear = 0.0;
  double tfar = std::numeric_limits<double>::infinity();

  DoubleRay() = default;
  DoubleRay(const dvec3& o, const dvec3& d, double near, double far)
    : origin(o), direction(d), tnear(near), tfar(far)
  {
  }
  DoubleRay(const Ray& ray) // NOLINT(google-explicit-constructor): every float ray is exact in double
    : origin(ray.origin), direction(ray.direction), tnear(ray.tnear), tfar(ray.tfar)
  {
  }
  dvec3 at(double t) const { return origin + t * direction; }
  /// The float rounding (for Embree's traversal and callers of the float API); the interval
  /// only widens, so no point of the double ray's segment is cut off.
  Ray rounded() const;
};

/// Axis-aligned box; an empty box has lower > upper.
struct Box3
{
  vec3 lower{ kInfinity };
  vec3 upper{ -kInfinity };

  void extend(const vec3& p)
  {
    lower = glm::min(lower, p);
    upper = glm::max(upper, p);
  }
  void extend(const Box3& b)
  {
    lower = glm::min(lower, b.lower);
    upper = glm::max(upper, b.upper);
  }
  bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
};

/// The smallest float >= x (largest <= x): conservative bounds and ray intervals. Inline bit
/// steps rather than std::nextafter, a library call, since rays are rounded once per trace.
inline float floatAtLeast(double x)
{
  float f = float(x);
  if (double(f) < x) // f is finite here: x > f >= -FLT_MAX
  {
    if (f == 0.0f)
      return std::numeric_limits<float>::denorm_min();
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    bits = f > 0.0f ? bits + 1 : bits - 1;
    std::memcpy(&f, &bits, sizeof f);
  }
  return f;
}
inline float floatAtMost(double x)
{
  return -floatAtLeast(-x);
}

inline Ray DoubleRay::rounded() const
{
  Ray ray;
  ray.origin = vec3(origin);
  ray.direction = vec3(direction);
  ray.tnear = floatAtMost(tnear);
  ray.tfar = floatAtLeast(tfar);
  return ray;
}

/// Narrows [tnear, tfar] to where origin + t direction lies in the box [lower, upper] (slab
/// test; infinite faces allowed). Returns false when nothing of the interval is left. A ray
/// lying in a face plane belongs to the box above that plane only, so of two boxes sharing a
/// face exactly one takes it.
inline bool clipToBox(const dvec3& origin, const dvec3& direction, const dvec3& lower,
  const dvec3& upper, double& tnear, double& tfar)
{
  for (int axis = 0; axis < 3; ++axis)
  {
    const double o = origin[axis], d = direction[axis];
    if (d == 0.0)
    {
      if (o < lower[axis] || o >= upper[axis])
        return false;
      continue;
    }
    double t0 = (lower[axis] - o) / d, t1 = (upper[axis] - o) / d;
    if (t0 > t1)
      std::swap(t0, t1);
    tnear = std::max(tnear, t0);
    tfar = std::min(tfar, t1);
  }
  return tnear <= tfar;
}

inline bool isFinite(const vec3& v)
{
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
} // namespace sightline
