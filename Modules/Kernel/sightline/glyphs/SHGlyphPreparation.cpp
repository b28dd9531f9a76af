// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/glyphs/SHGlyphPreparation.h"

#include "sightline/core/Geometry.h"
#include "sightline/glyphs/SHGlyph.h"
#include "sightline/math/SHRotation.h"
#include "sightline/math/SymmetricTensor.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace sightline
{
namespace
{
constexpr float kNotComputed = std::numeric_limits<float>::quiet_NaN();
/// Boxes are computed in blocks of this many glyphs, reporting progress after each.
constexpr std::size_t kBoxBlock = 2048;
/// Points read at a time when every point of the source counts (global normalisation).
constexpr std::size_t kReadBlock = 4096;

/// Glyphs handed to the kernel's batched searches at a time by one task (whole batches of four
/// share a pass over the direction tables).
constexpr std::size_t kSearchGrain = 32;

/// Largest amplitudes of glyphs of one order, in parallel: radii[i] = shGlyphMaxRadius(order,
/// coefficients[i]).
std::vector<double> maxRadii(int order, const std::vector<const double*>& coefficients)
{
  std::vector<double> radii(coefficients.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, coefficients.size(), kSearchGrain),
    [&](const tbb::blocked_range<std::size_t>& range)
    {
      shGlyphMaxRadius(order, range.size(), coefficients.data() + range.begin(), radii.data() + range.begin());
    });
  return radii;
}

double canonicalNorm(const double* coefficients, int count)
{
  double sum = 0.0;
  for (int j = 0; j < count; ++j)
    sum += coefficients[j] * coefficients[j];
  return std::sqrt(sum);
}

bool allZero(const double* values, int count)
{
  return std::all_of(values, values + count, [](double v) { return v == 0.0; });
}

void checkPoints(const GlyphSource& source, const std::vector<std::size_t>& points)
{
  if (!source.read)
    throw std::invalid_argument("the glyph source has no reader");
  for (std::size_t point : points)
    if (point >= source.pointCount)
      throw std::invalid_argument("glyph point " + std::to_string(point) + " is outside the " +
        std::to_string(source.pointCount) + " points of its source");
}

void checkOrder(int order)
{
  if (order < 0 || order > kMaxGlyphOrder || order % 2 != 0)
    throw std::invalid_argument("SH glyph order " + std::to_string(order) +
      " is not an even number in [0, " + std::to_string(kMaxGlyphOrder) + "]");
}

/// The divisor a normalisation applies to one glyph; not positive and finite: nothing to draw.
double normalizationDivisor(GlyphNormalization normalization, double maxAmplitude, double norm,
  double globalMaxAmplitude)
{
  switch (normalization)
  {
    case GlyphNormalization::MaxAmplitude:
      return maxAmplitude;
    case GlyphNormalization::CoefficientNorm:
      return norm;
    case GlyphNormalization::Global:
      return globalMaxAmplitude;
    case GlyphNormalization::None:
      break;
  }
  return 1.0;
}

bool usableDivisor(double divisor)
{
  return divisor > 0.0 && std::isfinite(divisor);
}

void countNonFinite(GlyphDrops& drops, std::size_t point)
{
  if (drops.nonFinite++ == 0)
    drops.firstNonFinite = point;
}
} // namespace

void SHGlyphPreparation::useCacheFor(const GlyphSource& source, const dmat3& rotation)
{
  PointCache& c = Cache;
  const bool same = c.identity == source.identity && c.version == source.version &&
    c.pointCount == source.pointCount && c.order == source.order &&
    c.convention.basis == source.convention.basis &&
    c.convention.legacy == source.convention.legacy && c.rotation == rotation;
  if (same)
    return;
  c.identity = source.identity;
  c.version = source.version;
  c.pointCount = source.pointCount;
  c.order = source.order;
  c.convention = source.convention;
  c.rotation = rotation;
  c.halfExtents.assign(source.pointCount, vec3(kNotComputed));
  c.maxAmplitudes.assign(source.pointCount, kNotComputed);
  c.globalMaxAmplitude = -1.0;
}

void SHGlyphPreparation::clear()
{
  Cache = PointCache();
}

std::size_t SHGlyphPreparation::memoryBytes() const
{
  return Cache.halfExtents.capacity() * sizeof(vec3) + Cache.maxAmplitudes.capacity() * sizeof(float);
}

