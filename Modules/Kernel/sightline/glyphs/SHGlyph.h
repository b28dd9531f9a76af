// SPDX-License-Identifier: BSD-3-Clause
// One spherical-harmonics glyph, exactly: the surface |p| = |F(p / |p|)| for a function F given
// by canonical SH coefficients of even bands up to `order` (see SphericalHarmonics.h), centred
// at the origin. Implements Peters et al. 2023 ("Ray tracing spherical harmonics glyphs"):
// Algorithm 1 for all ray intersections, Eq. 11 for normals and Section 4.2 for a near-exact
// bounding box. The functions are templated on the arithmetic (float or double).
#pragma once

#include "sightline/math/Math.h"
#include "sightline/math/SphericalHarmonics.h"

namespace sightline
{
/// Highest glyph order the intersection supports (polynomial degree 2k + 2 = 34).
constexpr int kMaxGlyphOrder = 16;
/// Most intersections one ray can have with one glyph.
constexpr int kMaxGlyphHits = 2 * kMaxGlyphOrder + 2;

/// Ray intersections with one glyph. `origin` is relative to the glyph centre, `direction` has
/// unit length. Writes the ray parameters of all intersections in [tmin, tmax], sorted
/// ascending, to `t` (room for kMaxGlyphHits) and returns their number; with `firstOnly` only
/// the nearest. `tolerance` is relative to the glyph's size along the ray.
///
/// Following Algorithm 1: the ray and the centre span a plane with orthonormal frame (d, e);
/// k + 1 SH evaluations on the great circle of that plane give, through a precomputed inverse
/// Vandermonde matrix, the restriction g(u, v) of F to the plane as a homogeneous polynomial;
/// (e.o)^2 (u^2 + v^2)^(k+1) - v^2 g(u, v)^2 = 0 on the ray is then a polynomial of degree
/// 2k + 2 solved by bracketed Newton-bisection inside the bounding circle of Appendix B.
/// One change to the paper: it dehomogenises at v = 1, whose roots u grow like 1/(e.o) and
/// overflow float for rays near the centre; we dehomogenise at v = e.o and divide all lengths
/// by the bound g_max, so every coefficient and root is of order one and rays through the
/// centre need no special case.
/// Two additions that keep every root: the cross-section's height |q(theta)| = |g| sin in the
/// ray's plane, sampled with Bernstein's bound, culls rays beside the lobes and narrows the
/// interval to the lobe the ray passes; where those samples prove that one monotonic piece
/// holds the entry alone (an "entry certificate"), the nearest root is refined there without
/// root isolation. Nearest-hit and all-roots queries take the same steps (same nearest root).
template <class T>
int intersectSHGlyph(int order, const T* coefficients, const T origin[3], const T direction[3],
  T tmin, T tmax, T tolerance, T* t, bool firstOnly);

/// Default root tolerance for each arithmetic (relative to the glyph size).
template <class T>
constexpr T defaultGlyphTolerance()
{
  return sizeof(T) == sizeof(float) ? T(1e-4) : T(1e-6);
}

/// Unnormalised outward normal at a point p on the glyph (Eq. 11):
///   n = p - F(w) (I - w w^T) grad F(w) / |p|,  w = p / |p|.
/// Correct on negative lobes too; `value` receives F(w), whose sign tells the lobe.
dvec3 shGlyphNormal(int order, const double* coefficients, const dvec3& p, double* value = nullptr);

/// Whether p lies inside the glyph (|p| < |F(p / |p|)|).
bool insideSHGlyph(int order, const double* coefficients, const dvec3& p);

/// Near-exact axis-aligned half extents of the glyph (Section 4.2): the largest |coordinate| of
/// F(w) w over k * 256 spherical Fibonacci directions w, refined by up to five Newton steps on
/// the tangency conditions for each axis (fewer once a step is below 1e-5), then enlarged by
/// 2.5 % (k <= 8) or 3.5 % (k >= 10), the margins the paper validated. The glyph is point
/// symmetric, so the box is [-h, h].
dvec3 shGlyphHalfExtents(int order, const double* coefficients);
/// The same for `count` glyphs of one order: halfExtents[g] is shGlyphHalfExtents(order,
/// coefficients[g]), bit for bit; groups of four glyphs share one pass over the directions.
void shGlyphHalfExtents(
  int order, std::size_t count, const double* const* coefficients, dvec3* halfExtents);
/// The same without the safety margin (what the validation test compares).
dvec3 shGlyphHalfExtentsUnpadded(int order, const double* coefficients);

/// Largest |F(w)| over the sphere: the radius of the glyph's longest lobe, which per-glyph
/// normalisation divides by. The best of ~6 (k+1)^2 Fibonacci directions, refined by Newton's
/// method on the sphere.
double shGlyphMaxRadius(int order, const double* coefficients);
/// The same for `count` glyphs of one order (radii[g] bit for bit as one at a time; groups of
/// four share one pass over the directions).
void shGlyphMaxRadius(
  int order, std::size_t count, const double* const* coefficients, double* radii);

/// Radius of a sphere that certainly contains the glyph: sum_j |b_j| max|Y_j| (the bound of
/// Peeters et al. 2009 that ray-marching baselines use).
double shGlyphBoundingRadius(int order, const double* coefficients);

/// Smallest even order that holds every non-zero coefficient (trailing zero bands dropped).
int shEffectiveOrder(int order, const double* coefficients);
} // namespace sightline
