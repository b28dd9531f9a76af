// SPDX-License-Identifier: BSD-3-Clause
// Colour and depth of one rendered view, stored bottom row first as OpenGL and vtkImageData do.
#pragma once

#include "sightline/math/Math.h"

#include <cstdint>
#include <vector>

namespace sightline
{
/// The primitive a pixel's primary ray hit: its geometry's index in the scene and its index in
/// that geometry (Embree's geomID and primID), or for geometries whose primitives hold several
/// selectable elements the element hit (Geometry::selectionIndex: a tube chunk's link).
/// kNone in both where nothing opaque was hit.
struct PixelPrimitive
{
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::uint32_t geometry = kNone;
  std::uint32_t primitive = kNone;
  bool hit() const { return primitive != kNone; }
};

class Framebuffer
{
public:
  Framebuffer() = default;
  Framebuffer(int width, int height) { resize(width, height); }

  /// Resizes and clears to "nothing hit": colour (0,0,0,0), window depth 1, distance infinity;
  /// empties Primitives (only a render that asks for them fills them).
  /// Throws std::invalid_argument for a negative size and std::length_error, naming the size
  /// and the budget, for an image beyond the memory budget of 8 GiB (24 bytes a pixel: about
  /// 358 million pixels); the framebuffer is unchanged then.
  void resize(int width, int height);
  void clear();

  int width() const { return Width; }
  int height() const { return Height; }
  std::size_t pixelCount() const { return Color.size(); }
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * Width + x; }

  /// Linear RGBA, not premultiplied; alpha 0 where no primitive was hit.
  std::vector<vec4> Color;
  /// Window depth in [0, 1] (1 where nothing was hit), ready for gl_FragDepth.
  std::vector<float> Depth;
  /// World-space distance along the primary ray from the near plane (infinity on a miss).
  std::vector<float> Distance;
  /// Per pixel, the opaque primitive the primary ray hit (for picking). Empty unless the
  /// render asked for it (RenderOptions::primitiveIds): other frames neither allocate nor
  /// write it. Translucent layers and volumes record nothing here.
  std::vector<PixelPrimitive> Primitives;

  /// 8-bit RGBA composited over a background colour, bottom row first. Colours are clamped to
  /// [0, 1] and rounded; no gamma is applied, as VTK's OpenGL rendering applies none.
  std::vector<std::uint8_t> toRGBA8(const vec3& background) const;

  /// Keeps, per pixel, whichever of this and other is nearer (smaller window depth), the way the
  /// depth test composites several mappers in one window. Primitives are kept with their
  /// pixels when both framebuffers have them, and dropped otherwise.
  void compositeNearest(const Framebuffer& other);

  /// Puts this image behind a translucent layer `front` (alpha blending, "over"): colours and
  /// alpha blend, depth and distance stay this image's, as translucent surfaces drawn with
  /// alpha blending write no depth; unless `nearerDepth`, where pixels the layer covers take
  /// its depth and distance when they are nearer (volumes write the depth of their first
  /// visible sample).
  void blendUnder(const Framebuffer& front, bool nearerDepth = false);

private:
  int Width = 0;
  int Height = 0;
};
} // namespace sightline
