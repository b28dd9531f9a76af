// Small math vocabulary shared by the kernel: GLM vectors, rays and boxes.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <limits>

namespace sightline
{
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
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

inline bool isFinite(const vec3& v)
{
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
} // namespace sightline
