// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/core/Renderer.h"

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

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
  const RenderOptions& options;
  dmat4 objectToWorld;
  glm::mat3 normalToWorld;
  glm::dmat3 worldToObjectDirection;
  bool identityTransform;
  /// Translucent unions: intervals this close count as touching (no interior surface).
  double unionGap;
  /// Length of the first segment a translucent ray is traced in, and the translucent
  /// scene's bounds (scene coordinates).
  double translucentSegment;
  Box3 translucentBounds;
  /// RenderOptions' region is not all of space: primary rays are clipped to it.
  bool regionClipped;
  /// Primary rays traced together (EmbreeDevice::packetSize).
  int packetSize;
};

constexpr int kMaxShadowedLights = 16;

/// A small integer hash (Jarvis-style xorshift-multiply) for per-pixel sample rotations.
std::uint32_t hashPixel(std::uint32_t x, std::uint32_t y, std::uint32_t seed)
{
  std::uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ seed * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}

/// Unshadowed fraction of each light at a surface point (scene coordinates).
void lightVisibility(const FrameContext& frame, const dvec3& point, double hitDistance,
  const vec3& objectNormal, const vec3& worldNormal, int px, int py, float* visibility,
  std::size_t& shadowRays)
{
  const ShadowOptions& shadows = frame.options.shadows;
  // Leave the surface along the normal by a little more than the hit point's error: the hit is
  // computed in double along the double ray, so that error scales with the distance travelled,
  // not with how far the point is from the origin (double's rounding of it is the last term).
  const double offset = 1e-5 * (hitDistance + 1.0) + 1e-14 * glm::length(point);
  const dvec3 origin = point + offset * dvec3(objectNormal);
  const std::size_t lights = std::min<std::size_t>(frame.lighting.lights.size(), kMaxShadowedLights);
  for (std::size_t i = 0; i < lights; ++i)
  {
    const vec3 toLightWorld = -frame.lighting.lights[i].direction;
    if (glm::dot(worldNormal, toLightWorld) <= 0.0f)
    {
      visibility[i] = 0.0f;
      continue;
    }
    auto blocked = [&](const vec3& worldDirection)
    {
      const DoubleRay ray(origin,
        frame.identityTransform ? dvec3(worldDirection)
                                : glm::normalize(frame.worldToObjectDirection * dvec3(worldDirection)),
        0.0, kInfinity);
      ++shadowRays;
      return frame.scene.occluded(ray);
    };
    if (shadows.mode == ShadowMode::Hard || shadows.samples <= 1)
    {
      visibility[i] = blocked(toLightWorld) ? 0.0f : 1.0f;
      continue;
    }
    // Stratified directions in the light's cone, weighted by the cosine at the surface.
    const vec3 axis = toLightWorld;
    const vec3 helper = std::abs(axis.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0);
    const vec3 tangent = glm::normalize(glm::cross(helper, axis));
    const vec3 bitangent = glm::cross(axis, tangent);
    const float cosMax = std::cos(shadows.lightAngularRadius);
    const std::uint32_t h = hashPixel(std::uint32_t(px), std::uint32_t(py), shadows.seed);
    const float rotation = float(h & 0xffffu) / 65536.0f;
    const float jitter = float(h >> 16) / 65536.0f;
    float lit = 0.0f, total = 0.0f;
    for (int s = 0; s < shadows.samples; ++s)
    {
      const float u1 = (float(s) + jitter) / float(shadows.samples);
      float u2 = float(s) * 0.618034f + rotation;
      u2 -= std::floor(u2);
      const float cosTheta = 1.0f - u1 * (1.0f - cosMax);
      const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
      const float phi = 6.2831853f * u2;
      const vec3 direction = cosTheta * axis + sinTheta * (std::cos(phi) * tangent + std::sin(phi) * bitangent);
      const float weight = glm::dot(worldNormal, direction);
      if (weight <= 0.0f)
        continue;
      total += weight;
      if (!blocked(direction))
        lit += weight;
    }
    visibility[i] = total > 0.0f ? lit / total : 0.0f;
  }
  for (std::size_t i = lights; i < frame.lighting.lights.size(); ++i)
    visibility[i] = 1.0f;
}

