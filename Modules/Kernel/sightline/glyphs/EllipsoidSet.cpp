// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/glyphs/EllipsoidSet.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
EllipsoidSet::EllipsoidSet(const std::vector<vec3>& centers, const std::vector<dmat3>& axes,
  const std::vector<std::uint32_t>& colors)
{
  if (axes.size() != centers.size())
    throw std::invalid_argument("sightline::EllipsoidSet: " + std::to_string(axes.size()) +
      " axis matrices for " + std::to_string(centers.size()) + " centres");
  if (!colors.empty() && colors.size() != centers.size())
    throw std::invalid_argument("sightline::EllipsoidSet: " + std::to_string(colors.size()) +
      " colours for " + std::to_string(centers.size()) + " centres");
  std::size_t bad = 0, flat = 0;
  for (std::size_t i = 0; i < centers.size(); ++i)
  {
    const dmat3& m = axes[i];
    bool finite = isFinite(centers[i]);
    for (int c = 0; c < 3 && finite; ++c)
      finite = std::isfinite(m[c].x) && std::isfinite(m[c].y) && std::isfinite(m[c].z);
    if (!finite)
    {
      if (bad++ == 0)
        Report.reasons.push_back("ellipsoid " + std::to_string(i) +
          " has a non-finite centre or axis (first of the ellipsoids skipped for this reason)");
      continue;
    }
    // |det| against the product of the column lengths bounds the smallest singular value.
    const double scale = glm::length(m[0]) * glm::length(m[1]) * glm::length(m[2]);
    if (!(std::abs(glm::determinant(m)) > 1e-9 * scale))
    {
      if (flat++ == 0)
        Report.reasons.push_back("ellipsoid " + std::to_string(i) +
          " has a singular axis matrix (first of the ellipsoids skipped for this reason)");
      continue;
    }
    Ellipsoid e;
    e.center = dvec3(centers[i]);
    e.inverse = glm::inverse(m);
    for (int row = 0; row < 3; ++row)
      e.halfExtent[row] = float(std::sqrt(m[0][row] * m[0][row] + m[1][row] * m[1][row] + m[2][row] * m[2][row]));
    Ellipsoids.push_back(e);
    SourceIndex.push_back(std::uint32_t(i));
    if (!colors.empty())
      Colors.push_back(colors[i]);
    AllBounds.extend(bounds(unsigned(Ellipsoids.size() - 1)));
  }
  Report.rejected = bad + flat;
}

Box3 EllipsoidSet::bounds(unsigned primitive) const
{
  const Ellipsoid& e = Ellipsoids[primitive];
  // One part in 10^6 of padding absorbs float rounding of the box.
  const vec3 h = e.halfExtent * 1.000001f;
  return Box3{ vec3(e.center - dvec3(h)), vec3(e.center + dvec3(h)) };
}

bool EllipsoidSet::intersect(unsigned primitive, const DoubleRay& ray, SurfaceHit& hit) const
{
  // In the unit sphere's frame the ray is o' + t d' with the same t; solve |o' + t d'|^2 = 1
  // with the cancellation-free discriminant (the line's distance from the centre).
  const Ellipsoid& e = Ellipsoids[primitive];
  const dvec3 o = e.inverse * (dvec3(ray.origin) - e.center);
  const dvec3 d = e.inverse * dvec3(ray.direction);
  const double a = glm::dot(d, d);
  const double b = -glm::dot(o, d);
  const dvec3 offLine = o + (b / a) * d;
  const double discriminant = a * (1.0 - glm::dot(offLine, offLine));
  if (!(discriminant >= 0.0))
    return false;
  const double c = glm::dot(o, o) - 1.0;
  const double q = b + std::copysign(std::sqrt(discriminant), b);
  double t0 = q != 0.0 ? c / q : 0.0, t1 = q / a;
  if (t0 > t1)
    std::swap(t0, t1);
  double t = t0 > double(ray.tnear) ? t0 : t1;
  if (!(t > double(ray.tnear)) || !(t < double(ray.tfar)))
    return false;
  hit.t = t;
  // The sphere's normal u maps to M^-T u.
  hit.normal = vec3(glm::transpose(e.inverse) * (o + t * d));
  return true;
}

vec3 EllipsoidSet::primitiveColor(unsigned primitive) const
{
  const std::uint32_t c = Colors[primitive];
  return vec3(float(c & 0xffu), float((c >> 8) & 0xffu), float((c >> 16) & 0xffu)) / 255.0f;
}

EllipsoidSet::EllipsoidSet(const dvec3& origin, const std::vector<vec3>& centers,
  const std::vector<dmat3>& axes, const std::vector<std::uint32_t>& colors)
  : EllipsoidSet(centers, axes, colors)
{
  if (!(std::isfinite(origin.x) && std::isfinite(origin.y) && std::isfinite(origin.z)))
    throw std::invalid_argument("sightline::EllipsoidSet: the origin must be finite");
  // Centres are double already: move them, and the boxes with them.
  AllBounds = Box3{};
  for (unsigned i = 0; i < Ellipsoids.size(); ++i)
  {
    Ellipsoids[i].center += origin;
    AllBounds.extend(bounds(i));
  }
}

std::size_t EllipsoidSet::memoryBytes() const
{
  return Ellipsoids.capacity() * sizeof(Ellipsoid) + Colors.capacity() * sizeof(std::uint32_t) +
    SourceIndex.capacity() * sizeof(std::uint32_t);
}
} // namespace sightline
