// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/glyphs/SHGlyphSet.h"

#include "sightline/math/SymmetricTensor.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <numeric>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
namespace
{
vec3 unpackRGB(std::uint32_t c)
{
  return vec3(float(c & 0xffu), float((c >> 8) & 0xffu), float((c >> 16) & 0xffu)) / 255.0f;
}

void addReason(ValidationReport& report, std::size_t& counter, std::size_t index, const char* what)
{
  if (counter++ == 0)
    report.reasons.push_back("glyph " + std::to_string(index) + " " + what +
      " (first of the glyphs skipped for this reason)");
  ++report.rejected;
}
} // namespace

SHGlyphSet::SHGlyphSet(const std::vector<vec3>& centers, const std::vector<float>& coefficients,
  int order, const SHGlyphOptions& options, const std::vector<float>& scales,
  const std::vector<std::uint32_t>& colors, const std::vector<vec3>& halfExtents)
  : Options(options)
{
  if (order < 0 || order > kMaxGlyphOrder || order % 2 != 0)
    throw std::invalid_argument("SH glyph order " + std::to_string(order) +
      " is not an even number in [0, " + std::to_string(kMaxGlyphOrder) + "]");
  const std::size_t stride = std::size_t(shCoefficientCount(order));
  const std::size_t n = centers.size();
  if (coefficients.size() != n * stride)
    throw std::invalid_argument("SH coefficient array has " + std::to_string(coefficients.size()) +
      " values; " + std::to_string(n) + " glyphs of order " + std::to_string(order) + " need " +
      std::to_string(n * stride) + " (" + std::to_string(stride) + " per glyph)");
  if (!scales.empty() && scales.size() != n)
    throw std::invalid_argument("SH glyph scale array has " + std::to_string(scales.size()) +
      " values for " + std::to_string(n) + " glyphs");
  if (!halfExtents.empty() && halfExtents.size() != n)
    throw std::invalid_argument("SH glyph box array has " + std::to_string(halfExtents.size()) +
      " half-extents for " + std::to_string(n) + " glyphs");
  checkOptions(order, n, colors);

  const SHConversion conversion = SHConversion::toCanonical(options.convention, order);
  std::vector<double> canonical(stride);
  Glyphs.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const float* input = coefficients.data() + i * stride;
    const float scale = scales.empty() ? 1.0f : scales[i];
    if (!std::all_of(input, input + stride, [](float v) { return std::isfinite(v); }) ||
      !std::isfinite(scale))
    {
      addReason(Report, NonFiniteCount, i, "has a non-finite centre, coefficient or scale");
      continue;
    }
    conversion.apply(input, canonical.data());
    for (double& c : canonical)
      c *= scale;
    if (std::all_of(canonical.begin(), canonical.end(), [](double c) { return c == 0.0; }))
    {
      addReason(Report, ZeroCount, i, "has only zero coefficients (nothing to draw)");
      continue;
    }
    const int glyphOrder = options.trimZeroBands ? shEffectiveOrder(order, canonical.data()) : order;
    addGlyph(centers[i], glyphOrder, canonical.data(), scale,
      halfExtents.empty() ? vec3(-1.0f) : halfExtents[i], i, colors);
  }
  finish();
}

SHGlyphSet::SHGlyphSet(const std::vector<vec3>& centers, const PreparedSHGlyphs& glyphs,
  const SHGlyphOptions& options, const std::vector<std::uint32_t>& colors)
  : Options(options)
{
  const std::size_t n = glyphs.size();
  if (centers.size() != n)
    throw std::invalid_argument("SH glyph centre array has " + std::to_string(centers.size()) +
      " centres for " + std::to_string(n) + " prepared glyphs");
  int order = 0;
  for (std::uint8_t glyphOrder : glyphs.orders)
    order = std::max(order, int(glyphOrder));
  checkOptions(order, n, colors);
  Glyphs.reserve(n);
  std::vector<double> scaled;
  for (std::size_t i = 0; i < n; ++i)
  {
    const double* c = glyphs.coefficients.data() + glyphs.offsets[i];
    scaled.assign(c, c + shCoefficientCount(glyphs.orders[i]));
    for (double& value : scaled)
      value *= glyphs.scales[i];
    addGlyph(centers[i], glyphs.orders[i], scaled.data(), glyphs.scales[i], glyphs.halfExtents[i],
      i, colors);
  }
  finish();
}