/// Per-thread scratch and counters.
struct PixelScratch
{
  std::size_t shadowRays = 0;
  std::size_t translucentSurfaces = 0;
  std::vector<InsideInterval> intervals[EmbreeScene::kMaxPacket]; ///< per lane
  std::vector<UnionSurface> surfaces;
};

/// Unit normal facing the viewer (two-sided lighting, as VTK's default) in scene and world
/// coordinates, and the direction to the viewer in world coordinates.
struct ShadingFrame
{
  vec3 objectNormal, normal, toViewer;
};

ShadingFrame orientNormal(const FrameContext& frame, vec3 objectNormal, const vec3& direction)
{
  ShadingFrame s;
  objectNormal = glm::normalize(objectNormal);
  if (glm::dot(objectNormal, direction) > 0.0f)
    objectNormal = -objectNormal;
  s.objectNormal = s.normal = objectNormal;
  s.toViewer = -direction;
  if (!frame.identityTransform)
  {
    s.normal = glm::normalize(frame.normalToWorld * s.normal);
    s.toViewer = glm::normalize(vec3(frame.objectToWorld * dvec4(dvec3(s.toViewer), 0.0)));
  }
  return s;
}

/// Where one ray of a packet stands in the translucent scene.
struct TranslucentLane
{
  double segmentStart = 0.0, segmentEnd = 0.0, rayEnd = 0.0, segmentLength = 0.0;
  vec3 premultiplied{ 0.0f };
  float alpha = 0.0f;
  double nearest = kInfinity;
};

