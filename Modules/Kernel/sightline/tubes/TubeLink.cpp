// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/tubes/TubeLink.h"

#include <algorithm>
#include <cmath>

namespace sightline
{
namespace
{
/// Real roots of a t^2 + b t + c (a may be 0), ascending; returns how many.
int quadraticRoots(double a, double b, double c, double roots[2])
{
  const double scale = std::max({ std::abs(a), std::abs(b), std::abs(c) });
  if (scale == 0.0)
    return 0;
  if (std::abs(a) <= 1e-14 * scale)
  {
    if (b == 0.0)
      return 0;
    roots[0] = -c / b;
    return 1;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0)
    return 0;
  // Citardauq pair: no cancellation.
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double r0 = q / a, r1 = q != 0.0 ? c / q : r0;
  if (r0 > r1)
    std::swap(r0, r1);
  roots[0] = r0;
  roots[1] = r1;
  return 2;
}
} // namespace

ConeStump makeConeStump(const dvec3& p1, double r1, const dvec3& p2, double r2)
{
  ConeStump stump;
  const dvec3 d = p2 - p1;
  stump.length = glm::length(d);
  if (!(stump.length > 0.0))
    return stump;
  stump.slope = (r2 - r1) / stump.length;
  if (!(std::abs(stump.slope) < 1.0))
    return stump; // one sphere holds the other
  stump.base = p1;
  stump.axis = d / stump.length;
  stump.cosine = std::sqrt((1.0 - stump.slope) * (1.0 + stump.slope));
  stump.radius1 = r1;
  stump.u1 = -stump.slope * r1;
  stump.u2 = stump.length - stump.slope * r2;
  stump.valid = true;
  return stump;
}

bool coneStumpInterval(const ConeStump& k, const dvec3& o, const dvec3& d, double tmin,
  double tmax, double& t0, double& t1)
{
  if (!k.valid)
    return false;
  // Between the tangent planes: u(t) = u0 + t du in [u1, u2].
  const dvec3 e = o - k.base;
  const double u0 = glm::dot(e, k.axis), du = glm::dot(d, k.axis);
  double a = tmin, b = tmax;
  if (du != 0.0)
  {
    double ta = (k.u1 - u0) / du, tb = (k.u2 - u0) / du;
    if (ta > tb)
      std::swap(ta, tb);
    a = std::max(a, ta);
    b = std::min(b, tb);
  }
  else if (u0 < k.u1 || u0 > k.u2)
    return false;
  if (!(a <= b))
    return false;
  // Inside the cone: F(t) = c^2 (|e + t d|^2 - u^2) - (r1 + s u)^2 <= 0, a quadratic in t.
  const double c2 = k.cosine * k.cosine, s = k.slope;
  const double w0 = k.radius1 + s * u0;
  const double qa = c2 * (glm::dot(d, d) - du * du) - s * s * du * du;
  const double qb = 2.0 * (c2 * (glm::dot(e, d) - u0 * du) - s * du * w0);
  const double qc = c2 * (glm::dot(e, e) - u0 * u0) - w0 * w0;
  auto inside = [&](double t) { return (qa * t + qb) * t + qc <= 0.0; };
  double roots[2];
  const int count = quadraticRoots(qa, qb, qc, roots);
  // Candidate breakpoints inside [a, b]; the stump is convex, so the hull of the inside pieces
  // is the answer (rounding can only split it at a root).
  double points[4] = { a, 0, 0, b };
  int n = 1;
  for (int i = 0; i < count; ++i) // the roots come ascending
    if (roots[i] > a && roots[i] < b)
      points[n++] = roots[i];
  points[n++] = b;
  bool found = false;
  for (int i = 0; i + 1 < n; ++i)
  {
    const double lo = points[i], hi = points[i + 1];
    if (!inside(0.5 * (lo + hi)) && !(lo == hi && inside(lo)))
      continue;
    if (!found)
      t0 = lo;
    t1 = hi;
    found = true;
  }
  return found;
}

bool sphereInterval(const dvec3& center, double radius, const dvec3& o, const dvec3& d,
  double tmin, double tmax, double& t0, double& t1)
{
  const dvec3 f = o - center;
  const double a = glm::dot(d, d);
  const double b = -glm::dot(f, d);
  const dvec3 offLine = f + (b / a) * d; // the line's closest point, without cancellation
  const double disc = a * (radius * radius - glm::dot(offLine, offLine));
  if (!(disc >= 0.0))
    return false;
  const double q = b + std::copysign(std::sqrt(disc), b);
  double r0 = q / a, r1 = q != 0.0 ? (glm::dot(f, f) - radius * radius) / q : r0;
  if (r0 > r1)
    std::swap(r0, r1);
  t0 = std::max(tmin, r0);
  t1 = std::min(tmax, r1);
  return t0 <= t1;
}

dvec3 coneStumpNormal(const ConeStump& k, const dvec3& p)
{
  const dvec3 e = p - k.base;
  const double u = glm::dot(e, k.axis);
  return k.cosine * k.cosine * (e - u * k.axis) - k.slope * (k.radius1 + k.slope * u) * k.axis;
}
} // namespace sightline
