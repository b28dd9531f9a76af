#include "sightline/SphericalVolume.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
SphericalVolumeStatistics renderSphericalVolume(const SphericalTraversal& traversal,
  const std::vector<double>& values, const std::function<TransferSample(double)>& transfer,
  const Camera& camera, Framebuffer& framebuffer, const SphericalVolumeOptions& options)
{
  const auto start = std::chrono::steady_clock::now();
  const SphericalGrid& grid = traversal.grid();
  if (values.size() != grid.cellCount())
    throw std::invalid_argument("sightline::renderSphericalVolume: " + std::to_string(values.size()) +
      " values for " + std::to_string(grid.cellCount()) + " cells");
  framebuffer.resize(camera.width(), camera.height());
  if (options.depthLimit && options.depthLimit->size() != framebuffer.pixelCount())
    throw std::invalid_argument("sightline::renderSphericalVolume: the depth limit has " +
      std::to_string(options.depthLimit->size()) + " values for " + std::to_string(framebuffer.pixelCount()) + " pixels");
  // The transfer function once per cell, not once per ray and cell.
  std::vector<TransferSample> cells(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    cells[i] = transfer(values[i]);

  tbb::combinable<std::size_t> visited([] { return std::size_t(0); });
  tbb::parallel_for(tbb::blocked_range<int>(0, camera.height()),
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
          traversal.traverse(o, d, ray.tnear, tmax, segments);
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
  SphericalVolumeStatistics stats;
  stats.cellsVisited = visited.combine([](std::size_t a, std::size_t b) { return a + b; });
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}
} // namespace sightline
