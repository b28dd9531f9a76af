// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/core/ImageIO.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <stdexcept>

namespace sightline
{
namespace
{
void writeScanlines(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
  const void* bottomRowFirst, std::size_t rowBytes)
{
  auto out = OIIO::ImageOutput::create(path);
  if (!out)
    throw std::runtime_error("sightline: cannot write '" + path + "': " + OIIO::geterror());
  if (!out->open(path, spec))
    throw std::runtime_error("sightline: cannot open '" + path + "': " + out->geterror());
  // Images are stored bottom row first; files want the top row first: a negative y stride.
  const char* lastRow = static_cast<const char*>(bottomRowFirst) + (spec.height - 1) * rowBytes;
  if (!out->write_image(type, lastRow, OIIO::AutoStride, -static_cast<OIIO::stride_t>(rowBytes)))
    throw std::runtime_error("sightline: writing '" + path + "' failed: " + out->geterror());
  out->close();
}
} // namespace

void writeImage(const std::string& path, const Framebuffer& fb, const vec3& background)
{
  if (fb.pixelCount() == 0)
    throw std::invalid_argument("sightline::writeImage: empty framebuffer");
  const std::vector<std::uint8_t> rgba = fb.toRGBA8(background);
  OIIO::ImageSpec spec(fb.width(), fb.height(), 4, OIIO::TypeDesc::UINT8);
  // The colour is already composited, not premultiplied: stop OIIO from dividing it by alpha.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  writeScanlines(path, spec, OIIO::TypeDesc::UINT8, rgba.data(), 4 * std::size_t(fb.width()));
}

void writeEXR(const std::string& path, const Framebuffer& fb)
{
  if (fb.pixelCount() == 0)
    throw std::invalid_argument("sightline::writeEXR: empty framebuffer");
  std::vector<float> pixels(6 * fb.pixelCount());
  for (std::size_t i = 0; i < fb.pixelCount(); ++i)
  {
    for (int c = 0; c < 4; ++c)
      pixels[6 * i + c] = fb.Color[i][c];
    pixels[6 * i + 4] = fb.Distance[i];
    pixels[6 * i + 5] = fb.Depth[i];
  }
  OIIO::ImageSpec spec(fb.width(), fb.height(), 6, OIIO::TypeDesc::FLOAT);
  spec.channelnames = { "R", "G", "B", "A", "Z", "depth.Z" };
  spec.alpha_channel = 3;
  spec.z_channel = 4;
  writeScanlines(path, spec, OIIO::TypeDesc::FLOAT, pixels.data(), 6 * sizeof(float) * fb.width());
}

std::vector<std::uint8_t> readImageRGBA8(const std::string& path, int& width, int& height)
{
  // Read the bytes as stored, without premultiplying by alpha, to invert writeImage exactly.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in)
    throw std::runtime_error("sightline: cannot read '" + path + "': " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  width = spec.width;
  height = spec.height;
  const int channels = spec.nchannels;
  std::vector<std::uint8_t> file(std::size_t(width) * height * channels);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, file.data()))
    throw std::runtime_error("sightline: reading '" + path + "' failed: " + in->geterror());
  std::vector<std::uint8_t> rgba(std::size_t(width) * height * 4, 255);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
    {
      const std::uint8_t* src = &file[(std::size_t(height - 1 - y) * width + x) * channels];
      std::uint8_t* dst = &rgba[(std::size_t(y) * width + x) * 4];
      if (channels < 3) // grey, optionally with alpha
      {
        dst[0] = dst[1] = dst[2] = src[0];
        if (channels == 2)
          dst[3] = src[1];
      }
      else
      {
        for (int c = 0; c < std::min(channels, 4); ++c)
          dst[c] = src[c];
      }
    }
  return rgba;
}
} // namespace sightline
