// SPDX-License-Identifier: BSD-3-Clause
// Framebuffer: clearing, 8-bit conversion (compositing over the background, clamping, rounding)
// and depth compositing.
#include "sightline/core/Framebuffer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace
{
using sightline::Framebuffer;
using sightline::vec3;
using sightline::vec4;

/// Independent 8-bit conversion: composite in double, clamp, round to nearest.
std::uint8_t expectedByte(double foreground, double background, double alpha)
{
  const double composited = background * (1 - alpha) + foreground * alpha;
  return std::uint8_t(std::floor(std::clamp(composited, 0.0, 1.0) * 255 + 0.5));
}

TEST(Framebuffer, ResizeClearsToNothingHit)
{
  Framebuffer framebuffer(5, 3);
  EXPECT_EQ(framebuffer.width(), 5);
  EXPECT_EQ(framebuffer.height(), 3);
  ASSERT_EQ(framebuffer.pixelCount(), 15u);
  EXPECT_EQ(framebuffer.index(4, 2), 14u);
  EXPECT_EQ(framebuffer.index(1, 2), 11u); // row-major, bottom row first
  framebuffer.Color[7] = vec4(1.0f);
  framebuffer.Depth[7] = 0.5f;
  framebuffer.Distance[7] = 2.0f;
  framebuffer.resize(4, 4);
  ASSERT_EQ(framebuffer.pixelCount(), 16u);
  for (std::size_t i = 0; i < framebuffer.pixelCount(); ++i)
  {
    EXPECT_EQ(framebuffer.Color[i], vec4(0.0f));
    EXPECT_EQ(framebuffer.Depth[i], 1.0f);
    EXPECT_TRUE(std::isinf(framebuffer.Distance[i]));
  }
  EXPECT_THROW(framebuffer.resize(-1, 2), std::invalid_argument);
}

TEST(Framebuffer, ToRGBA8CompositesOverTheBackgroundAndRounds)
{
  Framebuffer framebuffer(3, 2);
  // Values chosen away from x.5 ties after scaling by 255, so rounding is unambiguous, and
  // such that truncation would give a different byte.
  const std::vector<vec4> colors{
    { 0.403f, 0.802f, 0.131f, 1.0f }, // opaque: background irrelevant
    { 0.9f, 0.2f, 0.6f, 0.37f },      // partly transparent
    { 0.7f, 0.7f, 0.7f, 0.0f },       // nothing hit: pure background
    { 1.7f, -0.3f, 0.52f, 1.0f },     // out of range: clamped
    { 0.25f, 0.5f, 0.75f, 0.8f },     { 0.0f, 1.0f, 0.0f, 0.55f },
  };
  framebuffer.Color = colors;
  const vec3 background(0.12f, 0.33f, 0.91f);
  const std::vector<std::uint8_t> bytes = framebuffer.toRGBA8(background);
  ASSERT_EQ(bytes.size(), 4 * colors.size());
  for (std::size_t i = 0; i < colors.size(); ++i)
  {
    const vec4& c = colors[i];
    for (int channel = 0; channel < 3; ++channel)
      EXPECT_EQ(bytes[4 * i + channel], expectedByte(c[channel], background[channel], c.a))
        << "pixel " << i << ", channel " << channel;
    EXPECT_EQ(bytes[4 * i + 3], expectedByte(c.a, 0.0, 1.0)) << "pixel " << i;
  }
  // Spot checks written out by hand.
  EXPECT_EQ(bytes[0], 103); // 0.403 * 255 = 102.77
  EXPECT_EQ(bytes[8], 31);  // background 0.12 * 255 = 30.6
  EXPECT_EQ(bytes[12], 255);
  EXPECT_EQ(bytes[13], 0);
}

TEST(Framebuffer, ToRGBA8RoundsEveryFloatAsLround)
{
  // The conversion rounds v * 255 (a float) halves away from zero, as std::lround does: every
  // tie that a float channel can produce, the floats on either side of it, and a sweep of
  // values across and beyond [0, 1], opaque so that the background drops out.
  std::vector<float> values{ 0.0f, 1.0f, -0.0f, -1e-30f, 1e-30f, 2.0f, -5.0f };
  int ties = 0;
  for (int k = 0; k < 255; ++k)
  {
    float v = float((k + 0.5) / 255.0);
    for (int step = 0; step < 4; ++step)
      v = std::nextafter(v, 0.0f);
    for (int step = 0; step < 9; ++step, v = std::nextafter(v, 1.0f))
    {
      values.push_back(v);
      ties += v * 255.0f == float(k) + 0.5f;
    }
  }
  ASSERT_GT(ties, 100); // the test really meets ties
  for (int i = 0; i <= 100000; ++i)
    values.push_back(-0.1f + 1.2f * float(i) / 100000.0f);
  Framebuffer framebuffer(int(values.size()), 1);
  for (std::size_t i = 0; i < values.size(); ++i)
    framebuffer.Color[i] = vec4(values[i], values[i], values[i], 1.0f);
  const std::vector<std::uint8_t> bytes = framebuffer.toRGBA8(vec3(0.3f));
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    const auto reference = std::uint8_t(std::lround(std::clamp(values[i], 0.0f, 1.0f) * 255.0f));
    ASSERT_EQ(bytes[4 * i], reference) << "value " << values[i];
    ASSERT_EQ(bytes[4 * i + 3], 255);
  }
}