void SHGlyphSet::checkOptions(int order, std::size_t n, const std::vector<std::uint32_t>& colors) const
{
  const SHGlyphOptions& options = Options;
  if (!colors.empty() && colors.size() != n)
    throw std::invalid_argument("SH glyph colour array has " + std::to_string(colors.size()) +
      " values for " + std::to_string(n) + " glyphs");
  if (options.method == SHIntersectionMethod::RayMarching &&
    (options.marchingSteps < 1 || options.bisectionSteps < 0))
    throw std::invalid_argument("ray marching needs at least one step");
  const bool tensorMethod = options.method == SHIntersectionMethod::TensorMarching ||
    options.method == SHIntersectionMethod::IntervalSubdivision;
  if (tensorMethod && order > kMaxTensorOrder)
    throw std::invalid_argument("the tensor glyph methods (marching, interval subdivision) support "
      "orders up to " + std::to_string(kMaxTensorOrder) + ", not " + std::to_string(order));
  if (options.method == SHIntersectionMethod::TensorMarching &&
    !(options.tensorMarching.stepSize > 0.0 && options.tensorMarching.centreStepFactor > 0.0 &&
      options.tensorMarching.centreStepFactor <= 1.0 && options.tensorMarching.bisectionSteps >= 0))
    throw std::invalid_argument("tensor marching needs a positive step size, a centre step factor "
      "in (0, 1] and no negative bisection count");
  if (options.method == SHIntersectionMethod::IntervalSubdivision &&
    !(options.subdivision.tolerance > 0.0 && options.subdivision.tolerance < 1.0))
    throw std::invalid_argument("interval subdivision needs a tolerance in (0, 1)");
  if (options.coloring == SHColoring::Radius &&
    (options.colormap.empty() || !(options.radiusRange.y > options.radiusRange.x)))
    throw std::invalid_argument("radius colouring needs a colormap and a radius range lo < hi");
}

void SHGlyphSet::addGlyph(const vec3& center, int order, const double* scaled, float scale,
  const vec3& halfExtents, std::size_t index, const std::vector<std::uint32_t>& colors)
{
  const int count = shCoefficientCount(order);
  if (!isFinite(center))
  {
    addReason(Report, NonFiniteCount, index, "has a non-finite centre, coefficient or scale");
    return;
  }
  Glyph glyph;
  glyph.center = dvec3(center);
  glyph.order = std::uint8_t(order);
  glyph.offset = std::uint32_t(DoubleCoefficients.size());
  glyph.useFloat = Options.precision == SHPrecision::Float;
  glyph.scale = scale;
  // A cached box is only trusted when it is a box: NaN marks "not computed yet".
  glyph.halfExtents = isFinite(halfExtents) && halfExtents.x >= 0.0f ? halfExtents : vec3(-1.0f);
  DoubleCoefficients.insert(DoubleCoefficients.end(), scaled, scaled + count);
  Glyphs.push_back(glyph);
  SourceIndex.push_back(std::uint32_t(index));
  if (!colors.empty())
    Colors.push_back(colors[index]);
}