/// Composites, for each active lane, the union surfaces of the translucent scene in
/// (rays[lane].tnear, rays[lane].tfar) front to back over colors[lane] (not premultiplied);
/// nearest[lane] receives the nearest surface's t, or infinity. Each ray is traced in segments
/// of growing length, so that once its layers saturate nothing farther is visited; the lanes'
/// segments are traced together as one packet. Each segment collects every solid overlapping it
/// (their intervals are not clipped), so the union's surfaces inside the segment are exact; a
/// solid spanning two segments is seen in both, and only surfaces within each segment's range
/// are drawn.
void compositeTranslucent(const FrameContext& frame, const DoubleRay* rays, const bool* active,
  int count, vec4* colors, double* nearest, PixelScratch& scratch)
{
  const EmbreeScene& scene = *frame.options.translucent.scene;
  TranslucentLane lanes[EmbreeScene::kMaxPacket];
  bool running[EmbreeScene::kMaxPacket];
  DoubleRay segments[EmbreeScene::kMaxPacket];
  int left = 0;
  for (int lane = 0; lane < count; ++lane)
  {
    nearest[lane] = kInfinity;
    running[lane] = false;
    if (!active[lane])
      continue;
    // Segments start where the ray enters the scene's box, not at the near plane.
    const DoubleRay& ray = rays[lane];
    TranslucentLane& l = lanes[lane];
    l.segmentStart = ray.tnear;
    l.rayEnd = ray.tfar;
    if (!clipToBox(ray.origin, ray.direction, dvec3(frame.translucentBounds.lower),
          dvec3(frame.translucentBounds.upper), l.segmentStart, l.rayEnd))
      continue;
    // Back off by the merge gap so a surface right at the box's face is not lost.
    l.segmentStart = std::max(ray.tnear, l.segmentStart - frame.unionGap);
    l.rayEnd = std::min(ray.tfar, l.rayEnd + frame.unionGap);
    l.segmentLength = frame.translucentSegment;
    running[lane] = l.segmentStart < l.rayEnd;
    left += running[lane];
  }
  while (left > 0)
  {
    for (int lane = 0; lane < count; ++lane)
    {
      if (!running[lane])
        continue;
      TranslucentLane& l = lanes[lane];
      segments[lane] = rays[lane];
      segments[lane].tnear = l.segmentStart;
      l.segmentEnd = std::min(l.rayEnd, l.segmentStart + l.segmentLength);
      segments[lane].tfar = l.segmentEnd;
      scratch.intervals[lane].clear();
    }
    scene.insideIntervalsPacket(segments, running, count, scratch.intervals);
    for (int lane = 0; lane < count; ++lane)
    {
      if (!running[lane])
        continue;
      TranslucentLane& l = lanes[lane];
      // unionSurfaces takes the open range (tnear, tfar): a surface exactly at a segment's end
      // belongs to that segment, so its range reaches just past the end (the last segment's
      // end is the ray's own).
      const bool last = l.segmentEnd >= l.rayEnd;
      unionSurfaces(scratch.intervals[lane], l.segmentStart,
        last ? l.segmentEnd : std::nextafter(l.segmentEnd, 1e300), frame.unionGap, scratch.surfaces);
      bool saturated = false;
      for (const UnionSurface& surface : scratch.surfaces)
      {
        const Geometry& geometry = scene.geometry(surface.geometry);
        const ShadingFrame s = orientNormal(frame,
          geometry.partNormal(surface.part, rays[lane].at(surface.t)), vec3(rays[lane].direction));
        const Material& m = geometry.material;
        vec3 ambientColor = m.ambientColor, diffuseColor = m.color;
        if (geometry.hasPrimitiveColors())
          ambientColor = diffuseColor = geometry.partColor(surface.part);
        const vec3 rgb = shade(m, ambientColor, diffuseColor, s.normal, s.toViewer, frame.lighting, nullptr);
        l.premultiplied += (1.0f - l.alpha) * m.opacity * rgb;
        l.alpha += (1.0f - l.alpha) * m.opacity;
        l.nearest = std::min(l.nearest, surface.t);
        ++scratch.translucentSurfaces;
        if (l.alpha >= frame.options.translucent.saturation)
        {
          saturated = true;
          break;
        }
      }
      l.segmentStart = l.segmentEnd;
      l.segmentLength *= 4.0;
      if (saturated || last || !(l.segmentStart < l.rayEnd))
      {
        running[lane] = false;
        --left;
      }
    }
  }
  for (int lane = 0; lane < count; ++lane)
  {
    const TranslucentLane& l = lanes[lane];
    if (!active[lane] || !(l.nearest < kInfinity))
      continue;
    nearest[lane] = l.nearest;
    vec4& color = colors[lane];
    const float total = l.alpha + (1.0f - l.alpha) * color.a;
    if (total > 0.0f)
      color = vec4((l.premultiplied + (1.0f - l.alpha) * color.a * vec3(color)) / total, total);
  }
}

/// The primary ray of pixel (x, y), stopped at the depth limit and clipped to the region;
/// false when the region leaves nothing of it.
bool primaryRay(const FrameContext& frame, int x, int y, std::size_t i, DoubleRay& ray)
{
  ray = frame.camera.doublePrimaryRay(x + 0.5, y + 0.5);
  if (frame.options.depthLimit)
  {
    // Stop at opaque geometry drawn by someone else (direction is unit: t is a distance).
    const float limit = (*frame.options.depthLimit)[i];
    if (limit < 1.0f)
      ray.tfar = frame.camera.primaryRayParameterAt(x + 0.5, y + 0.5, limit);
  }
  if (frame.regionClipped)
  {
    // The region is in world coordinates; the world ray has the same parameter t.
    const dvec3 worldOrigin = frame.identityTransform ? ray.origin : dvec3(frame.objectToWorld * dvec4(ray.origin, 1.0));
    const dvec3 worldDirection = frame.identityTransform ? ray.direction : glm::dmat3(frame.objectToWorld) * ray.direction;
    if (!clipToBox(worldOrigin, worldDirection, frame.options.regionLower, frame.options.regionUpper,
          ray.tnear, ray.tfar))
      return false;
  }
  return true;
}

/// A pixel between its opaque shading and its translucent layers.
struct PixelState
{
  vec4 color{ 0.0f };
  double depthT = kInfinity; ///< where the depth is taken (infinity: nothing drawn yet)
  DoubleRay segment;         ///< the ray up to the opaque hit
  double worldScale = 1.0;
};

