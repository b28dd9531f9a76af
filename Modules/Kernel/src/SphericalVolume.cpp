#include "sightline/SphericalVolume.h"

#include "sightline/SphericalFields.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
SphericalVolumeStatistics renderSphericalVolume(const SphericalTraversal& traversal,
  const std::vector<double>& values, const std::function<TransferSample(double)>& transfer,
  const Camera& camera, Framebuffer& framebuffer, const SphericalVolumeOptions& options)
{
  const SphericalGrid& grid = traversal.grid();
  if (values.size() != grid.cellCount())
    throw std::invalid_argument("sightline::renderSphericalVolume: " + std::to_string(values.size()) +
      " values for " + std::to_string(grid.cellCount()) + " cells");
  // The transfer function once per cell, not once per ray and cell.
  std::vector<TransferSample> cells(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    cells[i] = transfer(values[i]);
  return renderSphericalVolume(traversal, cells, camera, framebuffer, options);
}

SphericalVolumeStatistics renderSphericalVolume(const SphericalTraversal& traversal,
  const std::vector<TransferSample>& cells, const Camera& camera, Framebuffer& framebuffer,
  const SphericalVolumeOptions& options)
{
  const auto start = std::chrono::steady_clock::now();
  const SphericalGrid& grid = traversal.grid();
  if (cells.size() != grid.cellCount())
    throw std::invalid_argument("sightline::renderSphericalVolume: " + std::to_string(cells.size()) +
      " cell samples for " + std::to_string(grid.cellCount()) + " cells");
  framebuffer.resize(camera.width(), camera.height());
  if (options.depthLimit && options.depthLimit->size() != framebuffer.pixelCount())
    throw std::invalid_argument("sightline::renderSphericalVolume: the depth limit has " +
      std::to_string(options.depthLimit->size()) + " values for " + std::to_string(framebuffer.pixelCount()) + " pixels");

  // Empty space: rays are clipped to the sphere around the outermost shell with a visible cell,
  // and nothing is traced when no cell is visible.
  double visibleRadius = -1.0;
  for (int i = grid.radialCells() - 1; i >= 0 && visibleRadius < 0.0; --i)
    for (int k = 0; k < grid.azimuthalCells() && visibleRadius < 0.0; ++k)
      for (int j = 0; j < grid.polarCells(); ++j)
        if (cells[grid.cellIndex(i, j, k)].extinction > 0.0)
        {
          visibleRadius = grid.radius[i + 1];
          break;
        }
  SphericalVolumeStatistics stats;
  if (visibleRadius < 0.0)
  {
    if (options.progress)
      options.progress(1.0);
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
  }

  // Bands of rows one after another, so that progress is reported and a cancel takes effect.
  const int bands = options.progress ? std::min(camera.height(), 16) : 1;
  tbb::combinable<std::size_t> visited([] { return std::size_t(0); });
  for (int band = 0; band < bands; ++band)
  {
  const int firstRow = int(std::int64_t(camera.height()) * band / bands);
  const int endRow = int(std::int64_t(camera.height()) * (band + 1) / bands);
  tbb::parallel_for(tbb::blocked_range<int>(firstRow, endRow),
    [&](const tbb::blocked_range<int>& rows)
    {
      std::vector<CellSegment> segments;
      std::size_t count = 0;
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < camera.width(); ++x)
        {
          const Ray ray = camera.primaryRay(x + 0.5, y + 0.5);
          const dvec3 o(ray.origin), d(ray.direction);
          double tmax = ray.tfar;
          const std::size_t i = framebuffer.index(x, y);
          if (options.depthLimit && (*options.depthLimit)[i] < 1.0f)
            tmax = camera.primaryRayParameterAt(x + 0.5, y + 0.5, (*options.depthLimit)[i]);
          double enter, leave;
          if (!sphereChord(o, d, visibleRadius, ray.tnear, tmax, enter, leave))
            continue;
          traversal.traverse(o, d, enter, leave, segments);
          double first = -1.0;
          const vec4 rgba = compositeCells(
            [&](const CellSegment& c) -> const TransferSample& { return cells[grid.cellIndex(c.r, c.theta, c.phi)]; },
            segments, 1.0, options.minimumTransmittance, &first, &count);
          if (!(rgba.a > 0.0f))
            continue;
          framebuffer.Color[i] = vec4(vec3(rgba) / rgba.a, rgba.a);
          const dvec3 front = o + first * d;
          framebuffer.Depth[i] = float(std::clamp(camera.windowDepth(front), 0.0, 1.0));
          framebuffer.Distance[i] = float(first);
        }
      visited.local() += count;
    });
  if (options.progress && !options.progress(double(band + 1) / bands))
    break;
  }
  stats.cellsVisited = visited.combine([](std::size_t a, std::size_t b) { return a + b; });
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}
std::vector<dvec3> sphericalCellGradients(const SphericalGrid& grid, const std::vector<double>& values)
{
  if (values.size() != grid.cellCount())
    throw std::invalid_argument("sightline::sphericalCellGradients: " + std::to_string(values.size()) +
      " values for " + std::to_string(grid.cellCount()) + " cells");
  const int nr = grid.radialCells(), nt = grid.polarCells(), np = grid.azimuthalCells();
  const bool wrap = grid.fullCircle();
  auto centre = [](const std::vector<double>& b, int i) { return 0.5 * (b[i] + b[i + 1]); };
  // d value / d coordinate between the neighbours of cell i along one axis.
  auto difference = [&](int i, int n, bool periodic, const std::vector<double>& b, auto valueAt)
  {
    if (n < 2)
      return 0.0;
    int lo = i - 1, hi = i + 1;
    double clo, chi;
    if (periodic)
    {
      const double span = b.back() - b.front();
      clo = lo < 0 ? centre(b, n - 1) - span : centre(b, lo);
      chi = hi >= n ? centre(b, 0) + span : centre(b, hi);
      lo = (lo + n) % n;
      hi = hi % n;
    }
    else
    {
      lo = std::max(lo, 0);
      hi = std::min(hi, n - 1);
      clo = centre(b, lo);
      chi = centre(b, hi);
    }
    return (valueAt(hi) - valueAt(lo)) / (chi - clo);
  };
  std::vector<dvec3> gradients(values.size());
  for (int k = 0; k < np; ++k)
    for (int j = 0; j < nt; ++j)
      for (int i = 0; i < nr; ++i)
      {
        const double r = centre(grid.radius, i), theta = centre(grid.polar, j), phi = centre(grid.azimuth, k);
        const double dr = difference(i, nr, false, grid.radius, [&](int a) { return values[grid.cellIndex(a, j, k)]; });
        const double dtheta = difference(j, nt, false, grid.polar, [&](int a) { return values[grid.cellIndex(i, a, k)]; });
        const double dphi = difference(k, np, wrap, grid.azimuth, [&](int a) { return values[grid.cellIndex(i, j, a)]; });
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

void shadeCells(const SphericalGrid& grid, const std::vector<dvec3>& gradients,
  const Material& material, const Lighting& lighting, const Camera& camera,
  std::vector<TransferSample>& cells)
{
  if (gradients.size() != grid.cellCount() || cells.size() != grid.cellCount())
    throw std::invalid_argument("sightline::shadeCells: " + std::to_string(gradients.size()) + " gradients and " +
      std::to_string(cells.size()) + " samples for " + std::to_string(grid.cellCount()) + " cells");
  const int nr = grid.radialCells(), nt = grid.polarCells();
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
      const int i = int(c % std::size_t(nr)), j = int(c / std::size_t(nr) % std::size_t(nt)),
                k = int(c / (std::size_t(nr) * std::size_t(nt)));
      const dvec3 centre = sphericalToCartesian(0.5 * (grid.radius[i] + grid.radius[i + 1]),
        0.5 * (grid.polar[j] + grid.polar[j + 1]), 0.5 * (grid.azimuth[k] + grid.azimuth[k + 1]));
      // The viewer direction at the cell's projection, right for parallel and perspective views.
      const dvec4 clip = camera.worldToClip() * dvec4(centre, 1.0);
      const double px = (clip.x / clip.w * 0.5 + 0.5) * camera.width();
      const double py = (clip.y / clip.w * 0.5 + 0.5) * camera.height();
      const vec3 toViewer = -glm::normalize(camera.primaryRay(px, py).direction);
      vec3 normal = vec3(g / length);
      if (glm::dot(normal, toViewer) < 0.0f)
        normal = -normal; // two-sided, as VTK's volume shading
      cell.color = shade(material, cell.color, cell.color, normal, toViewer, lighting);
    });
}
} // namespace sightline
