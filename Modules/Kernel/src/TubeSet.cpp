#include "sightline/TubeSet.h"

#include "sightline/TubeLink.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
TubeSet::TubeSet(const std::vector<vec3>& points, const std::vector<float>& radii,
  const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors)
{
  const std::size_t n = points.size();
  if (radii.size() != n || predecessors.size() != n)
    throw std::invalid_argument("sightline::TubeSet: " + std::to_string(radii.size()) + " radii and " +
      std::to_string(predecessors.size()) + " predecessors for " + std::to_string(n) + " points");
  if (!colors.empty() && colors.size() != n)
    throw std::invalid_argument("sightline::TubeSet: " + std::to_string(colors.size()) +
      " colours for " + std::to_string(n) + " points");
  for (std::size_t i = 0; i < n; ++i)
    if (predecessors[i] < -1 || predecessors[i] >= std::int64_t(n))
      throw std::invalid_argument("sightline::TubeSet: point " + std::to_string(i) +
        " has the predecessor " + std::to_string(predecessors[i]) + ", outside [-1, " +
        std::to_string(n - 1) + "]");
  // Cycles: follow predecessors; a walk that meets a point of its own walk is a cycle.
  {
    std::vector<std::uint8_t> state(n, 0); // 0 unvisited, 1 on the current walk, 2 done
    std::vector<std::size_t> walk;
    for (std::size_t start = 0; start < n; ++start)
    {
      walk.clear();
      for (std::size_t i = start; state[i] != 2;)
      {
        if (state[i] == 1)
          throw std::invalid_argument("sightline::TubeSet: the links through point " +
            std::to_string(i) + " form a cycle");
        state[i] = 1;
        walk.push_back(i);
        if (predecessors[i] < 0)
          break;
        i = std::size_t(predecessors[i]);
      }
      for (std::size_t w : walk)
        state[w] = 2;
    }
  }
  auto usable = [&](std::size_t i)
  { return isFinite(points[i]) && std::isfinite(radii[i]) && radii[i] >= 0.0f; };
  std::size_t dropped = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!usable(i))
    {
      if (dropped++ == 0)
        Report.reasons.push_back("point " + std::to_string(i) +
          " has a non-finite position or a negative or non-finite radius (first of the points "
          "dropped for this reason, with their links)");
      continue;
    }
    Link link;
    link.end = points[i];
    link.endRadius = radii[i];
    link.start = points[i];
    link.startRadius = radii[i];
    const std::int64_t p = predecessors[i];
    if (p >= 0 && usable(std::size_t(p)))
    {
      link.start = points[std::size_t(p)];
      link.startRadius = radii[std::size_t(p)];
      link.hasStart = true;
    }
    Links.push_back(link);
    SourceIndex.push_back(std::uint32_t(i));
    if (!colors.empty())
      Colors.push_back(colors[i]);
    AllBounds.extend(bounds(unsigned(Links.size() - 1)));
  }
  Report.rejected = dropped;
}

Box3 TubeSet::bounds(unsigned primitive) const
{
  // The convex hull of two spheres lies in the union of their boxes.
  const Link& l = Links[primitive];
  Box3 box;
  box.extend(l.end - vec3(l.endRadius));
  box.extend(l.end + vec3(l.endRadius));
  box.extend(l.start - vec3(l.startRadius));
  box.extend(l.start + vec3(l.startRadius));
  const vec3 pad = 1e-6f * (glm::abs(box.lower) + glm::abs(box.upper) + vec3(1e-30f));
  box.lower -= pad;
  box.upper += pad;
  return box;
}

bool TubeSet::intersect(unsigned primitive, const Ray& ray, SurfaceHit& hit) const
{
  // The nearest surface of the end sphere and the stump in (tnear, tfar): an interval's entry,
  // or its exit when the ray starts inside.
  const Link& l = Links[primitive];
  const dvec3 o(ray.origin), d(ray.direction);
  const double tmin = ray.tnear, tmax = std::min(double(ray.tfar), 1e300);
  double best = tmax;
  dvec3 normal(0.0);
  bool found = false;
  auto consider = [&](double t0, double t1, auto normalAt)
  {
    const double t = t0 > tmin ? t0 : t1;
    if (t > tmin && t < best)
    {
      best = t;
      normal = normalAt(o + t * d);
      found = true;
    }
  };
  double t0, t1;
  const dvec3 end(l.end);
  if (sphereInterval(end, l.endRadius, o, d, -1e300, 1e300, t0, t1))
    consider(t0, t1, [&](const dvec3& p) { return p - end; });
  if (l.hasStart)
  {
    const ConeStump stump = makeConeStump(dvec3(l.start), l.startRadius, end, l.endRadius);
    if (coneStumpInterval(stump, o, d, -1e300, 1e300, t0, t1))
      consider(t0, t1, [&](const dvec3& p) { return coneStumpNormal(stump, p); });
  }
  if (!found || !(best < tmax))
    return false;
  hit.t = float(best);
  hit.normal = vec3(normal);
  return true;
}

vec3 TubeSet::primitiveColor(unsigned primitive) const
{
  const std::uint32_t c = Colors[primitive];
  return vec3(float(c & 0xffu), float((c >> 8) & 0xffu), float((c >> 16) & 0xffu)) / 255.0f;
}

std::size_t TubeSet::memoryBytes() const
{
  return Links.capacity() * sizeof(Link) + Colors.capacity() * sizeof(std::uint32_t) +
    SourceIndex.capacity() * sizeof(std::uint32_t);
}
} // namespace sightline
