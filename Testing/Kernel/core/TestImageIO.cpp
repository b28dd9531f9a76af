// SPDX-License-Identifier: BSD-3-Clause
// ImageIO: PNG round trips exactly and keeps the orientation; EXR holds the colour, distance and
// window-depth channels under the documented names.
#include "KernelTestSupport.h"

#include "sightline/core/ImageIO.h"

#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

namespace
{
using namespace sightline_test;
using sightline::Framebuffer;
using sightline::vec3;
using sightline::vec4;

/// A small image with no symmetry: every pixel's colour encodes its (x, y), alpha varies, and
/// one column is left empty (alpha 0, depth 1, distance infinity).
Framebuffer asymmetricFramebuffer(int width, int height)
{
  Framebuffer framebuffer(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 1; x < width; ++x)
    {
      const std::size_t i = framebuffer.index(x, y);
      framebuffer.Color[i] =
        vec4(float(x) / width, float(y) / height, 0.25f + 0.05f * float((x * 7 + y * 3) % 11),
             (x + y) % 3 == 0 ? 1.0f : 0.2f + 0.6f * float(x) / width);
      framebuffer.Depth[i] = 0.1f + 0.8f * float(x + width * y) / float(width * height);
      framebuffer.Distance[i] = 1.0f + float(3 * x + 5 * y);
    }
  return framebuffer;
}

TEST(ImageIO, PngRoundTripsExactlyBottomRowFirst)
{
  const Framebuffer framebuffer = asymmetricFramebuffer(7, 5);
  const vec3 background(0.2f, 0.4f, 0.9f);
  const std::string path = outputPath("roundtrip.png");
  sightline::writeImage(path, framebuffer, background);

  int width = 0, height = 0;
  const std::vector<std::uint8_t> read = sightline::readImageRGBA8(path, width, height);
  EXPECT_EQ(width, 7);
  EXPECT_EQ(height, 5);
  const std::vector<std::uint8_t> expected = framebuffer.toRGBA8(background);
  ASSERT_EQ(read.size(), expected.size());
  for (std::size_t i = 0; i < read.size(); ++i)
    EXPECT_EQ(int(read[i]), int(expected[i])) << "pixel " << i / 4 << ", channel " << i % 4;
}

// The file itself must hold the composited colour and the alpha as written (top row first),
// whatever alpha convention a reader applies afterwards.
TEST(ImageIO, PngStoresTopRowFirstWithUnassociatedAlpha)
{
  const Framebuffer framebuffer = asymmetricFramebuffer(6, 4);
  const vec3 background(0.0f, 0.5f, 1.0f);
  const std::string path = outputPath("orientation.png");
  sightline::writeImage(path, framebuffer, background);

  OIIO::ImageSpec rawConfig;
  rawConfig.attribute("oiio:UnassociatedAlpha", 1); // no premultiplication on reading
  auto input = OIIO::ImageInput::open(path, &rawConfig);
  ASSERT_TRUE(input) << OIIO::geterror();
  ASSERT_EQ(input->spec().nchannels, 4);
  std::vector<std::uint8_t> file(6 * 4 * 4);
  ASSERT_TRUE(input->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, file.data()));
  const std::vector<std::uint8_t> expected = framebuffer.toRGBA8(background);
  for (int fileRow = 0; fileRow < 4; ++fileRow)
    for (int x = 0; x < 6; ++x)
      for (int c = 0; c < 4; ++c)
        EXPECT_EQ(int(file[(fileRow * 6 + x) * 4 + c]),
                  int(expected[framebuffer.index(x, 3 - fileRow) * 4 + c]))
          << "file row " << fileRow << ", x " << x << ", channel " << c;
}

TEST(ImageIO, ExrHoldsColourDistanceAndWindowDepthChannels)
{
  const Framebuffer framebuffer = asymmetricFramebuffer(5, 3);
  const std::string path = outputPath("channels.exr");
  sightline::writeEXR(path, framebuffer);

  auto input = OIIO::ImageInput::open(path);
  ASSERT_TRUE(input) << OIIO::geterror();
  const OIIO::ImageSpec& spec = input->spec();
  EXPECT_EQ(spec.width, 5);
  EXPECT_EQ(spec.height, 3);
  ASSERT_EQ(spec.nchannels, 6);
  std::vector<std::string> names(spec.channelnames.begin(), spec.channelnames.end());
  std::vector<std::string> sortedNames = names;
  std::sort(sortedNames.begin(), sortedNames.end());
  EXPECT_EQ(sortedNames, (std::vector<std::string>{ "A", "B", "G", "R", "Z", "depth.Z" }));

  // Look channels up by name: EXR does not promise to keep the order they were written in.
  auto channel = [&](const std::string& name)
  { return int(std::find(names.begin(), names.end(), name) - names.begin()); };
  std::vector<float> pixels(std::size_t(5) * 3 * 6);
  ASSERT_TRUE(input->read_image(0, 0, 0, 6, OIIO::TypeDesc::FLOAT, pixels.data()));
  for (int fileRow = 0; fileRow < 3; ++fileRow)
    for (int x = 0; x < 5; ++x)
    {
      const std::size_t i = framebuffer.index(x, 2 - fileRow); // files are top row first
      const float* p = &pixels[(std::size_t(fileRow) * 5 + x) * 6];
      const vec4& color = framebuffer.Color[i];
      EXPECT_EQ(p[channel("R")], color.r);
      EXPECT_EQ(p[channel("G")], color.g);
      EXPECT_EQ(p[channel("B")], color.b);
      EXPECT_EQ(p[channel("A")], color.a);
      EXPECT_EQ(p[channel("Z")], framebuffer.Distance[i]) << "Z is the distance along the ray";
      EXPECT_EQ(p[channel("depth.Z")], framebuffer.Depth[i]) << "depth.Z is the window depth";
    }
}

TEST(ImageIO, FailuresThrow)
{
  EXPECT_THROW(sightline::writeImage(outputPath("empty.png"), Framebuffer(), vec3(0.0f)),
               std::invalid_argument);
  EXPECT_THROW(sightline::writeEXR(outputPath("empty.exr"), Framebuffer()), std::invalid_argument);
  const Framebuffer framebuffer(2, 2);
  EXPECT_THROW(
    sightline::writeImage(outputPath("no/such/directory/image.png"), framebuffer, vec3(0.0f)),
    std::runtime_error);
  int width = 0, height = 0;
  EXPECT_THROW(sightline::readImageRGBA8(outputPath("does-not-exist.png"), width, height),
               std::runtime_error);
}
} // namespace
