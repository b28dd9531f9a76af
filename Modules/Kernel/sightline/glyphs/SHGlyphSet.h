// SPDX-License-Identifier: BSD-3-Clause
// N spherical-harmonics glyphs as one Embree user geometry: near-exact boxes for the BVH,
// the exact root-finding intersection of SHGlyph.h for primary and shadow rays, and the
// all-intersections query that uncertainty volumes need. The ray-marching methods of the
// prior work live here too, as options, so that baselines run through the same BVH, camera,
// shading and image comparison as the exact method.
#pragma once

#include "sightline/core/Geometry.h"
#include "sightline/glyphs/SHGlyph.h"
#include "sightline/glyphs/SHGlyphPreparation.h"
#include "sightline/glyphs/TensorGlyph.h"

#include <cstdint>
#include <vector>

namespace sightline
{
/// How a ray is intersected with a glyph.
enum class SHIntersectionMethod
{
  RootFinding, ///< exact: Algorithm 1 of Peters et al. 2023
  RayMarching, ///< baseline: fixed steps plus bisection (Peeters et al. 2009, van Almsick 2011)
  /// baseline: the tensor glyph paper's marching on its Cartesian function (Hlawitschka et al.
  /// Sec. 4; see TensorGlyph.h), orders <= 12
  TensorMarching,
  /// baseline: rejection and bisection with interval or reduced affine arithmetic (Hlawitschka
  /// et al. Sec. 5, after Knoll et al.), orders <= 12
  IntervalSubdivision,
};

/// Which segment of the ray the marching baseline samples.
enum class SHMarchingBound
{
  Sphere,   ///< the ray inside the bounding sphere (Peeters et al. 2009)
  Cylinder, ///< a bounding cylinder along the ray, 2R long (van Almsick et al. 2011)
};

/// Arithmetic of the exact intersection.
enum class SHPrecision
{
  /// Double for every order: on a CPU the scalar root finder is latency-bound and float was
  /// not measurably faster (k = 4: 1.40 vs 1.43 us, k = 8: 6.1 vs 5.9 us per test), while
  /// double is 1e5 times more accurate and free of the k >= 10 artifacts the paper reports.
  Automatic,
  Float,
  Double,
};

/// How glyphs get their base colour.
enum class SHColoring
{
  Material,  ///< the material's colour
  Direction, ///< |p / |p|| as RGB, the usual colouring of fibre directions
  PerGlyph,  ///< the colours given to the constructor (e.g. a scalar through a colormap)
  /// colormap(radius): the hit point's distance from the centre in input units (world distance
  /// divided by the glyph's scale), the tensor glyph paper's "colour coding by scalar value"
  Radius,
};

struct SHGlyphOptions
{
  SHConvention convention;        ///< basis of the input coefficients
  SHPrecision precision = SHPrecision::Automatic;
  SHColoring coloring = SHColoring::Direction;
  /// Drop trailing bands whose coefficients are all zero and intersect with the lower degree.
  bool trimZeroBands = true;
  /// Hide negative lobes (points where F < 0) instead of drawing them as surface.
  bool hideNegativeLobes = false;
  /// Colour of negative lobes; a negative component keeps the glyph's own colour.
  vec3 negativeLobeColor{ -1.0f };
  /// Root tolerance relative to the glyph size; 0 picks the default of the arithmetic.
  double tolerance = 0.0;
  /// Coloring::Radius: colours spread evenly over [radiusRange.x, radiusRange.y] (clamped).
  std::vector<vec3> colormap;
  vec2 radiusRange{ 0.0f, 1.0f };

  SHIntersectionMethod method = SHIntersectionMethod::RootFinding;
  int marchingSteps = 200;
  int bisectionSteps = 10;
  SHMarchingBound marchingBound = SHMarchingBound::Cylinder;
  /// Baselines: use the near-exact boxes in the BVH (true) or the boxes of the bounding sphere.
  bool marchingUsesTightBoxes = false;
  TensorMarchingOptions tensorMarching;
  IntervalSubdivisionOptions subdivision;
};

/// shGlyphMaxRadius for coefficients given in `convention`: the radius of the glyph's longest
/// lobe, which normalisations divide by.
double shMaxAmplitude(int order, const float* coefficients, const SHConvention& convention);

/// Euclidean norm of the coefficients in the orthonormal canonical basis (the L2 norm of F
/// over the sphere), the same value in every convention.
double shCoefficientNorm(int order, const float* coefficients, const SHConvention& convention);

class SHGlyphSet : public UserGeometry<SHGlyphSet>
{
public:
  /// One glyph per centre; `coefficients` holds shCoefficientCount(order) values per glyph in
  /// `options.convention`, already scaled to world units (a glyph's radius in direction w is
  /// |F(w)|). `scales` is empty or one factor per glyph; `colors` (RGBA8) is empty or one per
  /// glyph. Glyphs with non-finite centres, coefficients or scales are dropped and reported in
  /// report(), as are glyphs whose coefficients are all zero. `halfExtents` is empty or, per
  /// glyph, the half-extents of its box after scaling (as halfExtents() returned for the same
  /// glyph earlier): boxes are only computed where it is empty or NaN, so a viewer that caches
  /// them rebuilds a slice of glyphs in milliseconds. Throws std::invalid_argument for an order
  /// that is not even in [0, kMaxGlyphOrder] and for array sizes that do not match.
  SHGlyphSet(const std::vector<vec3>& centers, const std::vector<float>& coefficients, int order,
    const SHGlyphOptions& options = {}, const std::vector<float>& scales = {},
    const std::vector<std::uint32_t>& colors = {}, const std::vector<vec3>& halfExtents = {});
  /// The same with the centres given relative to `origin` (kept in double), for glyphs far
  /// from the world origin: they are intersected in their own frame with double rays.
  SHGlyphSet(const dvec3& origin, const std::vector<vec3>& centers, const std::vector<float>& coefficients,
    int order, const SHGlyphOptions& options = {}, const std::vector<float>& scales = {},
    const std::vector<std::uint32_t>& colors = {}, const std::vector<vec3>& halfExtents = {});

