// SPDX-License-Identifier: BSD-3-Clause
// Image output through OpenImageIO: PNG for looking at, OpenEXR for keeping depth.
#pragma once

#include "sightline/core/Framebuffer.h"

#include <string>

namespace sightline
{
/// Writes 8-bit RGBA (composited over `background`; alpha kept) with the top row first.
/// The format follows the extension (.png, .tif, .jpg, ...). Throws std::runtime_error on failure.
void writeImage(const std::string& path, const Framebuffer& framebuffer, const vec3& background);

/// Writes float R, G, B, A plus Z (distance along the primary ray; infinity on a miss) and
/// depth.Z (window depth) channels to an OpenEXR file. Throws std::runtime_error on failure.
void writeEXR(const std::string& path, const Framebuffer& framebuffer);

/// Reads an 8-bit RGB(A) image as RGBA8, bottom row first (the inverse of writeImage), for tests.
std::vector<std::uint8_t> readImageRGBA8(const std::string& path, int& width, int& height);
} // namespace sightline
