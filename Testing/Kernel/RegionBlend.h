// SPDX-License-Identifier: BSD-3-Clause
// Sort-last compositing as MPI ranks do it under ordered compositing, for the region tests: the
// images of regions that tile space, blended front to back ("over", premultiplied) in the order
// a pixel's ray enters the regions.
#pragma once

#include "sightline/core/Camera.h"
#include "sightline/core/Framebuffer.h"

#include <gtest/gtest.h>

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

/// Every pixel of the regions' images blended in ray order against the whole image: opacity
/// within alphaTolerance, premultiplied colour within colourTolerance. Counts the covered
/// pixels and those with layers in several regions. A failed opacity check ends the comparison.
inline void expectRegionBlendIsWhole(const std::vector<std::array<sightline::dvec3, 2>>& regions,
  const std::vector<sightline::Framebuffer>& parts, const sightline::Framebuffer& whole,
  const sightline::Camera& camera, float alphaTolerance, float colourTolerance, int& covered, int& split)
{
  covered = split = 0;
  for (int py = 0; py < camera.height(); ++py)
    for (int px = 0; px < camera.width(); ++px)
    {
      const RegionBlend blend = blendRegionsInRayOrder(regions, parts, camera, px, py);
      const sightline::vec4 expected = whole.Color[whole.index(px, py)];
      ASSERT_NEAR(blend.alpha, expected.a, alphaTolerance) << "pixel " << px << ", " << py;
      if (expected.a == 0.0f)
        continue;
      ++covered;
      split += blend.contributing > 1;
      EXPECT_NEAR(glm::length(blend.premultiplied - expected.a * sightline::vec3(expected)), 0.0f, colourTolerance)
        << "pixel " << px << ", " << py;
    }
}
} // namespace sightline_test
