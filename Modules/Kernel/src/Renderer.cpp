#include "sightline/Renderer.h"

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <functional>

namespace sightline
{
namespace
{
/// Everything a pixel needs, computed once per frame.
struct FrameContext
{
  const EmbreeScene& scene;
  const Camera& camera;
  const Lighting& lighting;
  dmat4 objectToWorld;
  glm::mat3 normalToWorld;
  bool identityTransform;
};

/// Traces the primary ray of pixel (x, y); returns whether it hit.
bool renderPixel(const FrameContext& frame, int x, int y, Framebuffer& fb)
{
  const Ray ray = frame.camera.primaryRay(x + 0.5, y + 0.5);
  RTCRayHit rh = makeRayHit(ray);
  if (!frame.scene.intersect(rh, true))
    return false;

  const Geometry& geometry = frame.scene.geometry(rh.hit.geomID);
  const float t = rh.ray.tfar;
  const dvec3 hitObject = dvec3(ray.origin) + double(t) * dvec3(ray.direction);
  vec3 normal(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  vec3 toViewer = -ray.direction;
  if (!frame.identityTransform)
  {
    normal = frame.normalToWorld * normal;
    toViewer = vec3(frame.objectToWorld * dvec4(dvec3(toViewer), 0.0));
  }
  normal = glm::normalize(normal);
  toViewer = glm::normalize(toViewer);
  if (glm::dot(normal, toViewer) < 0.0f)
    normal = -normal; // two-sided lighting, as VTK's default

  const Material& m = geometry.material;
  vec3 ambientColor = m.ambientColor, diffuseColor = m.color;
  if (geometry.hasPrimitiveColors())
    ambientColor = diffuseColor = geometry.primitiveColor(rh.hit.primID);
  const vec3 rgb = shade(m, ambientColor, diffuseColor, normal, toViewer, frame.lighting);

  const std::size_t i = fb.index(x, y);
  fb.Color[i] = vec4(rgb, m.opacity);
  fb.Depth[i] = float(std::clamp(frame.camera.windowDepth(hitObject), 0.0, 1.0));
  // t is in the scene's units; the framebuffer keeps world distances.
  fb.Distance[i] = frame.identityTransform
    ? t
    : float(t * glm::length(glm::dmat3(frame.objectToWorld) * dvec3(ray.direction)));
  return true;
}
} // namespace

RenderStatistics Renderer::render(const EmbreeScene& scene, const Camera& camera,
  const Lighting& lighting, Framebuffer& framebuffer, const RenderOptions& options) const
{
  const auto start = std::chrono::steady_clock::now();
  framebuffer.resize(camera.width(), camera.height());
  RenderStatistics stats;
  if (scene.empty())
    return stats;

  const bool identity = options.objectToWorld == dmat4(1.0);
  const FrameContext frame{ scene, camera, lighting, options.objectToWorld,
    glm::mat3(glm::transpose(glm::inverse(glm::dmat3(options.objectToWorld)))), identity };

  // Bands of tile rows, rendered one after another so that progress is reported (and a cancel
  // honoured) on the calling thread; tiles within a band run in parallel.
  const int tile = std::max(1, options.tileSize);
  const int height = camera.height();
  const int width = camera.width();
  const int tileRows = (height + tile - 1) / tile;
  const int bands = options.progress ? std::min(tileRows, 16) : 1;
  tbb::combinable<std::size_t> hits([] { return std::size_t(0); });
  for (int band = 0; band < bands; ++band)
  {
    const int y0 = (tileRows * band / bands) * tile;
    const int y1 = std::min(height, (tileRows * (band + 1) / bands) * tile);
    tbb::parallel_for(tbb::blocked_range2d<int>(y0, y1, tile, 0, width, tile),
      [&](const tbb::blocked_range2d<int>& r)
      {
        std::size_t local = 0;
        for (int y = r.rows().begin(); y < r.rows().end(); ++y)
          for (int x = r.cols().begin(); x < r.cols().end(); ++x)
            local += renderPixel(frame, x, y, framebuffer);
        hits.local() += local;
      });
    if (options.progress && !options.progress(double(band + 1) / bands))
    {
      stats.completed = band + 1 == bands;
      break;
    }
  }
  stats.hits = hits.combine(std::plus<std::size_t>());
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}
} // namespace sightline