void SHGlyphPreparation::readCanonical(const GlyphSource& source,
  const std::vector<std::size_t>& which, std::vector<double>& canonical,
  std::vector<char>& finite) const
{
  const int count = shCoefficientCount(source.order);
  const bool convert = source.convention.basis != SHBasis::Canonical;
  const SHConversion conversion = SHConversion::toCanonical(source.convention, source.order);
  canonical.resize(which.size() * count);
  finite.resize(which.size());
  std::vector<double> raw(count);
  for (std::size_t g = 0; g < which.size(); ++g)
  {
    double* out = canonical.data() + g * count;
    source.read(which[g], convert ? raw.data() : out);
    const double* read = convert ? raw.data() : out;
    finite[g] = std::all_of(read, read + count, [](double v) { return std::isfinite(v); });
    if (convert && finite[g])
      conversion.apply(raw.data(), out);
  }
}

double SHGlyphPreparation::globalMaxAmplitude(const GlyphSource& source)
{
  if (Cache.globalMaxAmplitude >= 0.0)
    return Cache.globalMaxAmplitude;
  // Every point of the source counts, so that all slices share one scale; read in blocks so
  // that a volume is never copied whole.
  const int count = shCoefficientCount(source.order);
  double largest = 0.0;
  std::vector<std::size_t> block;
  std::vector<double> canonical;
  std::vector<char> finite;
  for (std::size_t start = 0; start < source.pointCount; start += kReadBlock)
  {
    block.clear();
    for (std::size_t p = start; p < std::min(source.pointCount, start + kReadBlock); ++p)
      if (std::isnan(Cache.maxAmplitudes[p]))
        block.push_back(p);
    readCanonical(source, block, canonical, finite);
    std::vector<const double*> searched;
    for (std::size_t g = 0; g < block.size(); ++g)
    {
      Cache.maxAmplitudes[block[g]] = 0.0f;
      if (finite[g])
        searched.push_back(canonical.data() + g * count);
    }
    const std::vector<double> radii = maxRadii(source.order, searched);
    for (std::size_t g = 0, i = 0; g < block.size(); ++g)
      if (finite[g])
        Cache.maxAmplitudes[block[g]] = float(radii[i++]);
  }
  for (float amplitude : Cache.maxAmplitudes)
    largest = std::max(largest, double(amplitude));
  Cache.globalMaxAmplitude = largest;
  return largest;
}

std::vector<double> SHGlyphPreparation::begin(const GlyphSource& source,
  const std::vector<std::size_t>& points, const dmat3& rotation, std::vector<char>& finite)
{
  checkOrder(source.order);
  checkPoints(source, points);
  useCacheFor(source, rotation);
  std::vector<double> canonical;
  readCanonical(source, points, canonical, finite);
  return canonical;
}

void SHGlyphPreparation::append(PreparedSHGlyphs& glyphs, std::size_t point, float scale,
  int order, double* canonical, const SHRotation* rotation)
{
  const int count = shCoefficientCount(order);
  if (rotation)
  {
    std::vector<double> turned(count);
    rotation->apply(canonical, turned.data());
    std::copy(turned.begin(), turned.end(), canonical);
  }
  // Trailing zero bands are dropped: a lower degree intersects faster.
  const int effective = shEffectiveOrder(order, canonical);
  glyphs.points.push_back(point);
  glyphs.scales.push_back(scale);
  glyphs.orders.push_back(std::uint8_t(effective));
  glyphs.offsets.push_back(glyphs.coefficients.size());
  glyphs.coefficients.insert(
    glyphs.coefficients.end(), canonical, canonical + shCoefficientCount(effective));
}