/// Shades pixel (x, y)'s opaque hit (if `hit`) and the volumes in front of it.
void shadeSurfaceAndVolumes(const FrameContext& frame, int x, int y, const DoubleRay& ray,
  bool hit, const SceneHit& sceneHit, PixelScratch& scratch, PixelState& pixel)
{
  pixel.worldScale = frame.identityTransform
    ? 1.0
    : glm::length(glm::dmat3(frame.objectToWorld) * ray.direction);
  if (hit)
  {
    const Geometry& geometry = frame.scene.geometry(sceneHit.geomID);
    const double t = sceneHit.t;
    const dvec3 hitObject = ray.at(t);
    const ShadingFrame s = orientNormal(frame, sceneHit.normal, vec3(ray.direction));
    const Material& m = geometry.material;
    vec3 ambientColor = m.ambientColor, diffuseColor = m.color;
    if (geometry.hasPrimitiveColors())
      ambientColor = diffuseColor = sceneHit.part != SurfaceHit::kNoPart
        ? geometry.partColor(sceneHit.part) // a primitive of several parts (tube chunks)
        : geometry.surfaceColor(sceneHit.primID, hitObject);
    float visibility[kMaxShadowedLights];
    const bool shadowed = frame.options.shadows.mode != ShadowMode::None && !frame.lighting.lights.empty();
    if (shadowed)
      lightVisibility(frame, hitObject, t, s.objectNormal, s.normal, x, y, visibility, scratch.shadowRays);
    const vec3 rgb = shade(m, ambientColor, diffuseColor, s.normal, s.toViewer, frame.lighting,
      shadowed ? visibility : nullptr);
    pixel.color = vec4(rgb, m.opacity);
    pixel.depthT = t;
  }
  pixel.segment = ray;
  pixel.segment.tfar = hit ? sceneHit.t : ray.tfar;
  const VolumeOptions& volumes = frame.options.volumes;
  if (volumes.scene && !volumes.scene->empty())
  {
    float entry = kInfinity;
    const double inside = volumes.scene->insideLength(pixel.segment, entry);
    if (inside > 0.0)
    {
      const float transmittance = float(std::exp(-double(volumes.extinction) * inside * pixel.worldScale));
      if (hit)
        pixel.color = vec4(transmittance * vec3(pixel.color) + (1.0f - transmittance) * volumes.emission, pixel.color.a);
      else
        pixel.color = vec4(volumes.emission, 1.0f - transmittance);
      pixel.depthT = std::min(pixel.depthT, double(entry)); // the volume's front, so it composites with GL geometry
    }
  }
}

/// Writes a pixel that shows something (colour, depth, distance and the primitive id).
void writePixel(const FrameContext& frame, std::size_t i, const DoubleRay& ray, bool hit,
  const SceneHit& sceneHit, const PixelState& pixel, Framebuffer& fb)
{
  if (hit && frame.options.primitiveIds)
    fb.Primitives[i] = PixelPrimitive{ sceneHit.geomID,
      frame.scene.geometry(sceneHit.geomID).selectionIndex(sceneHit.primID, sceneHit.part) };
  const dvec3 depthPoint = ray.at(pixel.depthT);
  fb.Color[i] = pixel.color;
  fb.Depth[i] = float(std::clamp(frame.camera.windowDepth(depthPoint), 0.0, 1.0));
  // t is in the scene's units; the framebuffer keeps world distances.
  fb.Distance[i] = float(pixel.depthT * pixel.worldScale);
}

