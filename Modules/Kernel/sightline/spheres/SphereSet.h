// SPDX-License-Identifier: BSD-3-Clause
// Analytic spheres (centre + radius), intersected exactly. The first primitive: small, but it
// exercises every layer, and the generalized tubes reuse it for their joints.
#pragma once

#include "sightline/core/Geometry.h"

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
bool intersectSphere(const dvec3& center, double radius, const DoubleRay& ray, SurfaceHit& hit);

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
