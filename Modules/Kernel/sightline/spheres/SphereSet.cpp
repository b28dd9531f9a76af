#include "sightline/spheres/SphereSet.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sightline
{
bool intersectSphere(const vec3& center, float radius, const Ray& ray, SurfaceHit& hit)
{
  // Solve a t^2 - 2 b t + c = 0 with f = o - c. The discriminant b^2 - a c equals
  // a (r^2 - |f - (f.d/a) d|^2): computing it from the ray's distance to the centre avoids
  // the cancellation of b^2 - a c when the origin is far away (Haines et al., Ray Tracing Gems 7).
  const vec3 f = ray.origin - center;
  const float a = glm::dot(ray.direction, ray.direction);
  const float b = -glm::dot(f, ray.direction);
  const vec3 offLine = f + (b / a) * ray.direction;
  const float r2 = radius * radius;
  const float discriminant = a * (r2 - glm::dot(offLine, offLine));
  if (!(discriminant >= 0.0f))
    return false;
  const float c = glm::dot(f, f) - r2;
  // Citardauq pair: q has no cancellation, and t0 = c / q, t1 = q / a.
  const float q = b + std::copysign(std::sqrt(discriminant), b);
  float t0 = c / q;
  float t1 = q / a;
  if (q == 0.0f) // ray through the centre, tangent at the origin: both roots zero
    t0 = t1 = 0.0f;
  if (t0 > t1)
    std::swap(t0, t1);
  float t = t0;
  if (!(t > ray.tnear))
    t = t1; // origin inside the sphere (or the near root is behind): the far side
  if (!(t > ray.tnear) || !(t < ray.tfar))
    return false;
  hit.t = t;
  hit.normal = (ray.origin + t * ray.direction - center) / radius;
  return true;
}

bool intersectSphere(const dvec3& center, double radius, const DoubleRay& ray, SurfaceHit& hit)
{
  // The float version's cancellation-free solution, in double and in the sphere's frame; one
  // division less (1/a overlaps the dot products), and the normal left unnormalised.
  const dvec3 f = ray.origin - center;
  const double a = glm::dot(ray.direction, ray.direction);
  const double inverseA = 1.0 / a;
  const double b = -glm::dot(f, ray.direction);
  const dvec3 offLine = f + (b * inverseA) * ray.direction;
  const double r2 = radius * radius;
  const double discriminant = a * (r2 - glm::dot(offLine, offLine));
  if (!(discriminant >= 0.0))
    return false;
  const double c = glm::dot(f, f) - r2;
  const double q = b + std::copysign(std::sqrt(discriminant), b);
  double t0 = c / q;
  double t1 = q * inverseA;
  if (q == 0.0)
    t0 = t1 = 0.0;
  if (t0 > t1)
    std::swap(t0, t1);
  double t = t0;
  if (!(t > ray.tnear))
    t = t1;
  if (!(t > ray.tnear) || !(t < ray.tfar))
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
