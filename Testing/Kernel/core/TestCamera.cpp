// SPDX-License-Identifier: BSD-3-Clause
// Camera: the matrix must be vtkCamera's (checked against gluLookAt + glFrustum/glOrtho written
// out here), and rays, depths and unprojection must all agree with that matrix.
#include "KernelTestSupport.h"

#include "sightline/core/Camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <random>
#include <stdexcept>

namespace
{
using namespace sightline_test;
using sightline::Camera;
using sightline::CameraParameters;

struct CameraCase
{
  std::string name;
  CameraParameters parameters;
  int width;
  int height;
};

CameraParameters perspective(dvec3 position, dvec3 focalPoint, dvec3 viewUp, double viewAngle,
                             double nearClip, double farClip)
{
  CameraParameters p;
  p.position = position;
  p.focalPoint = focalPoint;
  p.viewUp = viewUp;
  p.viewAngle = viewAngle;
  p.nearClip = nearClip;
  p.farClip = farClip;
  return p;
}

CameraParameters parallel(dvec3 position, dvec3 focalPoint, dvec3 viewUp, double parallelScale,
                          double nearClip, double farClip)
{
  CameraParameters p = perspective(position, focalPoint, viewUp, 30.0, nearClip, farClip);
  p.parallelProjection = true;
  p.parallelScale = parallelScale;
  return p;
}

std::vector<CameraCase> cameraCases()
{
  return {
    { "VtkDefault", CameraParameters{}, 300, 300 },
    // View-up neither unit length nor orthogonal to the view direction; wide image.
    { "PerspectiveOffAxisUp",
      perspective({ 3, -2, 5 }, { 0.5, 0.2, -0.3 }, { 0.3, 1, 0.2 }, 30, 0.01, 1000.01), 640, 360 },
    // Tall image, wide angle, camera far from the origin.
    { "PerspectiveTall", perspective({ -40, 25, 10 }, { 1, 2, 3 }, { 0, 0, 1 }, 60, 0.5, 200), 101,
      257 },
    // far / near = 1e6 with a narrow angle.
    { "PerspectiveDeepRange",
      perspective({ 0.2, 0.1, 2 }, { 0, 0, 0 }, { 1, 0.2, 0 }, 10, 1e-3, 1e3), 300, 200 },
    { "ParallelOffAxisUp", parallel({ 2, 3, 4 }, { 0, 0, 0 }, { -1, 1, 0.5 }, 2.5, 0.1, 1e4), 333,
      111 },
    // Camera far from the origin, far / near = 1e5.
    { "ParallelFarFromOrigin",
      parallel({ 1000, 1200, 900 }, { 1001, 1198, 903 }, { 0, 1, 1 }, 0.5, 0.01, 1e3), 64, 200 },
  };
}

dvec3 viewDirection(const CameraParameters& p)
{
  return glm::normalize(p.focalPoint - p.position);
}

/// Pixel coordinates to probe: the image corners, the centre and random interior points.
std::vector<std::pair<double, double>> probePixels(int width, int height)
{
  std::vector<std::pair<double, double>> pixels{
    { 0, 0 }, { width, 0 }, { 0, height }, { width, height }, { 0.5 * width, 0.5 * height }
  };
  std::mt19937 random(20240601);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 20; ++i)
    pixels.emplace_back(u(random) * width, u(random) * height);
  return pixels;
}

/// One camera case: the kernel's camera and the reference matrix it must agree with.
struct CameraSetup
{
  explicit CameraSetup(const CameraCase& c)
    : parameters(c.parameters)
    , width(c.width)
    , height(c.height)
    , aspect(double(c.width) / c.height)
    , reference(referenceWorldToClip(c.parameters, aspect))
    , camera(Camera::fromParameters(c.parameters, c.width, c.height))
  {
  }

  WindowPoint project(const dvec3& point) const
  {
    return referenceProject(reference, point, width, height);
  }
  dvec3 unproject(long double px, long double py, long double depth) const
  {
    return referenceUnproject(reference, px, py, depth, width, height);
  }

  CameraParameters parameters;
  int width;
  int height;
  double aspect;
  Matrix4 reference;
  Camera camera;
};

/// Runs a check for every camera case in one test, SCOPED_TRACE naming the case. (One test per
/// case would be one process per case, and each costs a quarter second of library loading.)
template <class Check>
void forEachCameraCase(Check check)
{
  for (const CameraCase& cameraCase : cameraCases())
  {
    SCOPED_TRACE(cameraCase.name);
    check(CameraSetup(cameraCase));
  }
}

// Row by row, because the rows of a projection differ in scale by orders of magnitude.
void expectMatrixNear(const sightline::dmat4& actual, const Matrix4& expected, double relative)
{
  for (int row = 0; row < 4; ++row)
  {
    long double rowScale = 0;
    for (int column = 0; column < 4; ++column)
      rowScale = std::max(rowScale, std::fabs(expected[row][column]));
    for (int column = 0; column < 4; ++column)
      EXPECT_NEAR(actual[column][row], double(expected[row][column]), relative * double(rowScale))
        << "row " << row << ", column " << column;
  }
}

TEST(Camera, WorldToClipMatchesGluLookAtAndGlFrustumOrOrtho)
{
  forEachCameraCase(
    [](const CameraSetup& setup)
    {
      expectMatrixNear(Camera::worldToClipMatrix(setup.parameters, setup.aspect), setup.reference,
                       1e-12);
      EXPECT_EQ(setup.camera.width(), setup.width);
      EXPECT_EQ(setup.camera.height(), setup.height);
      expectMatrixNear(setup.camera.worldToClip(), setup.reference, 1e-12);
    });
}