void SHGlyphSet::finish()
{
  FloatCoefficients.assign(DoubleCoefficients.begin(), DoubleCoefficients.end());
  if (Options.coloring == SHColoring::PerGlyph && Colors.empty())
    Options.coloring = SHColoring::Material;

  // Boxes: the near-exact ones (Section 4.2) unless a baseline asks for its bounding sphere.
  // The tensor methods march inside the sphere of the longest lobe (padded by 0.1 %: the lobe
  // search is a refined sampling) in the seed's unit-ball frame.
  const bool tensorMethod = Options.method == SHIntersectionMethod::TensorMarching ||
    Options.method == SHIntersectionMethod::IntervalSubdivision;
  const bool tight = Options.method == SHIntersectionMethod::RootFinding || Options.marchingUsesTightBoxes;
  if (tensorMethod)
    Cartesian.resize(Glyphs.size());
  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(std::size_t(0), Glyphs.size(), [&](std::size_t i)
    {
      Glyph& glyph = Glyphs[i];
      const double* b = DoubleCoefficients.data() + glyph.offset;
      glyph.boundingRadius = float(shGlyphBoundingRadius(glyph.order, b));
      if (tensorMethod)
      {
        glyph.maxRadius = float(1.001 * shGlyphMaxRadius(glyph.order, b));
        Cartesian[i] = CartesianGlyphFunction::fromSH(glyph.order, b, glyph.maxRadius);
      }
      if (!tight)
        glyph.halfExtents = vec3(tensorMethod ? glyph.maxRadius : glyph.boundingRadius);
      else if (glyph.halfExtents.x < 0.0f)
        glyph.halfExtents = vec3(shGlyphHalfExtents(glyph.order, b));
      glyph.box.lower = vec3(glyph.center - dvec3(glyph.halfExtents));
      glyph.box.upper = vec3(glyph.center + dvec3(glyph.halfExtents));
    });
  BoundsSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const Glyph& glyph : Glyphs)
    AllBounds.extend(glyph.box);
}

SHGlyphSet::SHGlyphSet(const dvec3& origin, const std::vector<vec3>& centers,
  const std::vector<float>& coefficients, int order, const SHGlyphOptions& options,
  const std::vector<float>& scales, const std::vector<std::uint32_t>& colors,
  const std::vector<vec3>& halfExtents)
  : SHGlyphSet(centers, coefficients, order, options, scales, colors, halfExtents)
{
  moveTo(origin);
}

SHGlyphSet::SHGlyphSet(const dvec3& origin, const std::vector<vec3>& centers,
  const PreparedSHGlyphs& glyphs, const SHGlyphOptions& options,
  const std::vector<std::uint32_t>& colors)
  : SHGlyphSet(centers, glyphs, options, colors)
{
  moveTo(origin);
}

void SHGlyphSet::moveTo(const dvec3& origin)
{
  if (!(std::isfinite(origin.x) && std::isfinite(origin.y) && std::isfinite(origin.z)))
    throw std::invalid_argument("sightline::SHGlyphSet: the origin must be finite");
  // Centres are double already: move them, and the boxes with them.
  AllBounds = Box3{};
  for (Glyph& glyph : Glyphs)
  {
    glyph.center += origin;
    glyph.box.lower = vec3(glyph.center - dvec3(glyph.halfExtents));
    glyph.box.upper = vec3(glyph.center + dvec3(glyph.halfExtents));
    AllBounds.extend(glyph.box);
  }
}

double shMaxAmplitude(int order, const float* coefficients, const SHConvention& convention)
{
  if (order < 0 || order > kMaxSHOrder || order % 2 != 0)
    throw std::invalid_argument("SH order " + std::to_string(order) + " is not an even number in [0, " +
      std::to_string(kMaxSHOrder) + "]");
  std::vector<double> c(shCoefficientCount(order));
  SHConversion::toCanonical(convention, order).apply(coefficients, c.data());
  return shGlyphMaxRadius(order, c.data());
}

double shCoefficientNorm(int order, const float* coefficients, const SHConvention& convention)
{
  const int count = shCoefficientCount(order);
  std::vector<double> c(count);
  SHConversion::toCanonical(convention, order).apply(coefficients, c.data());
  double sum = 0.0;
  for (double v : c)
    sum += v * v;
  return std::sqrt(sum);
}

vec3 SHGlyphSet::primitiveColor(unsigned primitive) const
{
  return Colors.empty() ? material.color : unpackRGB(Colors[primitive]);
}

