// SPDX-License-Identifier: BSD-3-Clause
// Sort-last compositing as MPI ranks do it under ordered compositing, for the region tests: the
// images of regions that tile space, blended front to back ("over", premultiplied) in the order
// a pixel's ray enters the regions.
#pragma once

#include "sightline/core/Camera.h"
#include "sightline/core/Framebuffer.h"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

namespace sightline_test
{
struct RegionBlend
{
  sightline::vec3 premultiplied{ 0.0f };
  float alpha = 0.0f;
  int contributing = 0; ///< regions with a layer at the pixel
};

/// Pixel (px, py) of `parts` (one image per region [lower, upper]) blended in ray order.
inline RegionBlend blendRegionsInRayOrder(const std::vector<std::array<sightline::dvec3, 2>>& regions,
  const std::vector<sightline::Framebuffer>& parts, const sightline::Camera& camera, int px, int py)
{
  // Convex regions: the ray meets them in the order of its entry into each.
  const sightline::DoubleRay ray = camera.doublePrimaryRay(px + 0.5, py + 0.5);
  std::vector<std::pair<double, std::size_t>> order;
  for (std::size_t r = 0; r < regions.size(); ++r)
  {
    double t0 = ray.tnear, t1 = ray.tfar;
    if (sightline::clipToBox(ray.origin, ray.direction, regions[r][0], regions[r][1], t0, t1))
      order.emplace_back(t0, r);
  }
  std::sort(order.begin(), order.end());
  RegionBlend blend;
  for (const auto& entry : order)
  {
    const sightline::Framebuffer& part = parts[entry.second];
    const sightline::vec4 c = part.Color[part.index(px, py)];
    blend.premultiplied += (1.0f - blend.alpha) * c.a * sightline::vec3(c);
    blend.alpha += (1.0f - blend.alpha) * c.a;
    blend.contributing += c.a > 0.0f;
  }
  return blend;
}
} // namespace sightline_test