TEST(Framebuffer, CompositeNearestKeepsTheSmallerDepth)
{
  Framebuffer near(2, 2), far(2, 2);
  // Pixel 0: only `near` hit. Pixel 1: both, `near` closer. Pixel 2: both, `far` closer.
  // Pixel 3: neither.
  near.Color[0] = vec4(1, 0, 0, 1), near.Depth[0] = 0.3f, near.Distance[0] = 3.0f;
  near.Color[1] = vec4(1, 0, 0, 1), near.Depth[1] = 0.4f, near.Distance[1] = 4.0f;
  far.Color[1] = vec4(0, 1, 0, 1), far.Depth[1] = 0.6f, far.Distance[1] = 6.0f;
  near.Color[2] = vec4(1, 0, 0, 1), near.Depth[2] = 0.9f, near.Distance[2] = 9.0f;
  far.Color[2] = vec4(0, 1, 0, 1), far.Depth[2] = 0.2f, far.Distance[2] = 2.0f;

  Framebuffer composite = near;
  composite.compositeNearest(far);
  EXPECT_EQ(composite.Color[0], vec4(1, 0, 0, 1));
  EXPECT_EQ(composite.Depth[0], 0.3f);
  EXPECT_EQ(composite.Color[1], vec4(1, 0, 0, 1));
  EXPECT_EQ(composite.Depth[1], 0.4f);
  EXPECT_EQ(composite.Distance[1], 4.0f);
  EXPECT_EQ(composite.Color[2], vec4(0, 1, 0, 1));
  EXPECT_EQ(composite.Depth[2], 0.2f);
  EXPECT_EQ(composite.Distance[2], 2.0f);
  EXPECT_EQ(composite.Color[3], vec4(0.0f));
  EXPECT_EQ(composite.Depth[3], 1.0f);

  // The order of compositing must not matter.
  Framebuffer reversed = far;
  reversed.compositeNearest(near);
  EXPECT_EQ(reversed.Color, composite.Color);
  EXPECT_EQ(reversed.Depth, composite.Depth);
  EXPECT_EQ(reversed.Distance, composite.Distance);

  EXPECT_THROW(composite.compositeNearest(Framebuffer(2, 3)), std::invalid_argument);
}
} // namespace

// A huge image size used to end in an uncaught std::bad_alloc (abort) inside resize; it must be
// refused with an exception naming the size and the budget, and leave the framebuffer as it was.
TEST(Framebuffer, SizeBeyondTheMemoryBudgetIsRefusedByName)
{
  Framebuffer framebuffer(4, 2);
  framebuffer.Color[3] = vec4(1.0f);
  for (const auto& size : { std::pair<int, int>{ 46341, 46341 }, { 100000, 100000 },
         { 2147483647, 2147483647 }, { 1, 2147483647 } })
  {
    try
    {
      framebuffer.resize(size.first, size.second);
      ADD_FAILURE() << size.first << " x " << size.second << " was accepted";
    }
    catch (const std::length_error& error)
    {
      const std::string message = error.what();
      EXPECT_NE(message.find(std::to_string(size.first) + " x " + std::to_string(size.second)),
        std::string::npos)
        << message;
      EXPECT_NE(message.find("budget of 8 GiB"), std::string::npos) << message;
    }
    EXPECT_EQ(framebuffer.width(), 4);
    EXPECT_EQ(framebuffer.height(), 2);
    ASSERT_EQ(framebuffer.pixelCount(), 8u);
    EXPECT_EQ(framebuffer.Color[3], vec4(1.0f));
  }
  EXPECT_THROW(Framebuffer(-1, 5), std::invalid_argument);
  // An ordinary large image is still accepted.
  framebuffer.resize(4096, 2160);
  EXPECT_EQ(framebuffer.pixelCount(), 4096u * 2160u);
}