vec3 SHGlyphSet::surfaceColor(unsigned primitive, const dvec3& point) const
{
  const Glyph& glyph = Glyphs[primitive];
  const dvec3 p = dvec3(point) - glyph.center;
  const double r = glm::length(p);
  const dvec3 w = r > 0.0 ? p / r : dvec3(0.0, 0.0, 1.0);
  if (Options.negativeLobeColor.x >= 0.0f &&
    evaluateSHSum<double>(glyph.order, coefficients(primitive), w.x, w.y, w.z) < 0.0)
    return Options.negativeLobeColor;
  if (Options.coloring == SHColoring::PerGlyph)
    return unpackRGB(Colors[primitive]);
  if (Options.coloring == SHColoring::Material)
    return material.color;
  if (Options.coloring == SHColoring::Radius)
  {
    const float value = float(r) / glyph.scale;
    const float u = glm::clamp((value - Options.radiusRange.x) / (Options.radiusRange.y - Options.radiusRange.x), 0.0f, 1.0f);
    const float position = u * float(Options.colormap.size() - 1);
    const std::size_t index = std::min(std::size_t(position), Options.colormap.size() - 1);
    const std::size_t next = std::min(index + 1, Options.colormap.size() - 1);
    return glm::mix(Options.colormap[index], Options.colormap[next], position - float(index));
  }
  return vec3(glm::abs(w));
}

std::size_t SHGlyphSet::memoryBytes() const
{
  return Glyphs.capacity() * sizeof(Glyph) + DoubleCoefficients.capacity() * sizeof(double) +
    FloatCoefficients.capacity() * sizeof(float) + Colors.capacity() * sizeof(std::uint32_t) +
    std::accumulate(Cartesian.begin(), Cartesian.end(), std::size_t(0),
      [](std::size_t sum, const CartesianGlyphFunction& f) { return sum + f.memoryBytes(); }) +
    SourceIndex.capacity() * sizeof(std::uint32_t);
}

int SHGlyphSet::exactIntersections(const Glyph& glyph, const DoubleRay& ray, double* t, bool firstOnly) const
{
  // The glyph's frame: the double ray's origin relative to the centre (the glyph may be far
  // from the world origin), then the arithmetic chosen for this glyph.
  const dvec3 o = dvec3(ray.origin) - glyph.center;
  const dvec3 d = dvec3(ray.direction);
  const double length = glm::length(d);
  const dvec3 du = d / length;
  double tmin = double(ray.tnear) * length, tmax = double(ray.tfar) * length;
  // A line farther from the centre than the glyph's bounding sphere (the coefficient bound,
  // known for every glyph; its float rounding absorbed by the factor) misses it: cheaper than
  // the SH sums, and it culls the rays through a box's corners.
  {
    const dvec3 closest = o - glm::dot(o, du) * du;
    const double radius = double(glyph.boundingRadius) * (1.0 + 1e-6);
    if (glm::dot(closest, closest) > radius * radius)
      return 0;
  }
  // Clip the ray to the glyph's box (the BVH leaf may hold several glyphs, and a shorter
  // interval means less root isolation); the box encloses the glyph with padding already,
  // the margin only absorbs rounding in this test.
  {
    const double margin = 1e-5 * double(std::max(glyph.halfExtents.x,
      std::max(glyph.halfExtents.y, glyph.halfExtents.z)));
    double t0 = tmin, t1 = tmax;
    for (int axis = 0; axis < 3; ++axis)
    {
      const double h = double(glyph.halfExtents[axis]) + margin;
      const double inv = 1.0 / du[axis];
      double ta = (-h - o[axis]) * inv, tb = (h - o[axis]) * inv;
      if (ta > tb)
        std::swap(ta, tb);
      // An axis-parallel ray (inv infinite) inside the slab gives -inf..inf; NaN keeps t0/t1.
      t0 = ta > t0 ? ta : t0;
      t1 = tb < t1 ? tb : t1;
    }
    if (!(t0 <= t1))
      return 0;
    tmin = t0;
    tmax = t1;
  }
  int count;
  if (glyph.useFloat)
  {
    const float of[3] = { float(o.x), float(o.y), float(o.z) };
    const float df[3] = { float(du.x), float(du.y), float(du.z) };
    float tf[kMaxGlyphHits];
    const float tolerance = Options.tolerance > 0.0 ? float(Options.tolerance) : defaultGlyphTolerance<float>();
    count = intersectSHGlyph<float>(glyph.order, FloatCoefficients.data() + glyph.offset, of, df,
      float(tmin), std::min(float(tmax), std::numeric_limits<float>::max()), tolerance, tf, firstOnly);
    for (int i = 0; i < count; ++i)
      t[i] = double(tf[i]);
  }
  else
  {
    const double od[3] = { o.x, o.y, o.z };
    const double dd[3] = { du.x, du.y, du.z };
    const double tolerance = Options.tolerance > 0.0 ? Options.tolerance : defaultGlyphTolerance<double>();
    count = intersectSHGlyph<double>(glyph.order, DoubleCoefficients.data() + glyph.offset, od, dd,
      tmin, tmax, tolerance, t, firstOnly);
  }
  for (int i = 0; i < count; ++i)
    t[i] /= length;
  return count;
}

