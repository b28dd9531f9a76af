// SPDX-License-Identifier: BSD-3-Clause
// ImagePlane: an image slice traced as OpenGL draws a textured quad. Checked against closed
// forms written out here: OpenGL's window depth of a plane facing a perspective camera, the
// texel a world point falls in, GL_LINEAR's weights, the quad's extent and the depth test.
#include "KernelTestSupport.h"

#include "sightline/images/ImagePlane.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace
{
using namespace sightline_test;
using sightline::Camera;
using sightline::CameraParameters;
using sightline::ImagePlane;
using sightline::dvec2;

// A 4 x 3 texture whose texel (i, j) is (40 i, 60 j, 7, 255).
std::vector<std::uint8_t> RampTexels(int width = 4, int height = 3)
{
  std::vector<std::uint8_t> texels;
  for (int j = 0; j < height; ++j)
  {
    for (int i = 0; i < width; ++i)
    {
      texels.insert(texels.end(),
        { std::uint8_t(40 * i), std::uint8_t(60 * j), std::uint8_t(7), std::uint8_t(255) });
    }
  }
  return texels;
}

CameraParameters LookingDownZ(double distance)
{
  CameraParameters parameters;
  parameters.position = dvec3(0.1, -0.05, distance);
  parameters.focalPoint = dvec3(0.1, -0.05, 0.0);
  parameters.viewAngle = 40.0;
  parameters.nearClip = 0.5;
  parameters.farClip = 20.0;
  return parameters;
}
} // namespace

TEST(ImagePlane, DepthIsOpenGLsForAPlaneFacingTheCamera)
{
  // The plane z = 0.3, texels of 0.5 x 0.5 with the texture's corner at (-1, -0.75).
  const ImagePlane plane(dvec3(-1.0, -0.75, 0.3), dvec3(0.5, 0, 0), dvec3(0, 0.5, 0), 4, 3,
    RampTexels(), dvec2(0.0), dvec2(4.0, 3.0));
  const double distance = 4.0;
  const CameraParameters parameters = LookingDownZ(distance);
  const Camera camera = Camera::fromParameters(parameters, 64, 48);
  sightline::Framebuffer frame;
  plane.render(camera, frame);
  // glFrustum: the eye-space depth -d maps to NDC (f + n) / (f - n) - 2 f n / ((f - n) d).
  const double n = parameters.nearClip, f = parameters.farClip, d = distance - 0.3;
  const double expected = 0.5 * ((f + n) / (f - n) - 2 * f * n / ((f - n) * d)) + 0.5;
  int seen = 0;
  for (std::size_t pixel = 0; pixel < frame.pixelCount(); ++pixel)
  {
    if (frame.Color[pixel].a > 0)
    {
      ++seen;
      EXPECT_NEAR(frame.Depth[pixel], expected, 1e-6);
    }
  }
  EXPECT_GT(seen, 300);
}