// Unprojection is all double: it must invert the reference projection to 1e-6 pixels.
TEST(Camera, UnprojectInvertsTheReferenceProjection)
{
  forEachCameraCase(
    [](const CameraSetup& setup)
    {
      for (const auto& [px, py] : probePixels(setup.width, setup.height))
        for (double depth : { 0.0, 0.25, 0.5, 0.999, 1.0 })
        {
          const WindowPoint back = setup.project(setup.camera.unproject(px, py, depth));
          EXPECT_NEAR(double(back.x), px, 1e-6) << "depth " << depth;
          EXPECT_NEAR(double(back.y), py, 1e-6) << "depth " << depth;
          EXPECT_NEAR(double(back.depth), depth, 1e-9);
        }
    });
}

// The ray is float, so 1e-6 pixels is out of reach near the near plane: rounding the origin, the
// direction and tfar to float moves o + t d by at most u (|o| + (1 + sqrt 3) t) to first order
// (u = FLT_EPSILON / 2), which 2 FLT_EPSILON (|o| + t) bounds. That world error is converted to
// pixels and window depth with the reference projection's local scale; a convention error
// (half-pixel shift, flipped axis, wrong plane) is far larger.
TEST(Camera, PrimaryRayRunsThroughItsPixelFromNearToFarPlane)
{
  forEachCameraCase(
    [](const CameraSetup& setup)
    {
      const dvec3 forward = viewDirection(setup.parameters);
      for (const auto& [px, py] : probePixels(setup.width, setup.height))
      {
        const sightline::Ray ray = setup.camera.primaryRay(px, py);
        EXPECT_EQ(ray.tnear, 0.0f);
        EXPECT_NEAR(glm::length(dvec3(ray.direction)), 1.0, 1e-6);
        for (double fraction : { 0.0, 1e-3, 0.3, 1.0 })
        {
          SCOPED_TRACE("pixel (" + std::to_string(px) + ", " + std::to_string(py) + "), fraction " +
                       std::to_string(fraction));
          const double t = fraction * ray.tfar;
          const dvec3 point = dvec3(ray.origin) + t * dvec3(ray.direction);
          const double worldError = 2 * FLT_EPSILON * (glm::length(dvec3(ray.origin)) + t);

          const WindowPoint window = setup.project(point);
          const dvec3 here = setup.unproject(px, py, window.depth);
          const double pixelSize =
            std::min(glm::length(setup.unproject(px + 1, py, window.depth) - here),
                     glm::length(setup.unproject(px, py + 1, window.depth) - here));
          const double pixelTolerance = 1e-6 + worldError / pixelSize;
          EXPECT_NEAR(double(window.x), px, pixelTolerance);
          EXPECT_NEAR(double(window.y), py, pixelTolerance);

          // Window depth changes fastest along the view direction.
          const long double depthChange = setup.project(point + worldError * forward).depth -
            setup.project(point - worldError * forward).depth;
          const double depthTolerance = 1e-12 + 0.5 * double(std::fabs(depthChange));
          if (fraction == 0.0)
          {
            EXPECT_NEAR(double(window.depth), 0.0, depthTolerance)
              << "must start on the near plane";
          }
          if (fraction == 1.0)
          {
            EXPECT_NEAR(double(window.depth), 1.0, depthTolerance) << "must end on the far plane";
          }
        }
      }
    });
}

// A point computed in double on the pixel's exact ray goes to a window depth and back.
TEST(Camera, WindowDepthAndUnprojectRoundTrip)
{
  forEachCameraCase(
    [](const CameraSetup& setup)
    {
      for (const auto& [px, py] : probePixels(setup.width, setup.height))
      {
        const dvec3 nearPoint = setup.unproject(px, py, 0);
        const dvec3 farPoint = setup.unproject(px, py, 1);
        for (double fraction : { 0.0, 1e-4, 0.01, 0.5, 0.9, 1.0 })
        {
          const dvec3 point = nearPoint + fraction * (farPoint - nearPoint);
          const double depth = setup.camera.windowDepth(point);
          EXPECT_NEAR(depth, double(setup.project(point).depth), 1e-12);
          const dvec3 back = setup.camera.unproject(px, py, depth);
          EXPECT_LT(glm::length(back - point), 1e-9 * glm::length(point))
            << "pixel (" << px << ", " << py << "), fraction " << fraction;
        }
      }
    });
}

TEST(Camera, RejectsImageSizesThatAreNotPositive)
{
  const CameraParameters parameters;
  const sightline::dmat4 worldToClip = Camera::worldToClipMatrix(parameters, 1.0);
  for (const auto& [width, height] :
       std::vector<std::pair<int, int>>{ { 0, 10 }, { 10, 0 }, { -5, 10 }, { 10, -1 }, { 0, 0 } })
  {
    EXPECT_THROW(Camera(worldToClip, width, height), std::invalid_argument)
      << width << "x" << height;
    EXPECT_THROW(Camera::fromParameters(parameters, width, height), std::invalid_argument)
      << width << "x" << height;
  }
  EXPECT_NO_THROW(Camera(worldToClip, 1, 1));
}

TEST(Camera, RejectsASingularMatrix)
{
  EXPECT_THROW(Camera(sightline::dmat4(0.0), 8, 8), std::invalid_argument);
}
} // namespace