int SHGlyphSet::marchingIntersection(const Glyph& glyph, const DoubleRay& ray, double& tHit) const
{
  const double* b = DoubleCoefficients.data() + glyph.offset;
  const dvec3 o = dvec3(ray.origin) - glyph.center;
  const dvec3 d = glm::normalize(dvec3(ray.direction));
  const double length = glm::length(dvec3(ray.direction));
  const double R = glyph.boundingRadius;
  const double dO = glm::dot(d, o);
  const double eo2 = glm::dot(o, o) - dO * dO;
  if (eo2 >= R * R)
    return 0;
  const double half = Options.marchingBound == SHMarchingBound::Sphere ? std::sqrt(R * R - eo2) : R;
  const double t0 = -dO - half, t1 = -dO + half;
  const double step = (t1 - t0) / Options.marchingSteps;
  const double tmin = double(ray.tnear) * length, tmax = double(ray.tfar) * length;
  const bool positiveOnly = Options.hideNegativeLobes;
  auto inside = [&](double t)
  {
    const dvec3 p = o + t * d;
    const double r = glm::length(p);
    if (!(r > 0.0))
      return true;
    const double value = evaluateSHSum<double>(glyph.order, b, p.x / r, p.y / r, p.z / r);
    return r < (positiveOnly ? value : std::abs(value));
  };
  bool previousInside = true; // a sample can only hit after an outside sample
  double previous = t0;
  for (int i = 0; i <= Options.marchingSteps; ++i)
  {
    const double t = t0 + i * step;
    if (t < tmin)
      continue;
    if (t > tmax)
      break;
    const bool now = inside(t);
    if (now && !previousInside)
    {
      double a = previous, c = t; // bisection: a outside, c inside
      for (int j = 0; j < Options.bisectionSteps; ++j)
      {
        const double m = 0.5 * (a + c);
        (inside(m) ? c : a) = m;
      }
      tHit = c / length;
      return 1;
    }
    previousInside = now;
    previous = t;
  }
  return 0;
}

int SHGlyphSet::tensorMethodIntersection(unsigned primitive, const DoubleRay& ray, double& tHit) const
{
  // The seed's frame: glyph at the origin, lengths divided by the bounding radius.
  const Glyph& glyph = Glyphs[primitive];
  const double R = glyph.maxRadius;
  const dvec3 d = dvec3(ray.direction);
  const double length = glm::length(d);
  const dvec3 o = (dvec3(ray.origin) - glyph.center) / R;
  const double tmin = double(ray.tnear) * length / R;
  const double tmax = std::min(double(ray.tfar) * length, 1e300) / R;
  double t = 0.0;
  const bool found = Options.method == SHIntersectionMethod::TensorMarching
    ? marchTensorGlyph(Cartesian[primitive], o, d / length, tmin, tmax, Options.tensorMarching,
        Options.hideNegativeLobes, t)
    : subdivideTensorGlyph(Cartesian[primitive], o, d / length, tmin, tmax, Options.subdivision,
        Options.hideNegativeLobes, t);
  if (!found)
    return 0;
  tHit = t * R / length;
  return 1;
}