TEST(ImagePlane, NearestShowsTheTexelThePointFallsIn)
{
  const ImagePlane plane(dvec3(-1.0, -0.75, 0.0), dvec3(0.5, 0, 0), dvec3(0, 0.5, 0), 4, 3,
    RampTexels(), dvec2(0.0), dvec2(4.0, 3.0));
  const Camera camera = Camera::fromParameters(LookingDownZ(3.0), 80, 60);
  sightline::Framebuffer frame;
  plane.render(camera, frame);
  int checked = 0;
  for (int y = 0; y < camera.height(); ++y)
  {
    for (int x = 0; x < camera.width(); ++x)
    {
      // Where the pixel's ray meets z = 0, from the camera alone.
      const sightline::DoubleRay ray = camera.doublePrimaryRay(x + 0.5, y + 0.5);
      const dvec3 point = ray.origin + (-ray.origin.z / ray.direction.z) * ray.direction;
      const double s = (point.x + 1.0) / 0.5, t = (point.y + 0.75) / 0.5;
      const std::size_t pixel = frame.index(x, y);
      const bool inside = s > 1e-9 && s < 4 - 1e-9 && t > 1e-9 && t < 3 - 1e-9;
      const bool outside = s < -1e-9 || s > 4 + 1e-9 || t < -1e-9 || t > 3 + 1e-9;
      if (outside)
      {
        EXPECT_EQ(frame.Color[pixel].a, 0.0f) << x << "," << y;
        EXPECT_EQ(frame.Depth[pixel], 1.0f);
      }
      if (inside && std::abs(s - std::round(s)) > 1e-6 && std::abs(t - std::round(t)) > 1e-6)
      {
        EXPECT_NEAR(frame.Color[pixel].r * 255, 40 * std::floor(s), 1e-3);
        EXPECT_NEAR(frame.Color[pixel].g * 255, 60 * std::floor(t), 1e-3);
        EXPECT_EQ(frame.Color[pixel].a, 1.0f);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(ImagePlane, LinearWeighsTheFourNearestTexelCentres)
{
  ImagePlane plane(dvec3(0.0), dvec3(1, 0, 0), dvec3(0, 1, 0), 4, 3, RampTexels(), dvec2(0.0),
    dvec2(4.0, 3.0));
  plane.setFilter(ImagePlane::Filter::Linear);
  // At a texel centre, the texel; between centres, the linear blend; past the outer centres,
  // the edge texel (clamp to edge).
  EXPECT_NEAR(plane.sample(1.5, 2.5).r * 255, 40.0, 1e-4);
  EXPECT_NEAR(plane.sample(1.5, 2.5).g * 255, 120.0, 1e-4);
  EXPECT_NEAR(plane.sample(1.75, 1.0).r * 255, 40.0 + 0.25 * 40.0, 1e-4);
  EXPECT_NEAR(plane.sample(1.75, 1.0).g * 255, 0.5 * 0.0 + 0.5 * 60.0, 1e-4);
  EXPECT_NEAR(plane.sample(0.1, 0.2).r * 255, 0.0, 1e-4);
  EXPECT_NEAR(plane.sample(3.9, 2.9).r * 255, 120.0, 1e-4);
  EXPECT_NEAR(plane.sample(3.9, 2.9).g * 255, 120.0, 1e-4);
}

TEST(ImagePlane, OpacityAndBrightnessScaleTheTexels)
{
  ImagePlane plane(dvec3(0.0), dvec3(1, 0, 0), dvec3(0, 1, 0), 4, 3, RampTexels(), dvec2(0.5),
    dvec2(3.5, 2.5));
  EXPECT_TRUE(plane.opaque());
  plane.setBrightness(0.5f);
  plane.setOpacity(0.25f);
  EXPECT_FALSE(plane.opaque());
  const sightline::vec4 colour = plane.sample(2.5, 1.5);
  EXPECT_NEAR(colour.r * 255, 0.5 * 80, 1e-4);
  EXPECT_NEAR(colour.a, 0.25, 1e-6);
  std::vector<std::uint8_t> texels = RampTexels();
  texels[3] = 128;
  EXPECT_FALSE(ImagePlane(dvec3(0.0), dvec3(1, 0, 0), dvec3(0, 1, 0), 4, 3, texels, dvec2(0.0),
    dvec2(1.0)).opaque());
}

TEST(ImagePlane, ShearedStepsStillNameTheTextureCoordinates)
{
  // A prop matrix may shear the slice: steps (1, 0, 0) and (0.5, 1, 0.2).
  const ImagePlane plane(dvec3(2, 1, 0), dvec3(1, 0, 0), dvec3(0.5, 1, 0.2), 4, 3, RampTexels(),
    dvec2(0.0), dvec2(4.0, 3.0));
  const dvec3 point = dvec3(2, 1, 0) + 2.25 * dvec3(1, 0, 0) + 1.5 * dvec3(0.5, 1, 0.2);
  const dvec3 direction = glm::normalize(dvec3(0.1, -0.2, -1.0));
  const sightline::DoubleRay ray(point - 5.0 * direction, direction, 0.0, 100.0);
  double t;
  dvec2 texture;
  ASSERT_TRUE(plane.intersect(ray, t, texture));
  EXPECT_NEAR(t, 5.0, 1e-12);
  EXPECT_NEAR(texture.x, 2.25, 1e-12);
  EXPECT_NEAR(texture.y, 1.5, 1e-12);
  // The ray stops before the plane: no hit.
  const sightline::DoubleRay shortRay(point - 5.0 * direction, direction, 0.0, 4.9);
  EXPECT_FALSE(plane.intersect(shortRay, t, texture));
}

TEST(ImagePlane, DepthLimitHidesWhatIsBehind)
{
  const ImagePlane plane(dvec3(-1.0, -0.75, 0.0), dvec3(0.5, 0, 0), dvec3(0, 0.5, 0), 4, 3,
    RampTexels(), dvec2(0.0), dvec2(4.0, 3.0));
  const Camera camera = Camera::fromParameters(LookingDownZ(3.0), 32, 24);
  sightline::Framebuffer free, limited;
  plane.render(camera, free);
  // Something nearer than the plane on the left half, farther on the right half.
  std::vector<float> limit(free.pixelCount(), 1.0f);
  for (int y = 0; y < 24; ++y)
  {
    for (int x = 0; x < 32; ++x)
    {
      const std::size_t pixel = free.index(x, y);
      limit[pixel] = x < 16 ? free.Depth[pixel] - 1e-4f : std::min(1.0f, free.Depth[pixel] + 1e-4f);
    }
  }
  plane.render(camera, limited, &limit);
  for (int y = 0; y < 24; ++y)
  {
    for (int x = 0; x < 32; ++x)
    {
      const std::size_t pixel = free.index(x, y);
      if (free.Color[pixel].a == 0)
      {
        continue;
      }
      EXPECT_EQ(limited.Color[pixel].a, x < 16 ? 0.0f : 1.0f) << x << "," << y;
    }
  }
  const std::vector<float> wrongSize(3, 1.0f);
  EXPECT_THROW(plane.render(camera, limited, &wrongSize), std::invalid_argument);
}

TEST(ImagePlane, NamesBadConstruction)
{
  EXPECT_THROW(ImagePlane(dvec3(0.0), dvec3(1, 0, 0), dvec3(0, 1, 0), 0, 3, {}, dvec2(0.0),
                 dvec2(1.0)),
    std::invalid_argument);
  EXPECT_THROW(ImagePlane(dvec3(0.0), dvec3(1, 0, 0), dvec3(0, 1, 0), 4, 3, RampTexels(2, 2),
                 dvec2(0.0), dvec2(1.0)),
    std::invalid_argument);
  EXPECT_THROW(ImagePlane(dvec3(0.0), dvec3(1, 0, 0), dvec3(2, 0, 0), 4, 3, RampTexels(),
                 dvec2(0.0), dvec2(1.0)),
    std::invalid_argument);
  EXPECT_THROW(ImagePlane(dvec3(0.0), dvec3(1, 0, 0), dvec3(0, 1, 0), 4, 3, RampTexels(),
                 dvec2(1.0), dvec2(1.0)),
    std::invalid_argument);
}
