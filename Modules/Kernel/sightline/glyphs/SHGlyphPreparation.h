// SPDX-License-Identifier: BSD-3-Clause
// From the glyph functions of selected input points to what SHGlyphSet and EllipsoidSet draw:
// the single place where input conventions are converted. Each point's values are read once
// in double and converted once to the canonical basis; then the glyph is turned into world
// axes, normalised, trimmed to its non-zero bands, and dropped when it is invalid (NaN) or
// empty (zero). Boxes (Section 4.2, the costly part) and largest amplitudes are cached per
// input point, so a viewer that changes the slice, the scale or the normalisation recomputes
// only the glyphs it has not seen yet.
#pragma once

#include "sightline/math/Math.h"
#include "sightline/math/SphericalHarmonics.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace sightline
{
class SHRotation;

/// How each glyph is divided before the world scale.
enum class GlyphNormalization
{
  None,            ///< radius = scale * |F|
  MaxAmplitude,    ///< each glyph's longest lobe has radius = scale
  CoefficientNorm, ///< each glyph divided by its canonical coefficient norm
  Global,          ///< all glyphs divided by the largest amplitude of all input points
};

/// Where the glyph functions come from: one tuple of values per input point.
struct GlyphSource
{
  /// Writes the values of input point `point` (shCoefficientCount(order) SH coefficients in
  /// `convention`, or a tensor's unique components for ellipsoids) to `values`. Called from
  /// one thread at a time.
  std::function<void(std::size_t point, double* values)> read;
  std::size_t pointCount = 0;
  int order = 0;
  SHConvention convention{ SHBasis::Canonical, false };
  /// What the values are (e.g. an array's address) and its version (its modification time):
  /// the per-point cache is kept while both, the order, the convention and the rotation stay.
  const void* identity = nullptr;
  std::uint64_t version = 0;
};

/// Which glyphs to prepare and how to size them.
struct GlyphRequest
{
  std::vector<std::size_t> points;  ///< input points to draw (a slice, masked), in order
  dmat3 rotation{ 1.0 };            ///< from the functions' axes to world axes (orthogonal)
  GlyphNormalization normalization = GlyphNormalization::MaxAmplitude;
  double worldScale = 1.0;          ///< world length of a normalised radius of 1
  bool maxAmplitudes = false;       ///< also return each glyph's largest amplitude
  std::function<void(double)> progress; ///< box computation, 0..1 (may be empty)
  /// Frustum culling (may be empty): whether the glyph of input point `point`, inside a sphere
  /// of world radius `radius` around it, may be seen. A glyph for which it returns false gets
  /// a loose box instead of the near-exact box search: the cube around that sphere (the
  /// coefficient bound, which encloses the glyph), so it is still drawn exactly wherever a ray
  /// reaches it (shadows, a later view), only slower. Loose boxes are not cached: a later
  /// preparation that sees the glyph computes its box then. Called from one thread.
  std::function<bool(std::size_t point, double radius)> mayBeVisible;
};

/// Invalid or empty glyphs of a preparation, for the caller's report.
struct GlyphDrops
{
  std::size_t nonFinite = 0;      ///< glyphs with NaN or infinite values
  std::size_t firstNonFinite = 0; ///< the input point of the first of them
  std::size_t empty = 0;          ///< all-zero glyphs or zero normalisation (background)
};

/// SH glyphs ready to draw: canonical coefficients in world axes, unscaled.
struct PreparedSHGlyphs
{
  std::vector<std::size_t> points;   ///< the input point of each glyph
  std::vector<std::uint8_t> orders;  ///< each glyph's order after dropping zero bands
  std::vector<std::size_t> offsets;  ///< where each glyph's coefficients start
  std::vector<double> coefficients;  ///< canonical, in world axes, before scaling
  std::vector<float> scales;         ///< world length per input unit of each glyph
  std::vector<vec3> halfExtents;     ///< each glyph's box after scaling
  std::vector<float> maxAmplitudes;  ///< largest |F| per glyph when requested, input units
  GlyphDrops drops;
  std::size_t computedBoxes = 0; ///< boxes not found in the cache
  /// Per glyph, 1 where its box is loose (culled by GlyphRequest::mayBeVisible); empty when
  /// none is.
  std::vector<std::uint8_t> looseBoxes;
  std::size_t looseBoxCount = 0;

  std::size_t size() const { return points.size(); }
};

/// Second-order tensors as ellipsoids (vtkTensorGlyph's shape): no SH boxes.
struct PreparedEllipsoids
{
  std::vector<std::size_t> points;
  std::vector<dmat3> axes;                    ///< scaled semi-axes in the columns
  /// |principal eigenvector| as RGBA8 (the eigenvector of the largest |eigenvalue|), the
  /// usual colouring of diffusion directions
  std::vector<std::uint32_t> directionColors;
  std::vector<float> maxAmplitudes;           ///< largest |eigenvalue| when requested
  GlyphDrops drops;

  std::size_t size() const { return points.size(); }
};

/// Prepares glyphs of one source and keeps its per-point cache between preparations.
class SHGlyphPreparation
{
public:
  /// Reads, converts, normalises, turns, trims and boxes the requested points; points with
  /// non-finite values, zero functions or zero normalisation are dropped and counted. Throws
  /// std::invalid_argument for an order outside the glyphs' range or a point outside the
  /// source.
  PreparedSHGlyphs prepare(const GlyphSource& source, const GlyphRequest& request);

  /// Glyphs of a second source (e.g. uncertainty) at the points and scales of `reference`,
  /// turned by the same rotation (normalisation does not apply: they keep the reference's
  /// scale so that they enclose it).
  PreparedSHGlyphs prepareAlongside(const GlyphSource& source, const PreparedSHGlyphs& reference,
    const GlyphRequest& request);

  /// Second-order tensors (the source reads their six unique components, xx, xy, xz, yy, yz,
  /// zz) as ellipsoids: eigenvectors scaled by |eigenvalues|, flat ones kept visible at 1/1000
  /// of the largest. Nothing is cached: the decomposition is cheap.
  static PreparedEllipsoids prepareEllipsoids(const GlyphSource& tensors, const GlyphRequest& request);

  /// Drops the cache (e.g. when the input goes away).
  void clear();
  std::size_t memoryBytes() const;

private:
  struct PointCache
  {
    const void* identity = nullptr;
    std::uint64_t version = 0;
    std::size_t pointCount = 0;
    int order = -1;
    SHConvention convention;
    dmat3 rotation{ 1.0 };
    std::vector<vec3> halfExtents;    ///< unscaled, NaN: not computed yet
    std::vector<float> maxAmplitudes; ///< NaN: not computed yet
    double globalMaxAmplitude = -1.0; ///< negative: not computed yet
  };

  void useCacheFor(const GlyphSource& source, const dmat3& rotation);
  /// Checks the request, selects the cache and reads `points` as canonical coefficients.
  std::vector<double> begin(const GlyphSource& source, const std::vector<std::size_t>& points,
    const dmat3& rotation, std::vector<char>& finite);
  /// Turns one glyph (when `rotation` is given), trims its zero bands and appends it.
  static void append(PreparedSHGlyphs& glyphs, std::size_t point, float scale, int order,
    double* canonical, const SHRotation* rotation);
  /// Reads the points `which`, converted to canonical; `finite` false for non-finite ones.
  void readCanonical(const GlyphSource& source, const std::vector<std::size_t>& which,
    std::vector<double>& canonical, std::vector<char>& finite) const;
  void computeBoxes(PreparedSHGlyphs& glyphs, const GlyphRequest& request);
  double globalMaxAmplitude(const GlyphSource& source);

  PointCache Cache;
};
} // namespace sightline