bool SHGlyphSet::intersect(unsigned primitive, const DoubleRay& ray, SurfaceHit& hit) const
{
  const Glyph& glyph = Glyphs[primitive];
  double t[kMaxGlyphHits];
  int count;
  int chosen = 0;
  if (Options.method == SHIntersectionMethod::RayMarching)
    count = marchingIntersection(glyph, ray, t[0]);
  else if (Options.method != SHIntersectionMethod::RootFinding)
    count = tensorMethodIntersection(primitive, ray, t[0]);
  else if (!Options.hideNegativeLobes)
    count = exactIntersections(glyph, ray, t, true);
  else
  {
    // Keep the first intersection with a positive lobe.
    count = exactIntersections(glyph, ray, t, false);
    const double* b = coefficients(primitive);
    for (chosen = 0; chosen < count; ++chosen)
    {
      const dvec3 p = dvec3(ray.origin) - glyph.center + t[chosen] * dvec3(ray.direction);
      const dvec3 w = glm::normalize(p);
      if (evaluateSHSum<double>(glyph.order, b, w.x, w.y, w.z) > 0.0)
        break;
    }
  }
  if (chosen >= count || !(t[chosen] > double(ray.tnear)) || !(t[chosen] < double(ray.tfar)))
    return false;
  const dvec3 p = dvec3(ray.origin) - glyph.center + t[chosen] * dvec3(ray.direction);
  hit.t = t[chosen];
  hit.normal = vec3(shGlyphNormal(glyph.order, coefficients(primitive), p));
  return true;
}

int SHGlyphSet::allIntersections(unsigned primitive, const DoubleRay& ray, double* t) const
{
  return exactIntersections(Glyphs[primitive], ray, t, false);
}

double SHGlyphSet::insideLength(unsigned primitive, const DoubleRay& ray, float& entry) const
{
  const Glyph& glyph = Glyphs[primitive];
  double roots[kMaxGlyphHits + 2];
  // Double arithmetic here: volume rendering integrates over all intersections.
  const dvec3 o = dvec3(ray.origin) - glyph.center;
  const dvec3 d = dvec3(ray.direction);
  const double length = glm::length(d);
  const dvec3 du = d / length;
  const double tmin = double(ray.tnear) * length;
  const double tmax = std::min(double(ray.tfar) * length, 1e300);
  const double od[3] = { o.x, o.y, o.z }, dd[3] = { du.x, du.y, du.z };
  const int count = intersectSHGlyph<double>(glyph.order, coefficients(primitive), od, dd, tmin,
    tmax, defaultGlyphTolerance<double>(), roots + 1, false);
  if (count == 0 && !insideSHGlyph(glyph.order, coefficients(primitive), o + tmin * du))
    return 0.0;
  // Segments between consecutive intersections; the midpoint tells inside from outside, so
  // touching (double) roots cannot flip the parity.
  roots[0] = tmin;
  double end = tmax;
  if (!std::isfinite(end))
    end = roots[count] + 1.0; // after the last intersection the ray is outside
  roots[count + 1] = end;
  double inside = 0.0;
  for (int i = 0; i <= count; ++i)
  {
    const double a = roots[i], b = roots[i + 1];
    if (b <= a)
      continue;
    if (insideSHGlyph(glyph.order, coefficients(primitive), o + (0.5 * (a + b)) * du))
    {
      inside += b - a;
      entry = std::min(entry, float(a / length));
    }
  }
  return inside / length;
}
} // namespace sightline
