// SPDX-License-Identifier: BSD-3-Clause
// One link of a generalized tube (Han et al. 2019): two spheres and the cone stump tangent to
// both, whose union is the convex hull of the two spheres, i.e. the sphere swept along the
// segment with linearly varying radius. Equal radii give a cylinder, one sphere inside the
// other gives no stump (only the larger sphere shows).
//
// The stump is written without its apex, so that nearly equal radii (apex far away) stay
// accurate: with u the axial coordinate from P1 along the unit axis C, L = |P2 - P1| and
// s = (r2 - r1) / L (the sine of the half-angle), the tangent circles lie at u1 = -s r1 and
// u2 = L - s r2, and the radius at u is (r1 + s u) / sqrt(1 - s^2). This is Section 3.2.2's
// cone (apex A = P1 - (r1 / s) C, clipping planes z1, z2 at u1, u2) in another form.
#pragma once

#include "sightline/math/Math.h"

namespace sightline
{
struct ConeStump
{
  dvec3 base{ 0.0 };  ///< P1
  dvec3 axis{ 0.0 };  ///< unit vector from P1 to P2
  double length = 0;  ///< |P2 - P1|
  double slope = 0;   ///< s = (r2 - r1) / L, |s| < 1
  double cosine = 1;  ///< sqrt(1 - s^2)
  double radius1 = 0; ///< r1
  double u1 = 0, u2 = 0; ///< axial range between the tangent circles
  bool valid = false; ///< false when one sphere contains the other (|s| >= 1) or P1 = P2
};

/// The stump tangent to the spheres (p1, r1) and (p2, r2); invalid when there is none.
ConeStump makeConeStump(const dvec3& p1, double r1, const dvec3& p2, double r2);

/// The parameter interval [t0, t1] in which the ray o + t d (d any length) is inside the stump,
/// clipped to [tmin, tmax]; false when empty. The stump is convex: one interval at most.
bool coneStumpInterval(const ConeStump& stump, const dvec3& origin, const dvec3& direction,
  double tmin, double tmax, double& t0, double& t1);

/// The same for a sphere.
bool sphereInterval(const dvec3& center, double radius, const dvec3& origin,
  const dvec3& direction, double tmin, double tmax, double& t0, double& t1);

/// Outward (unnormalised) normal of the stump's side at a point on it.
dvec3 coneStumpNormal(const ConeStump& stump, const dvec3& point);

/// The box of a sphere (xyz centre, w radius); a link lies in the boxes of its two spheres.
inline Box3 sphereBox(const vec4& sphere)
{
  return Box3{ vec3(sphere) - vec3(sphere.w), vec3(sphere) + vec3(sphere.w) };
}
} // namespace sightline