PreparedSHGlyphs SHGlyphPreparation::prepare(const GlyphSource& source, const GlyphRequest& request)
{
  std::vector<char> finite;
  std::vector<double> canonical = begin(source, request.points, request.rotation, finite);
  const int order = source.order;
  const int count = shCoefficientCount(order);

  // Largest amplitudes (rotation does not change them), cached per point.
  const bool needAmplitudes =
    request.normalization == GlyphNormalization::MaxAmplitude || request.maxAmplitudes;
  if (needAmplitudes)
  {
    std::vector<std::size_t> missing;
    std::vector<const double*> searched;
    for (std::size_t g = 0; g < request.points.size(); ++g)
      if (finite[g] && std::isnan(Cache.maxAmplitudes[request.points[g]]))
      {
        missing.push_back(g);
        searched.push_back(canonical.data() + g * count);
      }
    const std::vector<double> radii = maxRadii(order, searched);
    for (std::size_t i = 0; i < missing.size(); ++i)
      Cache.maxAmplitudes[request.points[missing[i]]] = float(radii[i]);
  }
  const double global = request.normalization == GlyphNormalization::Global
    ? globalMaxAmplitude(source)
    : 0.0;

  // Keep the finite, non-zero glyphs that normalise to a size, in world axes.
  const bool turned = request.rotation != dmat3(1.0);
  const SHRotation rotation(turned ? order : 0, request.rotation);
  PreparedSHGlyphs glyphs;
  for (std::size_t g = 0; g < request.points.size(); ++g)
  {
    const std::size_t point = request.points[g];
    double* c = canonical.data() + g * count;
    if (!finite[g])
    {
      countNonFinite(glyphs.drops, point);
      continue;
    }
    const double divisor = normalizationDivisor(request.normalization,
      Cache.maxAmplitudes[point], canonicalNorm(c, count), global);
    if (allZero(c, count) || !usableDivisor(divisor))
    {
      ++glyphs.drops.empty; // background voxels of a fit are all zero: normal, not an error
      continue;
    }
    append(glyphs, point, float(request.worldScale / divisor), order, c, turned ? &rotation : nullptr);
    if (request.maxAmplitudes)
      glyphs.maxAmplitudes.push_back(Cache.maxAmplitudes[point]);
  }
  computeBoxes(glyphs, request);
  return glyphs;
}

void SHGlyphPreparation::computeBoxes(PreparedSHGlyphs& glyphs, const GlyphRequest& request)
{
  std::vector<std::size_t> missing;
  glyphs.looseBoxes.clear();
  glyphs.looseBoxCount = 0;
  std::vector<float> looseRadius; // unscaled, per glyph; 0 where the box is computed
  for (std::size_t g = 0; g < glyphs.size(); ++g)
  {
    if (!std::isnan(Cache.halfExtents[glyphs.points[g]].x))
      continue;
    if (request.mayBeVisible)
    {
      // The coefficient bound is cheap (a norm per band); the box search is not.
      const double radius = shGlyphBoundingRadius(glyphs.orders[g], glyphs.coefficients.data() + glyphs.offsets[g]);
      if (!request.mayBeVisible(glyphs.points[g], radius * std::abs(double(glyphs.scales[g]))))
      {
        if (glyphs.looseBoxes.empty())
        {
          glyphs.looseBoxes.assign(glyphs.size(), 0);
          looseRadius.assign(glyphs.size(), 0.0f);
        }
        glyphs.looseBoxes[g] = 1;
        // Rounded up past the double bound (float keeps 24 bits).
        looseRadius[g] = float(radius * (1.0 + 1e-6));
        ++glyphs.looseBoxCount;
        continue;
      }
    }
    missing.push_back(g);
  }
  // Glyphs of one order together (trailing zero bands lower some), so that the kernel's
  // batches share its direction tables.
  std::stable_sort(missing.begin(), missing.end(),
    [&](std::size_t a, std::size_t b) { return glyphs.orders[a] < glyphs.orders[b]; });
  for (std::size_t start = 0; start < missing.size(); start += kBoxBlock)
  {
    const std::size_t end = std::min(missing.size(), start + kBoxBlock);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(start, end, kSearchGrain),
      [&](const tbb::blocked_range<std::size_t>& range)
      {
        const double* coefficients[kSearchGrain * 2];
        dvec3 halfExtents[kSearchGrain * 2];
        for (std::size_t first = range.begin(); first < range.end();)
        {
          // The run of one order, at most as long as the arrays.
          const int order = glyphs.orders[missing[first]];
          std::size_t last = first;
          while (last < range.end() && last - first < kSearchGrain * 2 && glyphs.orders[missing[last]] == order)
          {
            coefficients[last - first] = glyphs.coefficients.data() + glyphs.offsets[missing[last]];
            ++last;
          }
          shGlyphHalfExtents(order, last - first, coefficients, halfExtents);
          for (std::size_t m = first; m < last; ++m)
            Cache.halfExtents[glyphs.points[missing[m]]] = vec3(halfExtents[m - first]);
          first = last;
        }
      });
    if (request.progress)
      request.progress(double(end) / double(missing.size()));
  }
  glyphs.computedBoxes = missing.size();
  glyphs.halfExtents.resize(glyphs.size());
  for (std::size_t g = 0; g < glyphs.size(); ++g)
    glyphs.halfExtents[g] = (glyphs.looseBoxes.empty() || !glyphs.looseBoxes[g]
      ? Cache.halfExtents[glyphs.points[g]] : vec3(looseRadius[g])) * std::abs(glyphs.scales[g]);
}

