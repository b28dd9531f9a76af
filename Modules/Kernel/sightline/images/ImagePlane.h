// SPDX-License-Identifier: BSD-3-Clause
// An image slice as a ray tracer sees it: a flat rectangle carrying an RGBA texture, drawn the
// way OpenGL draws VTK's textured slice quad (vtkImageSliceMapper), so that a slice traced here
// and glyphs traced by the kernel meet at exact depths with no window and no OpenGL.
#pragma once

#include "sightline/core/Camera.h"
#include "sightline/core/Framebuffer.h"
#include "sightline/math/Math.h"

#include <cstdint>
#include <vector>

namespace sightline
{
class ImagePlane
{
public:
  /// How texels are read between their centres: OpenGL's GL_NEAREST and GL_LINEAR (bilinear
  /// with clamp-to-edge) on the 8-bit texture.
  enum class Filter
  {
    Nearest,
    Linear
  };

  /// A Width x Height texture of 8-bit RGBA texels, row by row (first row first), placed in
  /// object space: texture coordinates (s, t), in texels (texel (i, j) spans [i, i+1) x
  /// [j, j+1), its centre at (i + 0.5, j + 0.5)), lie at origin + s * sStep + t * tStep.
  /// Only the rectangle [lower, upper] of texture coordinates is drawn (the quad: vtkImage-
  /// SliceMapper's runs from the first to the last texel centre, or the texels' full extent
  /// with its Border on). Throws std::invalid_argument for an empty texture, a texel array of
  /// the wrong size, degenerate (parallel or zero) steps or an empty rectangle.
  ImagePlane(const dvec3& origin, const dvec3& sStep, const dvec3& tStep, int width, int height,
    std::vector<std::uint8_t> rgba, const dvec2& lower, const dvec2& upper);

  void setFilter(Filter filter) { TextureFilter = filter; }
  Filter filter() const { return TextureFilter; }
  /// Scales the texels' colour (vtkImageProperty's Ambient: 1 shows them unchanged).
  void setBrightness(float brightness) { Brightness = brightness; }
  /// Multiplies the texels' alpha (vtkImageProperty's Opacity).
  void setOpacity(float opacity) { Opacity = opacity; }

  /// True when every drawn pixel is opaque (opacity 1 and no texel alpha below 255): the
  /// slice then belongs to the opaque pass, otherwise to the translucent one.
  bool opaque() const;

  /// The colour (texel colour times brightness, alpha times opacity) at texture coordinates
  /// (s, t), filtered as set.
  vec4 sample(double s, double t) const;

  /// Where the ray meets the drawn rectangle: its parameter and texture coordinates; false
  /// when it misses it (or runs parallel to the plane) or meets it outside [tnear, tfar].
  bool intersect(const DoubleRay& ray, double& t, dvec2& texture) const;

  /// Traces the plane into `framebuffer` (resized to the camera's image): colour, window
  /// depth and distance where the rectangle is seen, nothing elsewhere; pixels whose depth
  /// would not be nearer than `depthLimit` (window depths, when given) are left empty, as the
  /// depth test leaves them.
  void render(const Camera& camera, Framebuffer& framebuffer,
    const std::vector<float>* depthLimit = nullptr) const;

private:
  vec4 texel(int i, int j) const;

  dvec3 Origin, SStep, TStep;
  dvec3 Normal;
  // Solves p - Origin = s * SStep + t * TStep for points on the plane (steps need not be
  // orthogonal: a prop matrix may shear).
  dvec3 SDual, TDual;
  int Width, Height;
  std::vector<std::uint8_t> Texels;
  dvec2 Lower, Upper;
  Filter TextureFilter = Filter::Nearest;
  float Brightness = 1.0f;
  float Opacity = 1.0f;
};
} // namespace sightline
