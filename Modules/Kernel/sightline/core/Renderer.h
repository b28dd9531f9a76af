// SPDX-License-Identifier: BSD-3-Clause
// Tile-parallel primary-ray rendering of an EmbreeScene into a Framebuffer.
#pragma once

#include "sightline/core/Camera.h"
#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Framebuffer.h"
#include "sightline/core/Shading.h"

#include <functional>

namespace sightline
{
enum class ShadowMode
{
  None, ///< no shadow rays at all
  Hard, ///< one ray towards each directional light
  Soft, ///< `samples` rays into the cone of a spherical light (angular radius below)
};

struct ShadowOptions
{
  ShadowMode mode = ShadowMode::None;
  int samples = 16;
  /// Angular radius (radians) of the spherical light as seen from the scene.
  float lightAngularRadius = 0.15f;
  /// Samples are a stratified pattern rotated by a hash of the pixel and this seed, so a
  /// frame is reproducible bit for bit.
  unsigned seed = 0;
};

/// Homogeneous volumes drawn over the surfaces (Peters et al. 2023, Section 4.3): along each
/// pixel's ray up to the first opaque surface, the length d spent inside the volume geometries
/// gives transmittance T = exp(-extinction d), and the pixel becomes T * colour + (1 - T) *
/// emission.
struct VolumeOptions
{
  const EmbreeScene* scene = nullptr; ///< committed scene of volume geometries, or null
  float extinction = 1.0f;            ///< per world unit (after RenderOptions::objectToWorld)
  vec3 emission{ 0.5f };
};

/// Translucent unions of solids (Han et al. 2019, Section 4.3: generalized tubes) drawn over the
/// opaque surfaces. Along each pixel's ray, up to the first opaque surface, the inside intervals
/// of every primitive (Geometry::insideIntervals) are collected, and only the surfaces of their
/// union are shaded and composited front to back, each with its geometry material's opacity:
/// overlapping solids show no interior surfaces. Rays that start inside a solid see its exit
/// only. Translucent surfaces cast no shadows.
struct TranslucentOptions
{
  const EmbreeScene* scene = nullptr; ///< committed scene of union geometries, or null
  /// Compositing stops once the accumulated opacity reaches this: the rest cannot show.
  float saturation = 0.996f;
};

struct RenderOptions
{
  ShadowOptions shadows;
  VolumeOptions volumes;
  TranslucentOptions translucent;
  /// Window depth of opaque geometry drawn by someone else (e.g. read back from OpenGL), one
  /// per pixel of the camera, bottom row first; rays stop there. Null for none.
  const std::vector<float>* depthLimit = nullptr;
  /// Also record, per pixel, the opaque primitive the primary ray hit (Framebuffer::Primitives),
  /// for picking. Off by default: a frame without it allocates and writes nothing more.
  bool primitiveIds = false;
  /// Tiles are the unit of parallel work; 16x16 pixels keep rays coherent.
  int tileSize = 16;
  /// Primary rays traced together as one Embree packet (a 4x4, 4x2 or 2x2 block of a tile):
  /// 0 takes the machine's native size (EmbreeDevice::packetSize); 1, 4, 8 or 16 force one,
  /// 1 tracing ray by ray. Every size gives the same image.
  int packetSize = 0;
  /// Transform from the scene's coordinates to world coordinates (a VTK actor's matrix).
  /// The camera must then map scene coordinates to clip space (worldToClip * objectToWorld);
  /// normals are taken to world space with the inverse transpose before shading.
  dmat4 objectToWorld{ 1.0 };
  /// The box of world space this render draws, for sort-last compositing in visibility order
  /// (one MPI rank's region of a kd-tree partition, say). Every primary ray is clipped to it:
  /// surfaces, volumes and translucent layers outside are not drawn, and a ray that enters the
  /// region inside a translucent solid draws only the union surfaces within. So the images of
  /// regions that tile space, blended front to back ("over", premultiplied), give the unclipped
  /// image. Faces may be infinite; the default, all of space, clips nothing.
  dvec3 regionLower{ -std::numeric_limits<double>::infinity() };
  dvec3 regionUpper{ std::numeric_limits<double>::infinity() };
  /// Called on the calling thread with the fraction done (0..1) between bands of rows.
  /// Returning false stops the render early (what was not rendered stays cleared).
  std::function<bool(double)> progress;
};

/// Result of one render, for progress reports and benchmarks.
struct RenderStatistics
{
  double seconds = 0.0;
  std::size_t hits = 0;
  std::size_t shadowRays = 0;
  std::size_t translucentSurfaces = 0; ///< union surfaces composited (translucent scenes)
  bool completed = true;
};

/// The block of pixels whose primary rays one packet of `packetSize` rays traces (4x4, 4x2,
/// 2x2, else 1x1), so that they are coherent; lane = column + columns * row.
struct PacketBlock
{
  int columns, rows;
};
PacketBlock packetBlock(int packetSize);

class Renderer
{
public:
  /// Renders the committed scene as the camera sees it, with the geometries' materials and the
  /// given lights (directions in world coordinates). The framebuffer is resized to the camera.
  RenderStatistics render(const EmbreeScene& scene, const Camera& camera, const Lighting& lighting,
    Framebuffer& framebuffer, const RenderOptions& options = {}) const;
};
} // namespace sightline