PreparedSHGlyphs SHGlyphPreparation::prepareAlongside(const GlyphSource& source,
  const PreparedSHGlyphs& reference, const GlyphRequest& request)
{
  std::vector<char> finite;
  std::vector<double> canonical = begin(source, reference.points, request.rotation, finite);
  const int order = source.order;
  const int count = shCoefficientCount(order);
  const bool turned = request.rotation != dmat3(1.0);
  const SHRotation rotation(turned ? order : 0, request.rotation);
  PreparedSHGlyphs glyphs;
  for (std::size_t g = 0; g < reference.size(); ++g)
  {
    double* c = canonical.data() + g * count;
    if (!finite[g])
      countNonFinite(glyphs.drops, reference.points[g]);
    else if (allZero(c, count))
      ++glyphs.drops.empty;
    else
      append(glyphs, reference.points[g], reference.scales[g], order, c, turned ? &rotation : nullptr);
  }
  computeBoxes(glyphs, request);
  return glyphs;
}

PreparedEllipsoids SHGlyphPreparation::prepareEllipsoids(
  const GlyphSource& tensors, const GlyphRequest& request)
{
  if (tensors.order != 2)
    throw std::invalid_argument("ellipsoids need second-order tensors, not order " +
      std::to_string(tensors.order));
  checkPoints(tensors, request.points);
  constexpr int kUnique = symmetricTensorComponentCount(2);
  struct Decomposed
  {
    double values[3];
    dmat3 vectors;
    double largest = 0.0;
    bool finite = false;
  };
  auto decompose = [&](std::size_t point)
  {
    Decomposed d;
    double t[kUnique];
    tensors.read(point, t);
    d.finite = std::all_of(t, t + kUnique, [](double v) { return std::isfinite(v); });
    if (!d.finite)
      return d;
    symmetricEigenDecomposition(t, d.values, d.vectors);
    for (double value : d.values)
      d.largest = std::max(d.largest, std::abs(value));
    return d;
  };

  double global = 0.0;
  if (request.normalization == GlyphNormalization::Global)
    for (std::size_t point = 0; point < tensors.pointCount; ++point)
      global = std::max(global, decompose(point).largest);

  // Only the coefficient norm needs the SH form (the norm of F over the sphere).
  const TensorToSH toSH(2);
  PreparedEllipsoids ellipsoids;
  for (std::size_t point : request.points)
  {
    const Decomposed d = decompose(point);
    if (!d.finite)
    {
      countNonFinite(ellipsoids.drops, point);
      continue;
    }
    double norm = 0.0;
    if (request.normalization == GlyphNormalization::CoefficientNorm)
    {
      double t[kUnique], sh[kUnique];
      tensors.read(point, t);
      toSH.apply(t, sh);
      norm = canonicalNorm(sh, kUnique);
    }
    const double divisor = normalizationDivisor(request.normalization, d.largest, norm, global);
    if (!(d.largest > 0.0) || !usableDivisor(divisor))
    {
      ++ellipsoids.drops.empty;
      continue;
    }
    const double scale = request.worldScale / divisor;
    dmat3 axes;
    int principal = 0;
    for (int c = 0; c < 3; ++c)
    {
      axes[c] = request.rotation * d.vectors[c] *
        (scale * std::max(std::abs(d.values[c]), 1e-3 * d.largest));
      if (std::abs(d.values[c]) > std::abs(d.values[principal]))
        principal = c;
    }
    ellipsoids.points.push_back(point);
    ellipsoids.axes.push_back(axes);
    const dvec3 direction = glm::abs(request.rotation * d.vectors[principal]);
    auto channel = [](double v) { return std::uint8_t(std::lround(255.0 * std::min(1.0, v))); };
    ellipsoids.directionColors.push_back(
      packRGBA8(channel(direction.x), channel(direction.y), channel(direction.z)));
    if (request.maxAmplitudes)
      ellipsoids.maxAmplitudes.push_back(float(d.largest));
  }
  return ellipsoids;
}
} // namespace sightline