  /// Glyphs that SHGlyphPreparation made ready (canonical, turned, trimmed, boxed): nothing
  /// is converted again; `centers` has one world centre per prepared glyph and `colors` is
  /// empty or one RGBA8 colour per glyph. options.convention and options.trimZeroBands do not
  /// apply, and the coefficients are not checked again (the preparation dropped invalid and
  /// zero glyphs); only glyphs with non-finite centres are dropped and reported.
  SHGlyphSet(const std::vector<vec3>& centers, const PreparedSHGlyphs& glyphs,
    const SHGlyphOptions& options = {}, const std::vector<std::uint32_t>& colors = {});
  /// The same with the centres relative to `origin` (kept in double).
  SHGlyphSet(const dvec3& origin, const std::vector<vec3>& centers, const PreparedSHGlyphs& glyphs,
    const SHGlyphOptions& options = {}, const std::vector<std::uint32_t>& colors = {});

  std::size_t size() const override { return Glyphs.size(); }
  bool hasPrimitiveColors() const override
  {
    return Options.coloring != SHColoring::Material || Options.negativeLobeColor.x >= 0.0f;
  }
  vec3 primitiveColor(unsigned primitive) const override;
  vec3 surfaceColor(unsigned primitive, const dvec3& point) const override;
  std::size_t memoryBytes() const override;
  Box3 bounds() const override { return AllBounds; }
  double insideLength(unsigned primitive, const DoubleRay& ray, float& entry) const override;

  Box3 bounds(unsigned primitive) const { return Glyphs[primitive].box; }
  /// Half-extents of a glyph's box around its centre (to cache, see the constructor).
  vec3 halfExtents(unsigned primitive) const { return Glyphs[primitive].halfExtents; }
  bool intersect(unsigned primitive, const DoubleRay& ray, SurfaceHit& hit) const;

  /// All intersections of a ray with one glyph in [ray.tnear, ray.tfar], ascending; returns
  /// their number (t has room for kMaxGlyphHits).
  int allIntersections(unsigned primitive, const DoubleRay& ray, double* t) const;

  const ValidationReport& report() const { return Report; }
  const std::vector<std::uint32_t>& sourceIndex() const { return SourceIndex; }
  const SHGlyphOptions& options() const { return Options; }
  /// Order used for a glyph after dropping zero bands.
  int order(unsigned primitive) const { return Glyphs[primitive].order; }
  /// Canonical, scaled coefficients of a glyph (shCoefficientCount(order(primitive)) values).
  const double* coefficients(unsigned primitive) const
  {
    return DoubleCoefficients.data() + Glyphs[primitive].offset;
  }
  vec3 center(unsigned primitive) const { return vec3(Glyphs[primitive].center); }
  /// Seconds spent computing boxes (both cores), for benchmarks.
  double boundsSeconds() const { return BoundsSeconds; }

private:
  struct Glyph
  {
    dvec3 center;
    Box3 box;
    vec3 halfExtents{ 0.0f };
    std::uint32_t offset = 0; ///< into the coefficient arrays
    std::uint8_t order = 0;
    bool useFloat = false;
    float boundingRadius = 0.0f; ///< coefficient bound: the marching baselines, ray culling
    float scale = 1.0f;          ///< world units per input unit (radius colouring)
    float maxRadius = 0.0f;      ///< longest lobe, padded: the tensor methods' bounding sphere
  };

  void checkOptions(int order, std::size_t glyphs, const std::vector<std::uint32_t>& colors) const;
  /// Appends one glyph unless its centre is not finite: canonical coefficients of `order`,
  /// already scaled and not all zero; `halfExtents` negative or NaN when its box is still to
  /// be computed.
  void addGlyph(const vec3& center, int order, const double* scaled, float scale,
    const vec3& halfExtents, std::size_t index, const std::vector<std::uint32_t>& colors);
  /// Boxes (computed where missing) and the set's bounds, after the last addGlyph.
  void finish();
  /// Moves every glyph by `origin` (the origin constructors' centres are relative to it).
  void moveTo(const dvec3& origin);

  int exactIntersections(const Glyph& glyph, const DoubleRay& ray, double* t, bool firstOnly) const;
  int marchingIntersection(const Glyph& glyph, const DoubleRay& ray, double& t) const;
  int tensorMethodIntersection(unsigned primitive, const DoubleRay& ray, double& t) const;

  SHGlyphOptions Options;
  std::vector<Glyph> Glyphs;
  std::vector<double> DoubleCoefficients;
  std::vector<float> FloatCoefficients;
  std::vector<CartesianGlyphFunction> Cartesian; ///< per glyph, for the tensor methods only
  std::vector<std::uint32_t> Colors;
  std::vector<std::uint32_t> SourceIndex;
  Box3 AllBounds;
  ValidationReport Report;
  std::size_t NonFiniteCount = 0, ZeroCount = 0; ///< per reason, for the report's first line
  double BoundsSeconds = 0.0;
};
} // namespace sightline
