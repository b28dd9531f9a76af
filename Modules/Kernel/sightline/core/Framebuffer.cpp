// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/core/Framebuffer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sightline
{
namespace
{
// Colour (vec4), window depth and distance: what one pixel costs.
constexpr std::size_t kBytesPerPixel = sizeof(vec4) + 2 * sizeof(float);
// The memory budget of one framebuffer (see resize): 8 GiB, about 358 million pixels (an 18900
// x 18900 image), far beyond any screen or poster yet small enough to be refused cleanly
// instead of ending in std::bad_alloc or the out-of-memory killer.
constexpr std::size_t kMaxBytes = std::size_t(8) << 30;
} // namespace

void Framebuffer::resize(int width, int height)
{
  if (width < 0 || height < 0)
    throw std::invalid_argument("sightline::Framebuffer: negative size " + std::to_string(width) +
      " x " + std::to_string(height));
  // Checked before anything changes: a refused size leaves the framebuffer as it was.
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (pixels > kMaxBytes / kBytesPerPixel)
    throw std::length_error("sightline::Framebuffer: a " + std::to_string(width) + " x " +
      std::to_string(height) + " image needs " + std::to_string(pixels) + " pixels of " +
      std::to_string(kBytesPerPixel) + " bytes, beyond the budget of " +
      std::to_string(kMaxBytes >> 30) + " GiB (" + std::to_string(kMaxBytes / kBytesPerPixel) +
      " pixels)");
  Width = width;
  Height = height;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  Color.resize(n);
  Depth.resize(n);
  Distance.resize(n);
  Primitives.clear();
  clear();
}

void Framebuffer::clear()
{
  // In parallel: every frame starts here (50 MB at 1920x1080), on the caller's thread.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, Color.size(), 1 << 15),
    [&](const tbb::blocked_range<std::size_t>& range)
    {
      std::fill(Color.begin() + range.begin(), Color.begin() + range.end(), vec4(0.0f));
      std::fill(Depth.begin() + range.begin(), Depth.begin() + range.end(), 1.0f);
      std::fill(Distance.begin() + range.begin(), Distance.begin() + range.end(), kInfinity);
    });
  std::fill(Primitives.begin(), Primitives.end(), PixelPrimitive{});
}

namespace
{
using Floats4 = float __attribute__((vector_size(16)));
using Doubles4 = double __attribute__((vector_size(32)));
using Ints4 = int __attribute__((vector_size(16)));

/// One pixel's four channels: round(clamp(v, 0, 1) * 255), halves away from zero, as
/// std::lround rounds. v * 255 is a float in [0, 255], so adding 0.5 in double is exact and
/// truncation rounds it. On vectors without a library call or a branch (std::lround per channel
/// took 40 ms a 1080p frame); NaN gives 0, as before.
inline void toBytes(Floats4 v, std::uint8_t* out)
{
  const Floats4 zero = {}, one = zero + 1.0f;
  v = v > zero ? v : zero; // NaN fails the comparison: 0
  v = v < one ? v : one;
  const Ints4 rounded =
    __builtin_convertvector(__builtin_convertvector(v * 255.0f, Doubles4) + 0.5, Ints4);
  for (int channel = 0; channel < 4; ++channel)
    out[channel] = static_cast<std::uint8_t>(rounded[channel]);
}
} // namespace

std::vector<std::uint8_t> Framebuffer::toRGBA8(const vec3& background) const
{
  std::vector<std::uint8_t> out(4 * Color.size());
  // In parallel: every window frame converts its whole image before the upload.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, Color.size(), 1 << 14),
    [&](const tbb::blocked_range<std::size_t>& range)
    {
      const vec4* colors = Color.data();
      std::uint8_t* bytes = out.data(); // a local pointer: the stores cannot alias it
      for (std::size_t i = range.begin(); i < range.end(); ++i)
      {
        const vec4& c = colors[i];
        const vec3 rgb = glm::mix(background, vec3(c), c.a);
        toBytes(Floats4{ rgb.r, rgb.g, rgb.b, c.a }, bytes + 4 * i);
      }
    });
  return out;
}

void Framebuffer::compositeNearest(const Framebuffer& other)
{
  if (other.Width != Width || other.Height != Height)
    throw std::invalid_argument("sightline::Framebuffer::compositeNearest: sizes differ");
  const bool primitives = !Primitives.empty() && other.Primitives.size() == Primitives.size();
  if (!primitives)
    Primitives.clear();
  for (std::size_t i = 0; i < Color.size(); ++i)
  {
    if (other.Depth[i] < Depth[i])
    {
      Color[i] = other.Color[i];
      Depth[i] = other.Depth[i];
      Distance[i] = other.Distance[i];
      if (primitives)
        Primitives[i] = other.Primitives[i];
    }
  }
}

void Framebuffer::blendUnder(const Framebuffer& front, bool nearerDepth)
{
  if (front.Width != Width || front.Height != Height)
    throw std::invalid_argument("sightline::Framebuffer::blendUnder: sizes differ");
  for (std::size_t i = 0; i < Color.size(); ++i)
  {
    const vec4& f = front.Color[i];
    if (f.a <= 0.0f)
      continue;
    const vec4& b = Color[i];
    const float alpha = f.a + (1.0f - f.a) * b.a;
    const vec3 premultiplied = f.a * vec3(f) + (1.0f - f.a) * b.a * vec3(b);
    Color[i] = vec4(premultiplied / alpha, alpha);
    if (nearerDepth && front.Depth[i] < Depth[i])
    {
      Depth[i] = front.Depth[i];
      Distance[i] = front.Distance[i];
    }
  }
}
} // namespace sightline