/// Renders the block of the packet's shape whose lower-left pixel is (x0, y0), clipped to the
/// tile `r`: the primary rays are traced together, each pixel is shaded on its own, and the
/// translucent layers are traced together again. Returns the number of opaque hits.
std::size_t renderPacket(const FrameContext& frame, int x0, int y0,
  const tbb::blocked_range2d<int>& r, Framebuffer& fb, PixelScratch& scratch, bool& divergent)
{
  constexpr int kMax = EmbreeScene::kMaxPacket;
  const PacketBlock shape = packetBlock(frame.packetSize);
  DoubleRay rays[kMax];
  bool active[kMax];
  SceneHit hits[kMax];
  bool found[kMax] = {};
  std::size_t pixels[kMax];
  int count = 0;
  for (int y = y0; y < y0 + shape.rows; ++y)
    for (int x = x0; x < x0 + shape.columns; ++x, ++count)
    {
      active[count] = y < r.rows().end() && x < r.cols().end();
      if (!active[count])
        continue;
      pixels[count] = fb.index(x, y);
      active[count] = primaryRay(frame, x, y, pixels[count], rays[count]);
    }
  if (!frame.scene.empty())
  {
    // Where the previous block's rays hit more than three quarters different primitives (dense
    // data seen from far: 10M tube links in 1280x720), they also part ways in the BVH, and a
    // wide packet cost 12 % more than it shared; trace such blocks as rows of 4. Blocks of
    // small spheres a few pixels wide stay below the threshold and gain from wide packets.
    // The image is the same either way.
    constexpr int kNarrow = 4;
    if (divergent && count > kNarrow)
      for (int row = 0; row < count; row += kNarrow)
        frame.scene.intersectPacket(rays + row, active + row, std::min(kNarrow, count - row),
          hits + row, found + row, true);
    else
      frame.scene.intersectPacket(rays, active, count, hits, found, true);
    int hitCount = 0, distinct = 0;
    for (int lane = 0; lane < count; ++lane)
    {
      if (!found[lane])
        continue;
      ++hitCount;
      bool seen = false;
      for (int other = 0; other < lane && !seen; ++other)
        seen = found[other] && hits[other].primID == hits[lane].primID &&
          hits[other].geomID == hits[lane].geomID;
      distinct += !seen;
    }
    divergent = 4 * distinct > 3 * hitCount + 2;
  }

  const bool withVolumes = frame.options.volumes.scene && !frame.options.volumes.scene->empty();
  const bool withTranslucent = frame.options.translucent.scene && !frame.options.translucent.scene->empty();
  PixelState pixel[kMax];
  bool shaded[kMax];
  for (int lane = 0; lane < count; ++lane)
  {
    shaded[lane] = active[lane] && (found[lane] || withVolumes || withTranslucent);
    if (shaded[lane])
      shadeSurfaceAndVolumes(frame, x0 + lane % shape.columns, y0 + lane / shape.columns,
        rays[lane], found[lane], hits[lane], scratch, pixel[lane]);
  }
  if (withTranslucent)
  {
    DoubleRay segments[kMax];
    vec4 colors[kMax];
    double nearest[kMax];
    for (int lane = 0; lane < count; ++lane)
      if (shaded[lane])
      {
        segments[lane] = pixel[lane].segment;
        colors[lane] = pixel[lane].color;
      }
    compositeTranslucent(frame, segments, shaded, count, colors, nearest, scratch);
    for (int lane = 0; lane < count; ++lane)
      if (shaded[lane])
      {
        pixel[lane].color = colors[lane];
        pixel[lane].depthT = std::min(pixel[lane].depthT, nearest[lane]);
      }
  }
  std::size_t opaque = 0;
  for (int lane = 0; lane < count; ++lane)
  {
    if (!shaded[lane] || !(pixel[lane].depthT < kInfinity))
      continue;
    writePixel(frame, pixels[lane], rays[lane], found[lane], hits[lane], pixel[lane], fb);
    opaque += found[lane];
  }
  return opaque;
}
} // namespace

PacketBlock packetBlock(int packetSize)
{
  switch (packetSize)
  {
    case 16: return { 4, 4 };
    case 8: return { 4, 2 };
    case 4: return { 2, 2 };
    default: return { 1, 1 };
  }
}

