// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/images/ImagePlane.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace sightline
{
ImagePlane::ImagePlane(const dvec3& origin, const dvec3& sStep, const dvec3& tStep, int width,
  int height, std::vector<std::uint8_t> rgba, const dvec2& lower, const dvec2& upper)
  : Origin(origin)
  , SStep(sStep)
  , TStep(tStep)
  , Width(width)
  , Height(height)
  , Texels(std::move(rgba))
  , Lower(lower)
  , Upper(upper)
{
  if (width <= 0 || height <= 0)
  {
    throw std::invalid_argument("ImagePlane: an empty texture (" + std::to_string(width) + "x" +
      std::to_string(height) + " texels)");
  }
  if (Texels.size() != std::size_t(width) * std::size_t(height) * 4)
  {
    throw std::invalid_argument("ImagePlane: " + std::to_string(Texels.size()) +
      " texel bytes for " + std::to_string(width) + "x" + std::to_string(height) +
      " RGBA texels");
  }
  if (!(lower.x < upper.x) || !(lower.y < upper.y))
  {
    throw std::invalid_argument("ImagePlane: an empty rectangle of texture coordinates");
  }
  Normal = glm::cross(sStep, tStep);
  const double area = glm::length(Normal);
  if (!(area > 0.0) || !std::isfinite(area))
  {
    throw std::invalid_argument("ImagePlane: the texel steps are zero, parallel or not finite");
  }
  Normal /= area;
  // Dual basis: dot(SDual, SStep) = 1, dot(SDual, TStep) = 0, and the same for TDual.
  const double ss = glm::dot(sStep, sStep), st = glm::dot(sStep, tStep), tt = glm::dot(tStep, tStep);
  const double determinant = ss * tt - st * st;
  SDual = (tt * sStep - st * tStep) / determinant;
  TDual = (ss * tStep - st * sStep) / determinant;
}

bool ImagePlane::opaque() const
{
  if (Opacity < 1.0f)
  {
    return false;
  }
  for (std::size_t i = 3; i < Texels.size(); i += 4)
  {
    if (Texels[i] != 255)
    {
      return false;
    }
  }
  return true;
}

vec4 ImagePlane::texel(int i, int j) const
{
  i = std::clamp(i, 0, Width - 1); // clamp to edge, as VTK's slice textures do
  j = std::clamp(j, 0, Height - 1);
  const std::uint8_t* p = &Texels[(std::size_t(j) * Width + i) * 4];
  return vec4(p[0], p[1], p[2], p[3]) * (1.0f / 255.0f);
}

vec4 ImagePlane::sample(double s, double t) const
{
  vec4 colour;
  if (TextureFilter == Filter::Nearest)
  {
    colour = texel(int(std::floor(s)), int(std::floor(t)));
  }
  else
  {
    // Bilinear between the four nearest texel centres.
    const double u = s - 0.5, v = t - 0.5;
    const double i0 = std::floor(u), j0 = std::floor(v);
    const float a = float(u - i0), b = float(v - j0);
    const int i = int(i0), j = int(j0);
    colour = (1.0f - b) * ((1.0f - a) * texel(i, j) + a * texel(i + 1, j)) +
      b * ((1.0f - a) * texel(i, j + 1) + a * texel(i + 1, j + 1));
  }
  return vec4(vec3(colour) * Brightness, colour.a * Opacity);
}

bool ImagePlane::intersect(const DoubleRay& ray, double& t, dvec2& texture) const
{
  const double denominator = glm::dot(ray.direction, Normal);
  if (denominator == 0.0)
  {
    return false; // seen edge-on: OpenGL rasterises no fragment either
  }
  t = glm::dot(Origin - ray.origin, Normal) / denominator;
  if (!(t >= ray.tnear && t <= ray.tfar))
  {
    return false;
  }
  const dvec3 offset = ray.origin + t * ray.direction - Origin;
  texture = dvec2(glm::dot(offset, SDual), glm::dot(offset, TDual));
  return texture.x >= Lower.x && texture.x <= Upper.x && texture.y >= Lower.y &&
    texture.y <= Upper.y;
}

void ImagePlane::render(
  const Camera& camera, Framebuffer& framebuffer, const std::vector<float>* depthLimit) const
{
  framebuffer.resize(camera.width(), camera.height());
  if (depthLimit && depthLimit->size() != framebuffer.pixelCount())
  {
    throw std::invalid_argument("ImagePlane::render: the depth limit has " +
      std::to_string(depthLimit->size()) + " values for " +
      std::to_string(framebuffer.pixelCount()) + " pixels");
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, camera.height(), 8),
    [&](const tbb::blocked_range<int>& rows)
    {
      for (int y = rows.begin(); y < rows.end(); ++y)
      {
        for (int x = 0; x < camera.width(); ++x)
        {
          const DoubleRay ray = camera.doublePrimaryRay(x + 0.5, y + 0.5);
          double t;
          dvec2 texture;
          if (!intersect(ray, t, texture))
          {
            continue;
          }
          const std::size_t pixel = framebuffer.index(x, y);
          const double depth = camera.windowDepth(ray.origin + t * ray.direction);
          if (depthLimit && !(depth < (*depthLimit)[pixel]))
          {
            continue;
          }
          framebuffer.Color[pixel] = sample(texture.x, texture.y);
          framebuffer.Depth[pixel] = float(depth);
          framebuffer.Distance[pixel] = float(t);
        }
      }
    });
}
} // namespace sightline
