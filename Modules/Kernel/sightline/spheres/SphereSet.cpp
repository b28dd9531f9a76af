// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/spheres/SphereSet.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sightline
{
namespace
{
/// The root of |f + t d|^2 = r^2 (f = ray origin - centre) that a ray from tnear meets first, in
/// the arithmetic T: the near one, or the far one from inside.
template <class T, class Vec>
bool firstSphereRoot(const Vec& f, const Vec& d, T radius, T tnear, T tfar, T& t)
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
} // namespace

bool intersectSphere(const vec3& center, float radius, const Ray& ray, SurfaceHit& hit)
{
  float t;
  if (!firstSphereRoot(ray.origin - center, ray.direction, radius, ray.tnear, ray.tfar, t))
    return false;
  hit.t = t;
  hit.normal = (ray.origin + t * ray.direction - center) / radius;
  return true;
}

bool intersectSphere(const dvec3& center, double radius, const DoubleRay& ray, SurfaceHit& hit)
{
  // In the sphere's frame; the renderer normalises the normal.
  const dvec3 f = ray.origin - center;
  double t;
  if (!firstSphereRoot(f, ray.direction, radius, ray.tnear, ray.tfar, t))
    return false;
  hit.t = t;
  hit.normal = vec3(f + t * ray.direction);
  return true;
}

SphereSet::SphereSet(const dvec3& origin, const std::vector<vec3>& centers,
  const std::vector<float>& radii, float defaultRadius, const std::vector<std::uint32_t>& colors)
  : SphereSet(centers, radii, defaultRadius, colors)
{
  if (!(std::isfinite(origin.x) && std::isfinite(origin.y) && std::isfinite(origin.z)))
    throw std::invalid_argument("sightline::SphereSet: the origin must be finite");
  Origin = origin;
}

SphereSet::SphereSet(const std::vector<vec3>& centers, const std::vector<float>& radii,
  float defaultRadius, const std::vector<std::uint32_t>& colors)
{
  if (!radii.empty() && radii.size() != centers.size())
    throw std::invalid_argument("sightline::SphereSet: " + std::to_string(radii.size()) +
      " radii for " + std::to_string(centers.size()) + " centres");
  if (!colors.empty() && colors.size() != centers.size())
    throw std::invalid_argument("sightline::SphereSet: " + std::to_string(colors.size()) +
      " colours for " + std::to_string(centers.size()) + " centres");
  if (radii.empty() && !(std::isfinite(defaultRadius) && defaultRadius > 0.0f))
    throw std::invalid_argument("sightline::SphereSet: the default radius must be positive and "
                                "finite, got " + std::to_string(defaultRadius));

  std::size_t badCenter = 0, badRadius = 0;
  std::size_t firstBadCenter = 0, firstBadRadius = 0;
  Spheres.reserve(centers.size());
  SourceIndex.reserve(centers.size());
  if (!colors.empty())
    Colors.reserve(centers.size());
  for (std::size_t i = 0; i < centers.size(); ++i)
  {
    const float r = radii.empty() ? defaultRadius : radii[i];
    if (!isFinite(centers[i]))
    {
      if (badCenter++ == 0)
        firstBadCenter = i;
      continue;
    }
    if (!(std::isfinite(r) && r > 0.0f))
    {
      if (badRadius++ == 0)
        firstBadRadius = i;
      continue;
    }
    Spheres.emplace_back(centers[i], r);
    SourceIndex.push_back(static_cast<std::uint32_t>(i));
    if (!colors.empty())
      Colors.push_back(colors[i]);
  }
  Report.rejected = badCenter + badRadius;
  if (badCenter)
  {
    std::ostringstream s;
    s << badCenter << " sphere(s) with a NaN or infinite centre skipped (first: point "
      << firstBadCenter << ")";
    Report.reasons.push_back(s.str());
  }
  if (badRadius)
  {
    std::ostringstream s;
    s << badRadius << " sphere(s) with a radius that is not positive and finite skipped (first: "
      << "point " << firstBadRadius << ", radius " << radii[firstBadRadius] << ")";
    Report.reasons.push_back(s.str());
  }
}

vec3 SphereSet::primitiveColor(unsigned primitive) const
{
  const std::uint32_t c = Colors[primitive];
  return vec3(float(c & 0xffu), float((c >> 8) & 0xffu), float((c >> 16) & 0xffu)) / 255.0f;
}

std::size_t SphereSet::memoryBytes() const
{
  return Spheres.capacity() * sizeof(vec4) + Colors.capacity() * sizeof(std::uint32_t) +
    SourceIndex.capacity() * sizeof(std::uint32_t);
}

Box3 SphereSet::bounds(unsigned primitive) const
{
  const vec4& s = Spheres[primitive];
  const dvec3 center = Origin + dvec3(vec3(s));
  return { vec3(center - double(s.w)), vec3(center + double(s.w)) };
}

Box3 SphereSet::bounds() const
{
  Box3 box;
  for (unsigned i = 0; i < Spheres.size(); ++i)
    box.extend(bounds(i));
  return box;
}
} // namespace sightline