RenderStatistics Renderer::render(const EmbreeScene& scene, const Camera& camera,
  const Lighting& lighting, Framebuffer& framebuffer, const RenderOptions& options) const
{
  if (options.packetSize != 0 && options.packetSize != 1 && options.packetSize != 4 &&
    options.packetSize != 8 && options.packetSize != 16)
    throw std::invalid_argument("sightline::Renderer: packet size " +
      std::to_string(options.packetSize) + " is not 0 (native), 1, 4, 8 or 16");
  const auto start = std::chrono::steady_clock::now();
  framebuffer.resize(camera.width(), camera.height());
  if (options.primitiveIds)
    framebuffer.Primitives.assign(framebuffer.pixelCount(), PixelPrimitive{});
  RenderStatistics stats;
  const EmbreeScene* translucent = options.translucent.scene;
  if (scene.empty() && !(translucent && !translucent->empty()))
    return stats;
  if (options.depthLimit && options.depthLimit->size() != framebuffer.pixelCount())
    throw std::invalid_argument("sightline::Renderer: the depth limit has " +
      std::to_string(options.depthLimit->size()) + " values for " +
      std::to_string(framebuffer.pixelCount()) + " pixels");

  const bool identity = options.objectToWorld == dmat4(1.0);
  double unionGap = 0.0, translucentSegment = 1e30;
  Box3 translucentBounds;
  if (translucent && !translucent->empty())
  {
    const Box3 box = translucent->bounds();
    translucentBounds = box;
    const double diagonal = glm::length(box.upper - box.lower);
    // Interval ends come from double rays in each primitive's frame: their rounding scales with
    // the scene's size, not its distance from the origin (the small second term is double's).
    unionGap = 2e-7 * diagonal + 1e-14 * (glm::length(box.upper) + glm::length(box.lower));
    // A first segment of 1/64 of the scene: dense scenes saturate within a few segments, and
    // a ray through the whole scene costs log2(64) + 1 extra traversals at most.
    translucentSegment = std::max(diagonal / 32.0, 1e-30);
  }
  const FrameContext frame{ scene, camera, lighting, options, options.objectToWorld,
    glm::mat3(glm::transpose(glm::inverse(glm::dmat3(options.objectToWorld)))),
    glm::inverse(glm::dmat3(options.objectToWorld)), identity, unionGap, translucentSegment, translucentBounds,
    options.regionLower != dvec3(-kInfinity) || options.regionUpper != dvec3(kInfinity),
    options.packetSize ? options.packetSize : scene.device().packetSize() };
  const PacketBlock packet = packetBlock(frame.packetSize);
  const int packetColumns = packet.columns, packetRows = packet.rows;

  // Bands of tile rows, rendered one after another so that progress is reported (and a cancel
  // honoured) on the calling thread; tiles within a band run in parallel.
  const int tile = std::max(1, options.tileSize);
  const int height = camera.height();
  const int width = camera.width();
  const int tileRows = (height + tile - 1) / tile;
  const int bands = options.progress ? std::min(tileRows, 16) : 1;
  tbb::combinable<std::size_t> hits([] { return std::size_t(0); });
  tbb::enumerable_thread_specific<PixelScratch> scratches;
  for (int band = 0; band < bands; ++band)
  {
    const int y0 = (tileRows * band / bands) * tile;
    const int y1 = std::min(height, (tileRows * (band + 1) / bands) * tile);
    tbb::parallel_for(tbb::blocked_range2d<int>(y0, y1, tile, 0, width, tile),
      [&](const tbb::blocked_range2d<int>& r)
      {
        PixelScratch& scratch = scratches.local();
        std::size_t local = 0;
        bool divergent = false; // see renderPacket
        for (int y = r.rows().begin(); y < r.rows().end(); y += packetRows)
          for (int x = r.cols().begin(); x < r.cols().end(); x += packetColumns)
            local += renderPacket(frame, x, y, r, framebuffer, scratch, divergent);
        hits.local() += local;
      });
    if (options.progress && !options.progress(double(band + 1) / bands))
    {
      stats.completed = band + 1 == bands;
      break;
    }
  }
  stats.hits = hits.combine(std::plus<std::size_t>());
  for (const PixelScratch& scratch : scratches)
  {
    stats.shadowRays += scratch.shadowRays;
    stats.translucentSurfaces += scratch.translucentSurfaces;
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}
} // namespace sightline
