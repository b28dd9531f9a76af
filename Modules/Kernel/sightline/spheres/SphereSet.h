// SPDX-License-Identifier: BSD-3-Clause
// Analytic spheres (centre + radius), intersected exactly. The first primitive: small, but it
// exercises every layer, and the generalized tubes reuse it for their joints.
#pragma once

#include "sightline/core/Geometry.h"

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

namespace sightline
{
/// Exact ray-sphere intersection: the smallest root of |o + t d - c|^2 = r^2 in (tnear, tfar).
/// A ray starting inside the sphere hits the far side. Uses the cancellation-free discriminant
/// (the distance of the centre from the ray line, not b^2 - c), so grazing rays and rays from
/// far away keep their accuracy. `direction` need not be unit length.
bool intersectSphere(const vec3& center, float radius, const Ray& ray, SurfaceHit& hit);
/// The same in double, in the sphere's frame (ray origin minus centre): what SphereSet uses, so
/// that precision is relative to the radius wherever the sphere is. Its normal has length radius.
inline bool intersectSphere(const dvec3& center, double radius, const DoubleRay& ray, SurfaceHit& hit);

namespace detail
{
/// The root of |f + t d|^2 = r^2 (f = ray origin - centre) that a ray from tnear meets first, in
/// the arithmetic T: the near one, or the far one from inside.
template <class T, class Vec>
inline bool firstSphereRoot(const Vec& f, const Vec& d, T radius, T tnear, T tfar, T& t)
{
  // Solve a t^2 - 2 b t + c = 0. The discriminant b^2 - a c equals a (r^2 - |f - (f.d/a) d|^2):
  // computing it from the ray's distance to the centre avoids the cancellation of b^2 - a c
  // when the origin is far away (Haines et al., Ray Tracing Gems 7).
  const T a = glm::dot(d, d);
  const T inverseA = T(1) / a; // off the critical path: it overlaps the dot products
  const T b = -glm::dot(f, d);
  const Vec offLine = f + (b * inverseA) * d;
  const T r2 = radius * radius;
  const T discriminant = a * (r2 - glm::dot(offLine, offLine));
  if (!(discriminant >= T(0)))
    return false;
  const T c = glm::dot(f, f) - r2;
  // Citardauq pair: q has no cancellation, and t0 = c / q, t1 = q / a.
  const T q = b + std::copysign(std::sqrt(discriminant), b);
  T t0 = c / q;
  T t1 = q * inverseA;
  if (q == T(0)) // ray through the centre, tangent at the origin: both roots zero
    t0 = t1 = T(0);
  if (t0 > t1)
    std::swap(t0, t1);
  t = t0;
  if (!(t > tnear))
    t = t1; // origin inside the sphere (or the near root is behind): the far side
  return t > tnear && t < tfar;
}
} // namespace detail

inline bool intersectSphere(const dvec3& center, double radius, const DoubleRay& ray, SurfaceHit& hit)
{
  // In the sphere's frame; the renderer normalises the normal.
  const dvec3 f = ray.origin - center;
  double t;
  if (!detail::firstSphereRoot(f, ray.direction, radius, ray.tnear, ray.tfar, t))
    return false;
  hit.t = t;
  hit.normal = vec3(f + t * ray.direction);
  return true;
}

class SphereSet : public UserGeometry<SphereSet>
{
public:
  /// One sphere per centre. `radii` holds one radius per sphere, or is empty to give every
  /// sphere `defaultRadius`. `colors` (RGBA8) is empty or one per sphere.
  /// Spheres with a non-finite centre, a non-finite radius or a radius <= 0 are dropped and
  /// reported in report(); a size mismatch throws std::invalid_argument.
  SphereSet(const std::vector<vec3>& centers, const std::vector<float>& radii,
    float defaultRadius = 1.0f, const std::vector<std::uint32_t>& colors = {});
  /// The same with the centres given relative to `origin`, kept in double: spheres far from
  /// the world origin keep float precision relative to the set's extent, not to that distance.
  SphereSet(const dvec3& origin, const std::vector<vec3>& centers, const std::vector<float>& radii,
    float defaultRadius = 1.0f, const std::vector<std::uint32_t>& colors = {});

  std::size_t size() const override { return Spheres.size(); }
  bool hasPrimitiveColors() const override { return !Colors.empty(); }
  vec3 primitiveColor(unsigned primitive) const override;
  std::size_t memoryBytes() const override;

  Box3 bounds(unsigned primitive) const;
  bool intersect(unsigned primitive, const DoubleRay& ray, SurfaceHit& hit) const
  {
    const vec4& s = Spheres[primitive];
    return intersectSphere(Origin + dvec3(vec3(s)), s.w, ray, hit);
  }

  /// Bounds of all kept spheres.
  Box3 bounds() const override;
  const ValidationReport& report() const { return Report; }
  /// Index in the input of each kept sphere (for picking and colour lookups).
  const std::vector<std::uint32_t>& sourceIndex() const { return SourceIndex; }
  /// Centres (relative to origin()) and radii.
  const std::vector<vec4>& spheres() const { return Spheres; }
  const dvec3& origin() const { return Origin; }

private:
  dvec3 Origin{ 0.0 };
  std::vector<vec4> Spheres; ///< xyz centre relative to Origin, w radius
  std::vector<std::uint32_t> Colors;
  std::vector<std::uint32_t> SourceIndex;
  ValidationReport Report;
};
} // namespace sightline
