// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/volumes/SphericalVolume.h"

#include "sightline/volumes/GridTraversal.h"
#include "sightline/volumes/SphericalFields.h"

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace sightline
{
namespace
{
// What the renderer needs from a kind of grid: its traversal, the value index of a segment's
// cell, and the radius of the outermost shell holding a visible cell, to clip rays to (a sphere
// for spherical grids, a cylinder around z for cylindrical ones).
struct SphericalCells
{
  const SphericalTraversal& traversal;
  std::size_t index(const CellSegment& s) const { return traversal.grid().cellIndex(s.r, s.theta, s.phi); }
  const std::vector<double>& radii() const { return traversal.grid().radius; }
  std::size_t cellCount() const { return traversal.grid().cellCount(); }
  bool visibleShell(const std::vector<TransferSample>& cells, int i) const
  {
    const SphericalGrid& g = traversal.grid();
    for (int k = 0; k < g.azimuthalCells(); ++k)
      for (int j = 0; j < g.polarCells(); ++j)
        if (cells[g.cellIndex(i, j, k)].extinction > 0.0)
          return true;
    return false;
  }
  bool clip(const dvec3& o, const dvec3& d, double radius, double t0, double t1, double& enter, double& leave) const
  {
    return sphereChord(o, d, radius, t0, t1, enter, leave);
  }
};

struct CylindricalCells
{
  const CylindricalTraversal& traversal;
  std::size_t index(const CellSegment& s) const { return traversal.grid().cellIndex(s.r, s.phi, s.theta); }
  const std::vector<double>& radii() const { return traversal.grid().radius; }
  std::size_t cellCount() const { return traversal.grid().cellCount(); }
  bool visibleShell(const std::vector<TransferSample>& cells, int i) const
  {
    const CylindricalGrid& g = traversal.grid();
    for (int k = 0; k < g.heightCells(); ++k)
      for (int j = 0; j < g.azimuthalCells(); ++j)
        if (cells[g.cellIndex(i, j, k)].extinction > 0.0)
          return true;
    return false;
  }
  bool clip(const dvec3& o, const dvec3& d, double radius, double t0, double t1, double& enter, double& leave) const
  {
    const double a = d.x * d.x + d.y * d.y;
    enter = t0;
    leave = t1;
    if (a == 0.0)
      return std::hypot(o.x, o.y) < radius && t0 < t1;
    const double tc = -(o.x * d.x + o.y * d.y) / a;
    const double c = std::hypot(o.x + tc * d.x, o.y + tc * d.y);
    if (!(c < radius))
      return false;
    const double half = std::sqrt((radius - c) * (radius + c) / a);
    enter = std::max(t0, tc - half);
    leave = std::min(t1, tc + half);
    return enter < leave;
  }
};

// Empty space: the radius of the outermost shell with a visible cell (-1 when none is).
template <class Cells>
double visibleRadiusOf(const Cells& grid, const std::vector<TransferSample>& cells)
{
  for (int i = int(grid.radii().size()) - 2; i >= 0; --i)
    if (grid.visibleShell(cells, i))
      return grid.radii()[std::size_t(i) + 1];
  return -1.0;
}

/// Traces every pixel: rays clipped to the visible radius (nothing traced when it is < 0) and
/// to the depth limit, then traversed and composited by `composite(origin, direction, enter,
/// leave, &first, &count)` into premultiplied RGBA.
template <class Cells, class Composite>
SphericalVolumeStatistics renderCells(const Cells& grid, double visibleRadius, const Composite& composite,
  const Camera& camera, Framebuffer& framebuffer, const SphericalVolumeOptions& options, const char* who)
{
  const auto start = std::chrono::steady_clock::now();
  framebuffer.resize(camera.width(), camera.height());
  if (options.depthLimit && options.depthLimit->size() != framebuffer.pixelCount())
    throw std::invalid_argument(std::string("sightline::") + who + ": the depth limit has " +
      std::to_string(options.depthLimit->size()) + " values for " + std::to_string(framebuffer.pixelCount()) + " pixels");
  SphericalVolumeStatistics stats;
  if (visibleRadius < 0.0)
  {
    if (options.progress)
      options.progress(1.0);
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
  }

  const bool regionClipped = !(glm::all(glm::isinf(options.regionLower)) && glm::all(glm::isinf(options.regionUpper)) &&
    glm::all(glm::lessThan(options.regionLower, dvec3(0.0))) && glm::all(glm::greaterThan(options.regionUpper, dvec3(0.0))));

  // Bands of rows one after another, so that progress is reported and a cancel takes effect.
  const int bands = options.progress ? std::min(camera.height(), 16) : 1;
  tbb::combinable<std::size_t> visited([] { return std::size_t(0); });
  for (int band = 0; band < bands; ++band)
  {
    const int firstRow = int(std::int64_t(camera.height()) * band / bands);
    const int endRow = int(std::int64_t(camera.height()) * (band + 1) / bands);
    // Tiles of 16 x 16 pixels: neighbouring rays read neighbouring cells while they are still
    // cached (a row of rays sweeps a whole slice of the grid between two rows).
    tbb::parallel_for(tbb::blocked_range2d<int>(firstRow, endRow, 16, 0, camera.width(), 16),
      [&](const tbb::blocked_range2d<int>& tile)
      {
        std::size_t count = 0;
        for (int y = tile.rows().begin(); y < tile.rows().end(); ++y)
          for (int x = tile.cols().begin(); x < tile.cols().end(); ++x)
          {
            // The exact pixel ray: a float one is off by 2^-24 of its origin's distance, which
            // rays tangent to a shell turn into relative errors of 1e-3 in optical depth.
            const DoubleRay ray = camera.doublePrimaryRay(x + 0.5, y + 0.5);
            const dvec3& o = ray.origin;
            const dvec3& d = ray.direction;
            double tmax = ray.tfar;
            const std::size_t i = framebuffer.index(x, y);
            if (options.depthLimit && (*options.depthLimit)[i] < 1.0f)
              tmax = camera.primaryRayParameterAt(x + 0.5, y + 0.5, (*options.depthLimit)[i]);
            double tmin = ray.tnear;
            if (regionClipped)
            {
              const dvec3 worldOrigin = dvec3(options.objectToWorld * dvec4(o, 1.0));
              const dvec3 worldDirection = glm::dmat3(options.objectToWorld) * d;
              if (!clipToBox(worldOrigin, worldDirection, options.regionLower, options.regionUpper, tmin, tmax))
                continue;
            }
            double enter, leave;
            if (!grid.clip(o, d, visibleRadius, tmin, tmax, enter, leave))
              continue;
            double first = -1.0;
            const vec4 rgba = composite(o, d, enter, leave, &first, &count);
            if (!(rgba.a > 0.0f))
              continue;
            framebuffer.Color[i] = vec4(vec3(rgba) / rgba.a, rgba.a);
            const dvec3 front = o + first * d;
            framebuffer.Depth[i] = float(std::clamp(camera.windowDepth(front), 0.0, 1.0));
            framebuffer.Distance[i] = float(first);
          }
        visited.local() += count;
      },
      tbb::simple_partitioner());
    if (options.progress && !options.progress(double(band + 1) / bands))
      break;
  }
  stats.cellsVisited = visited.combine([](std::size_t a, std::size_t b) { return a + b; });
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

double centreOf(const std::vector<double>& b, int i)
{
  return 0.5 * (b[std::size_t(i)] + b[std::size_t(i) + 1]);
}

// d value / d coordinate between the neighbours of cell i along an axis of n cells with
// breakpoints b: central differences, one-sided at a section's edges, across the seam of a
// full circle.
template <class ValueAt>
double centralDifference(int i, int n, bool periodic, const std::vector<double>& b, const ValueAt& valueAt)
{
  if (n < 2)
    return 0.0;
  int lo = i - 1, hi = i + 1;
  double clo, chi;
  if (periodic)
  {
    const double span = b.back() - b.front();
    clo = lo < 0 ? centreOf(b, n - 1) - span : centreOf(b, lo);
    chi = hi >= n ? centreOf(b, 0) + span : centreOf(b, hi);
    lo = (lo + n) % n;
    hi = hi % n;
  }
  else
  {
    lo = std::max(lo, 0);
    hi = std::min(hi, n - 1);
    clo = centreOf(b, lo);
    chi = centreOf(b, hi);
  }
  return (valueAt(hi) - valueAt(lo)) / (chi - clo);
}

void checkValueCount(std::size_t values, std::size_t cells, const char* who)
{
  if (values != cells)
    throw std::invalid_argument(std::string("sightline::") + who + ": " + std::to_string(values) +
      " values for " + std::to_string(cells) + " cells");
}
} // namespace

SphericalVolumeStatistics renderSphericalVolume(const SphericalTraversal& traversal,
  const std::vector<double>& values, const std::function<TransferSample(double)>& transfer,
  const Camera& camera, Framebuffer& framebuffer, const SphericalVolumeOptions& options)
{
  checkValueCount(values.size(), traversal.grid().cellCount(), "renderSphericalVolume");
  // The transfer function once per cell, not once per ray and cell.
  std::vector<TransferSample> cells(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    cells[i] = transfer(values[i]);
  return renderSphericalVolume(traversal, cells, camera, framebuffer, options);
}

namespace
{
template <class Cells>
SphericalVolumeStatistics renderCellData(const Cells& grid, const std::vector<TransferSample>& cells,
  const Camera& camera, Framebuffer& framebuffer, const SphericalVolumeOptions& options, const char* who)
{
  if (cells.size() != grid.cellCount())
    throw std::invalid_argument(std::string("sightline::") + who + ": " + std::to_string(cells.size()) +
      " cell samples for " + std::to_string(grid.cellCount()) + " cells");
  return renderCells(grid, visibleRadiusOf(grid, cells),
    [&](const dvec3& o, const dvec3& d, double enter, double leave, double* first, std::size_t* count)
    {
      // Cells composited as the traversal reaches them: no list of segments, and the merge
      // stops where the ray saturates.
      CellCompositor compositor;
      compositor.minimumTransmittance = options.minimumTransmittance;
      grid.traversal.forEachCell(o, d, enter, leave,
        [&](int i0, int i1, int i2, double t0, double t1)
        { return compositor.add(cells[grid.index(CellSegment{ i0, i1, i2, t0, t1 })], t0, t1); });
      *first = compositor.first;
      *count += compositor.visited;
      return compositor.rgba();
    },
    camera, framebuffer, options, who);
}

// Trilinear weights of a coordinate inside [b_i, b_{i+1}], clamped against rounding.
double weightIn(const std::vector<double>& b, int i, double x)
{
  return std::clamp((x - b[std::size_t(i)]) / (b[std::size_t(i) + 1] - b[std::size_t(i)]), 0.0, 1.0);
}

double unwrapAzimuth(double phi, double phi0)
{
  return phi0 + std::fmod(std::fmod(phi - phi0, kTwoPi) + kTwoPi,
                  kTwoPi);
}

// Point data through a cell-segment traversal: `valueAt(segment, point)` interpolates the
// point values inside the segment's cell.
template <class Cells, class ValueAt>
SphericalVolumeStatistics renderPointData(const Cells& grid, const ValueAt& valueAt,
  const TransferTable& transfer, double sampleDistance, const Camera& camera, Framebuffer& framebuffer,
  const SphericalVolumeOptions& options, const char* who)
{
  if (!(sampleDistance > 0.0))
    throw std::invalid_argument(std::string("sightline::") + who + ": the sample distance must be positive, got " +
      std::to_string(sampleDistance));
  if (transfer.entries.empty())
    throw std::invalid_argument(std::string("sightline::") + who + ": the transfer table is empty");
  return renderCells(grid, grid.radii().back(),
    [&](const dvec3& o, const dvec3& d, double enter, double leave, double* first, std::size_t* count)
    {
      dvec3 color(0.0);
      double transmittance = 1.0;
      *first = -1.0;
      const double dl = glm::length(d);
      grid.traversal.forEachCell(o, d, enter, leave, [&](int i0, int i1, int i2, double t0, double t1)
      {
        const CellSegment s{ i0, i1, i2, t0, t1 };
        const double length = (s.t1 - s.t0) * dl;
        const int samples = std::max(1, int(std::ceil(length / sampleDistance)));
        const double step = (s.t1 - s.t0) / samples;
        ++*count;
        for (int k = 0; k < samples; ++k)
        {
          const double t = s.t0 + (k + 0.5) * step;
          const double v = valueAt(s, o + t * d);
          if (std::isnan(v))
            continue;
          const TransferSample sample = transfer(v);
          if (!(sample.extinction > 0.0))
            continue;
          if (*first < 0.0)
            *first = s.t0 + k * step;
          const double absorbed = 1.0 - std::exp(-sample.extinction * step * dl);
          color += transmittance * absorbed * dvec3(sample.color);
          transmittance *= 1.0 - absorbed;
        }
        return !(transmittance < options.minimumTransmittance);
      });
      return vec4(vec3(color), float(1.0 - transmittance));
    },
    camera, framebuffer, options, who);
}

void checkPointCount(std::size_t values, std::size_t points, const char* who)
{
  if (values != points)
    throw std::invalid_argument(std::string("sightline::") + who + ": " + std::to_string(values) +
      " point values for " + std::to_string(points) + " points");
}
} // namespace

TransferSample TransferTable::operator()(double value) const
{
  const std::size_t n = entries.size();
  if (n == 1 || !(maximum > minimum))
    return entries.front();
  const double x = std::clamp((value - minimum) / (maximum - minimum), 0.0, 1.0) * double(n - 1);
  const std::size_t i = std::min(std::size_t(x), n - 2);
  const double w = x - double(i);
  TransferSample s;
  s.color = glm::mix(entries[i].color, entries[i + 1].color, float(w));
  s.extinction = (1.0 - w) * entries[i].extinction + w * entries[i + 1].extinction;
  return s;
}

SphericalVolumeStatistics renderSphericalVolume(const SphericalTraversal& traversal,
  const std::vector<TransferSample>& cells, const Camera& camera, Framebuffer& framebuffer,
  const SphericalVolumeOptions& options)
{
  return renderCellData(SphericalCells{ traversal }, cells, camera, framebuffer, options, "renderSphericalVolume");
}

SphericalVolumeStatistics renderCylindricalVolume(const CylindricalTraversal& traversal,
  const std::vector<TransferSample>& cells, const Camera& camera, Framebuffer& framebuffer,
  const SphericalVolumeOptions& options)
{
  return renderCellData(CylindricalCells{ traversal }, cells, camera, framebuffer, options, "renderCylindricalVolume");
}

SphericalVolumeStatistics renderSphericalVolumePoints(const SphericalTraversal& traversal,
  const std::vector<double>& pointValues, const TransferTable& transfer, double sampleDistance,
  const Camera& camera, Framebuffer& framebuffer, const SphericalVolumeOptions& options)
{
  const SphericalGrid& g = traversal.grid();
  const std::size_t nr = g.radius.size(), nt = g.polar.size();
  checkPointCount(pointValues.size(), nr * nt * g.azimuth.size(), "renderSphericalVolumePoints");
  const double phi0 = g.azimuth.front();
  auto valueAt = [&](const CellSegment& s, const dvec3& x)
  {
    const double r = glm::length(x);
    const double theta = r > 0.0 ? std::acos(std::clamp(x.z / r, -1.0, 1.0)) : g.polar[std::size_t(s.theta)];
    const double phi = unwrapAzimuth(std::atan2(x.y, x.x), phi0);
    const double wr = weightIn(g.radius, s.r, r), wt = weightIn(g.polar, s.theta, theta),
                 wp = weightIn(g.azimuth, s.phi, phi);
    double v = 0.0;
    for (int corner = 0; corner < 8; ++corner)
    {
      const int a = corner & 1, b = (corner >> 1) & 1, c = (corner >> 2) & 1;
      const double w = (a ? wr : 1.0 - wr) * (b ? wt : 1.0 - wt) * (c ? wp : 1.0 - wp);
      if (w > 0.0)
        v += w * pointValues[std::size_t(s.r + a) + nr * (std::size_t(s.theta + b) + nt * std::size_t(s.phi + c))];
    }
    return v;
  };
  return renderPointData(SphericalCells{ traversal }, valueAt, transfer, sampleDistance, camera, framebuffer,
    options, "renderSphericalVolumePoints");
}

SphericalVolumeStatistics renderCylindricalVolumePoints(const CylindricalTraversal& traversal,
  const std::vector<double>& pointValues, const TransferTable& transfer, double sampleDistance,
  const Camera& camera, Framebuffer& framebuffer, const SphericalVolumeOptions& options)
{
  const CylindricalGrid& g = traversal.grid();
  const std::size_t nr = g.radius.size(), np = g.azimuth.size();
  checkPointCount(pointValues.size(), nr * np * g.height.size(), "renderCylindricalVolumePoints");
  const double phi0 = g.azimuth.front();
  auto valueAt = [&](const CellSegment& s, const dvec3& x)
  {
    const double rho = std::hypot(x.x, x.y);
    const double phi = unwrapAzimuth(std::atan2(x.y, x.x), phi0);
    // In the segments of a cylindrical traversal theta holds the height index.
    const double wr = weightIn(g.radius, s.r, rho), wp = weightIn(g.azimuth, s.phi, phi),
                 wz = weightIn(g.height, s.theta, x.z);
    double v = 0.0;
    for (int corner = 0; corner < 8; ++corner)
    {
      const int a = corner & 1, b = (corner >> 1) & 1, c = (corner >> 2) & 1;
      const double w = (a ? wr : 1.0 - wr) * (b ? wp : 1.0 - wp) * (c ? wz : 1.0 - wz);
      if (w > 0.0)
        v += w * pointValues[std::size_t(s.r + a) + nr * (std::size_t(s.phi + b) + np * std::size_t(s.theta + c))];
    }
    return v;
  };
  return renderPointData(CylindricalCells{ traversal }, valueAt, transfer, sampleDistance, camera, framebuffer,
    options, "renderCylindricalVolumePoints");
}

std::vector<dvec3> sphericalCellGradients(const SphericalGrid& grid, const std::vector<double>& values)
{
  checkValueCount(values.size(), grid.cellCount(), "sphericalCellGradients");
  const int nr = grid.radialCells(), nt = grid.polarCells(), np = grid.azimuthalCells();
  const bool wrap = grid.fullCircle();
  std::vector<dvec3> gradients(values.size());
  for (int k = 0; k < np; ++k)
    for (int j = 0; j < nt; ++j)
      for (int i = 0; i < nr; ++i)
      {
        const double r = centreOf(grid.radius, i), theta = centreOf(grid.polar, j), phi = centreOf(grid.azimuth, k);
        const double dr = centralDifference(i, nr, false, grid.radius, [&](int a) { return values[grid.cellIndex(a, j, k)]; });
        const double dtheta = centralDifference(j, nt, false, grid.polar, [&](int a) { return values[grid.cellIndex(i, a, k)]; });
        const double dphi = centralDifference(k, np, wrap, grid.azimuth, [&](int a) { return values[grid.cellIndex(i, j, a)]; });
        const double st = std::sin(theta), ct = std::cos(theta), sp = std::sin(phi), cp = std::cos(phi);
        const dvec3 er(st * cp, st * sp, ct), et(ct * cp, ct * sp, -st), ep(-sp, cp, 0.0);
        dvec3 g = dr * er;
        if (r > 0.0)
          g += dtheta / r * et;
        if (r * st > 0.0)
          g += dphi / (r * st) * ep;
        gradients[grid.cellIndex(i, j, k)] = g;
      }
  return gradients;
}

std::vector<dvec3> cylindricalCellGradients(const CylindricalGrid& grid, const std::vector<double>& values)
{
  checkValueCount(values.size(), grid.cellCount(), "cylindricalCellGradients");
  const int nr = grid.radialCells(), np = grid.azimuthalCells(), nz = grid.heightCells();
  const bool wrap = grid.fullCircle();
  std::vector<dvec3> gradients(values.size());
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < np; ++j)
      for (int i = 0; i < nr; ++i)
      {
        const double rho = centreOf(grid.radius, i), phi = centreOf(grid.azimuth, j);
        const double drho = centralDifference(i, nr, false, grid.radius, [&](int a) { return values[grid.cellIndex(a, j, k)]; });
        const double dphi = centralDifference(j, np, wrap, grid.azimuth, [&](int a) { return values[grid.cellIndex(i, a, k)]; });
        const double dz = centralDifference(k, nz, false, grid.height, [&](int a) { return values[grid.cellIndex(i, j, a)]; });
        const double sp = std::sin(phi), cp = std::cos(phi);
        dvec3 g = drho * dvec3(cp, sp, 0.0) + dz * dvec3(0.0, 0.0, 1.0);
        if (rho > 0.0)
          g += dphi / rho * dvec3(-sp, cp, 0.0);
        gradients[grid.cellIndex(i, j, k)] = g;
      }
  return gradients;
}

namespace
{

// Inclusive range of the cells between breakpoints b that meet [low, high] (with a margin of
// `slack`); false for none.
bool cellsMeeting(const std::vector<double>& b, double low, double high, double slack, int& first, int& last)
{
  first = -1;
  for (int i = 0; i + 1 < int(b.size()); ++i)
    if (b[std::size_t(i) + 1] >= low - slack && b[std::size_t(i)] <= high + slack)
    {
      if (first < 0)
        first = i;
      last = i;
    }
  return first >= 0;
}

// Nearest and farthest distances from the z axis over the box's xy rectangle.
void axisDistances(const dvec3& lower, const dvec3& upper, double& nearest, double& farthest)
{
  const glm::dvec2 lo(lower), hi(upper);
  nearest = glm::length(glm::clamp(glm::dvec2(0.0), lo, hi));
  farthest = glm::length(glm::max(glm::abs(lo), glm::abs(hi)));
}

// The azimuth cells meeting the box's xy rectangle: every cell when the axis runs through the
// rectangle's inside; a run across a full circle's seam as first > last (a wedge's cells at
// both ends are not neighbours, so they give every cell). A cell that only
// touches the rectangle's angles (a shared face, to 1e-12) is left out when others overlap
// them: what lies in a face is a sliver without volume.
bool azimuthCellsInBox(const std::vector<double>& azimuth, const dvec3& lower, const dvec3& upper, int& first, int& last)
{
  const int cells = int(azimuth.size()) - 1;
  first = 0;
  last = cells - 1;
  if ((lower.x < 0.0 && upper.x > 0.0 && lower.y < 0.0 && upper.y > 0.0) ||
    !std::isfinite(lower.x + upper.x + lower.y + upper.y))
    return true;
  // Seen from the axis (outside the rectangle or on its edge) the rectangle spans at most pi:
  // its corners' angles about its centre's bound it.
  const double centre = std::atan2(0.5 * (lower.y + upper.y), 0.5 * (lower.x + upper.x));
  double low = 0.0, high = 0.0;
  for (int corner = 0; corner < 4; ++corner)
  {
    const double x = corner & 1 ? upper.x : lower.x, y = corner & 2 ? upper.y : lower.y;
    if (x == 0.0 && y == 0.0)
      continue; // a corner on the axis has every angle, and its edges give the rectangle's
    double a = std::atan2(y, x) - centre;
    a -= kTwoPi * std::round(a / kTwoPi);
    low = std::min(low, a);
    high = std::max(high, a);
  }
  low += centre;
  high += centre;
  for (const double slack : { -1e-12, 1e-12 })
  {
    // First the cells that overlap the angles by more than 1e-12, else those that touch them.
    std::vector<bool> meets(std::size_t(cells), false);
    int count = 0;
    for (int k = 0; k < cells; ++k)
    {
      for (int turn = -2; turn <= 2 && !meets[std::size_t(k)]; ++turn)
        meets[std::size_t(k)] = std::min(azimuth[std::size_t(k) + 1] + turn * kTwoPi, high) -
            std::max(azimuth[std::size_t(k)] + turn * kTwoPi, low) > -slack;
      count += meets[std::size_t(k)];
    }
    if (count == 0)
      continue;
    first = 0;
    last = cells - 1;
    if (count == cells)
      return true;
    // The run's start: a meeting cell whose predecessor (across the seam on a full circle)
    // does not meet.
    const bool wraps = traversal::spansFullCircle(azimuth);
    int start = -1;
    for (int k = 0; k < cells && start < 0; ++k)
      if (meets[std::size_t(k)] && (k > 0 ? !meets[std::size_t(k) - 1] : !wraps || !meets[std::size_t(cells) - 1]))
        start = k;
    for (int step = 0; step < count; ++step)
      if (start < 0 || !meets[std::size_t((start + step) % cells)])
        return true; // not one run (a wedge's two ends): every cell
    if (start + count > cells && !wraps)
      return true;
    first = start;
    last = (start + count - 1) % cells;
    return true;
  }
  return false;
}

bool isBox(const dvec3& lower, const dvec3& upper)
{
  return !glm::any(glm::isnan(lower)) && !glm::any(glm::isnan(upper)) &&
    glm::all(glm::lessThanEqual(lower, upper));
}
} // namespace

bool cellRangeInBox(const SphericalGrid& grid, const dvec3& lower, const dvec3& upper, int first[3], int last[3])
{
  if (!isBox(lower, upper))
    return false;
  const double scale = std::max(grid.radius.back(), 1e-300);
  const double nearest = glm::length(glm::clamp(dvec3(0.0), lower, upper));
  const double farthest = glm::length(glm::max(glm::abs(lower), glm::abs(upper)));
  if (!cellsMeeting(grid.radius, nearest, farthest, 1e-12 * scale, first[0], last[0]))
    return false;
  double axisNear, axisFar;
  axisDistances(lower, upper, axisNear, axisFar);
  const double pi = 0.5 * kTwoPi;
  // theta = atan2(rho, z) falls as z grows; it grows with rho above the equator and falls
  // below it, and the box's (rho, z) are all pairs of its rho and z ranges (z = 0 is the
  // equator, the origin aside).
  const double thetaLow = upper.z > 0.0 ? std::atan2(axisNear, upper.z) : upper.z < 0.0 ? std::atan2(axisFar, upper.z) : 0.5 * pi;
  const double thetaHigh = lower.z > 0.0 ? std::atan2(axisFar, lower.z) : lower.z < 0.0 ? std::atan2(axisNear, lower.z) : 0.5 * pi;
  if (!cellsMeeting(grid.polar, thetaLow, thetaHigh, 1e-12, first[1], last[1]))
    return false;
  return azimuthCellsInBox(grid.azimuth, lower, upper, first[2], last[2]);
}

bool cellRangeInBox(const CylindricalGrid& grid, const dvec3& lower, const dvec3& upper, int first[3], int last[3])
{
  if (!isBox(lower, upper))
    return false;
  double axisNear, axisFar;
  axisDistances(lower, upper, axisNear, axisFar);
  const double scale = std::max(grid.radius.back(), 1e-300);
  const double heightScale = std::max(std::abs(grid.height.front()), std::abs(grid.height.back()));
  return cellsMeeting(grid.radius, axisNear, axisFar, 1e-12 * scale, first[0], last[0]) &&
    azimuthCellsInBox(grid.azimuth, lower, upper, first[1], last[1]) &&
    cellsMeeting(grid.height, lower.z, upper.z, 1e-12 * heightScale, first[2], last[2]);
}

std::vector<dvec3> cellCentres(const SphericalGrid& grid)
{
  std::vector<dvec3> centres(grid.cellCount());
  for (int k = 0; k < grid.azimuthalCells(); ++k)
    for (int j = 0; j < grid.polarCells(); ++j)
      for (int i = 0; i < grid.radialCells(); ++i)
        centres[grid.cellIndex(i, j, k)] =
          sphericalToCartesian(centreOf(grid.radius, i), centreOf(grid.polar, j), centreOf(grid.azimuth, k));
  return centres;
}

std::vector<dvec3> cellCentres(const CylindricalGrid& grid)
{
  std::vector<dvec3> centres(grid.cellCount());
  for (int k = 0; k < grid.heightCells(); ++k)
    for (int j = 0; j < grid.azimuthalCells(); ++j)
      for (int i = 0; i < grid.radialCells(); ++i)
      {
        const double rho = centreOf(grid.radius, i), phi = centreOf(grid.azimuth, j);
        centres[grid.cellIndex(i, j, k)] = dvec3(rho * std::cos(phi), rho * std::sin(phi), centreOf(grid.height, k));
      }
  return centres;
}

void shadeCells(const std::vector<dvec3>& centres, const std::vector<dvec3>& gradients,
  const Material& material, const Lighting& lighting, const Camera& camera,
  std::vector<TransferSample>& cells)
{
  if (gradients.size() != cells.size() || centres.size() != cells.size())
    throw std::invalid_argument("sightline::shadeCells: " + std::to_string(centres.size()) + " centres and " +
      std::to_string(gradients.size()) + " gradients for " + std::to_string(cells.size()) + " cells");
  tbb::parallel_for(std::size_t(0), cells.size(),
    [&](std::size_t c)
    {
      TransferSample& cell = cells[c];
      if (!(cell.extinction > 0.0))
        return;
      const dvec3 g = gradients[c];
      const double length = glm::length(g);
      if (!(length > 0.0))
      {
        cell.color *= material.ambient + material.diffuse;
        return;
      }
      // The viewer direction at the cell's projection, right for parallel and perspective views.
      const dvec4 clip = camera.worldToClip() * dvec4(centres[c], 1.0);
      const double px = (clip.x / clip.w * 0.5 + 0.5) * camera.width();
      const double py = (clip.y / clip.w * 0.5 + 0.5) * camera.height();
      const vec3 toViewer = -vec3(camera.doublePrimaryRay(px, py).direction);
      vec3 normal = vec3(g / length);
      if (glm::dot(normal, toViewer) < 0.0f)
        normal = -normal; // two-sided, as VTK's volume shading
      cell.color = shade(material, cell.color, cell.color, normal, toViewer, lighting);
    });
}
} // namespace sightline
