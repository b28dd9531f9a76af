// SPDX-License-Identifier: BSD-3-Clause
// The intersection methods of Hlawitschka, Hijazi, Knoll and Hamann ("Towards high-quality
// rendering of higher-order tensor glyphs"), kept as options and baselines next to the exact
// root finding of SHGlyph.h. They work on the seed's implicit function (Eq. 5 and Sec. 3.1)
//   g(p) = |T(p)| - |p|^(n+1),   T(p) = sum_i mult_i T_i x^a y^b z^c,
// positive inside the glyph |p| < |T(p / |p|)|, evaluated in Cartesian form (no trigonometry):
// - fixed-step ray marching inside the bounding sphere with a sign test, optional bisection
//   steps, a final linear interpolation and finer steps near the centre (Sec. 4);
// - guaranteed rejection-and-bisection along the ray with interval arithmetic or reduced
//   affine arithmetic (Sec. 5, after Knoll et al.).
// Every glyph of SHGlyph.h is such a function (even SH bands up to n and order-n symmetric
// tensors span the same space), so the methods apply to SH glyphs too.
#pragma once

#include "sightline/math/Math.h"

#include <array>
#include <cstdint>
#include <vector>

namespace sightline
{
/// A closed interval [lo, hi].
struct Interval
{
  double lo = 0.0;
  double hi = 0.0;
  bool contains(double x) const { return lo <= x && x <= hi; }
};

/// The seed's glyph function of one glyph, scaled to the unit ball: the glyph lies in the
/// sphere of radius 1 around the origin (its longest lobe has radius at most 1).
class CartesianGlyphFunction
{
public:
  CartesianGlyphFunction() = default;
  /// From the unique components of an even-order symmetric tensor (SymmetricTensor.h order),
  /// divided by `radius` so that a glyph of that largest radius fits the unit ball.
  CartesianGlyphFunction(int order, const double* components, double radius = 1.0);
  /// The same glyph from canonical SH coefficients of bands 0..order (order <= 12).
  static CartesianGlyphFunction fromSH(int order, const double* coefficients, double radius = 1.0);

  int order() const { return Order; }
  /// T(p), the homogeneous polynomial of degree n (the glyph radius for unit p).
  double tensor(const dvec3& p) const;
  /// g(p) = |T(p)| - |p|^(n+1) (or T(p) - |p|^(n+1) with `positiveOnly`, which hides
  /// negative lobes): positive inside the glyph.
  double implicit(const dvec3& p, bool positiveOnly) const;
  /// An enclosure of g over the box `box` (interval arithmetic, Moore): contains g(p) for
  /// every p in the box, rounding errors included.
  Interval implicit(const Interval box[3], bool positiveOnly) const;
  /// An enclosure of g over the segment p = center + e * half, e in [-1, 1], by reduced affine
  /// arithmetic with the one noise symbol e (Comba and Stolfi): tighter than intervals because
  /// the linear parts of T and |p|^(n+1) cancel.
  Interval implicitAffine(const dvec3& center, const dvec3& half, bool positiveOnly) const;
  /// Bytes held, the object included.
  std::size_t memoryBytes() const
  {
    return sizeof(*this) + Weights.capacity() * sizeof(double) + Exponents.capacity() * 3;
  }

private:
  int Order = 0;
  std::vector<double> Weights; ///< mult_i T_i / radius
  std::vector<std::array<std::uint8_t, 3>> Exponents;
  double WeightSum = 0.0; ///< sum |Weights|, for the rounding-error bound
};

/// The seed's fixed-step ray marching. Steps are in units of the bounding radius (the seed
/// scales each glyph into [-1, 1]^3); 0.2 with linear interpolation is its recommendation.
struct TensorMarchingOptions
{
  double stepSize = 0.2;
  int bisectionSteps = 0;
  /// Replace the refined point by the root of the line through the last outside and inside
  /// samples (no extra evaluation).
  bool linearInterpolation = true;
  /// Inside the ball of radius centreRadius the step is stepSize * centreStepFactor ("a third
  /// of the original step size towards the centre"); 1 turns the adaptive sampling off. The
  /// seed gives no radius; a quarter of the bounding radius is ours.
  double centreStepFactor = 1.0 / 3.0;
  double centreRadius = 0.25;
};

/// Which enclosure the subdivision uses.
enum class EnclosureArithmetic
{
  Interval,      ///< interval arithmetic
  ReducedAffine, ///< reduced affine arithmetic with one noise symbol along the ray
};

struct IntervalSubdivisionOptions
{
  EnclosureArithmetic arithmetic = EnclosureArithmetic::ReducedAffine;
  /// A segment shorter than this (relative to the bounding radius) that cannot be rejected is
  /// the hit; its midpoint is returned.
  double tolerance = 1e-4;
};

/// Work counters of one subdivision query (for tests and benchmarks).
struct SubdivisionStatistics
{
  int evaluations = 0;
  int rejected = 0;
};

/// First intersection of the ray o + t d (|d| = 1, glyph frame, unit-ball units) with the glyph
/// in [tmin, tmax] by the seed's marching inside the unit sphere; false when none was found.
bool marchTensorGlyph(const CartesianGlyphFunction& glyph, const dvec3& origin,
  const dvec3& direction, double tmin, double tmax, const TensorMarchingOptions& options,
  bool positiveOnly, double& t);

/// First intersection by rejection and bisection (Knoll et al.): a segment whose enclosure
/// excludes 0 holds no surface; the nearest segment shorter than the tolerance that cannot be
/// rejected is the hit. Never misses surface (the enclosures are guaranteed); may report a
/// grazing near miss within the tolerance.
bool subdivideTensorGlyph(const CartesianGlyphFunction& glyph, const dvec3& origin,
  const dvec3& direction, double tmin, double tmax, const IntervalSubdivisionOptions& options,
  bool positiveOnly, double& t, SubdivisionStatistics* statistics = nullptr);
} // namespace sightline
