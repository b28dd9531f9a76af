// Tile-parallel primary-ray rendering of an EmbreeScene into a Framebuffer.
#pragma once

#include "sightline/Camera.h"
#include "sightline/EmbreeScene.h"
#include "sightline/Framebuffer.h"
#include "sightline/Shading.h"

#include <functional>

namespace sightline
{
struct RenderOptions
{
  /// Tiles are the unit of parallel work; 16x16 pixels keep rays coherent.
  int tileSize = 16;
  /// Transform from the scene's coordinates to world coordinates (a VTK actor's matrix).
  /// The camera must then map scene coordinates to clip space (worldToClip * objectToWorld);
  /// normals are taken to world space with the inverse transpose before shading.
  dmat4 objectToWorld{ 1.0 };
  /// Called on the calling thread with the fraction done (0..1) between bands of rows.
  /// Returning false stops the render early (what was not rendered stays cleared).
  std::function<bool(double)> progress;
};

/// Result of one render, for progress reports and benchmarks.
struct RenderStatistics
{
  double seconds = 0.0;
  std::size_t hits = 0;
  bool completed = true;
};

class Renderer
{
public:
  /// Renders the committed scene as the camera sees it, with the geometries' materials and the
  /// given lights (directions in world coordinates). The framebuffer is resized to the camera.
  RenderStatistics render(const EmbreeScene& scene, const Camera& camera, const Lighting& lighting,
    Framebuffer& framebuffer, const RenderOptions& options = {}) const;
};
} // namespace sightline
