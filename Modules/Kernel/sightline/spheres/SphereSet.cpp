// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/spheres/SphereSet.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sightline
{

bool intersectSphere(const vec3& center, float radius, const Ray& ray, SurfaceHit& hit)
{
  float t;
  if (!detail::firstSphereRoot(ray.origin - center, ray.direction, radius, ray.tnear, ray.tfar, t))
    return false;
  hit.t = t;
  hit.normal = (ray.origin + t * ray.direction - center) / radius;
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
