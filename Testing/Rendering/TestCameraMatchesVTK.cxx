// SPDX-License-Identifier: BSD-3-Clause
// The kernel camera against vtkCamera: the same world-to-clip matrix, and primary rays that
// project back onto their pixel centres through VTK's own projection.
#include "SightlineKernelConversions.h" // private to the module: the conversion under test

#include "vtkCamera.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"

#include "sightline/core/Camera.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{
struct CameraSetup
{
  bool parallel;
  double viewAngle;
  double aspectWidth, aspectHeight; // image size
  double position[3], focal[3], up[3];
  double nearClip, farClip;
};

const CameraSetup CameraSetups[] = {
  { false, 30, 300, 300, { 0, 0, 1 }, { 0, 0, 0 }, { 0, 1, 0 }, 0.01, 1000.01 },
  { false, 10, 640, 480, { 3, -2, 5 }, { 0.5, 1, -1 }, { 0.2, 1, 0.1 }, 0.1, 100 },
  { false, 75, 201, 401, { -40, 10, 2 }, { 1, 2, 3 }, { 0, 0, 1 }, 1, 1e5 },
  { true, 30, 300, 200, { 3, -2, 5 }, { 0.5, 1, -1 }, { 0.2, 1, 0.1 }, 0.1, 100 },
  { true, 30, 123, 457, { 0, 0, -7 }, { 0, 0, 0 }, { 1, 0, 0 }, 2, 12 },
};

void Configure(vtkCamera* camera, const CameraSetup& s, double parallelScale = 2.5)
{
  camera->SetPosition(s.position);
  camera->SetFocalPoint(s.focal);
  camera->SetViewUp(s.up);
  camera->SetViewAngle(s.viewAngle);
  camera->SetParallelProjection(s.parallel);
  camera->SetParallelScale(parallelScale);
  camera->SetClippingRange(s.nearClip, s.farClip);
}

} // namespace

TEST(CameraMatchesVTK, WorldToClipEqualsCompositeProjection)
{
  for (const CameraSetup& s : CameraSetups)
  {
    vtkNew<vtkCamera> camera;
    Configure(camera, s);
    const double aspect = s.aspectWidth / s.aspectHeight;
    vtkMatrix4x4* vtkMatrix = camera->GetCompositeProjectionTransformMatrix(aspect, -1, 1);

    sightline::CameraParameters p;
    camera->GetPosition(&p.position.x);
    camera->GetFocalPoint(&p.focalPoint.x);
    camera->GetViewUp(&p.viewUp.x);
    p.viewAngle = s.viewAngle;
    p.parallelProjection = s.parallel;
    p.parallelScale = camera->GetParallelScale();
    p.nearClip = s.nearClip;
    p.farClip = s.farClip;
    const sightline::dmat4 ours = sightline::Camera::worldToClipMatrix(p, aspect);

    double largest = 0;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        largest = std::max(largest, std::abs(vtkMatrix->GetElement(r, c)));
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(ours[c][r], vtkMatrix->GetElement(r, c), 1e-12 * largest)
          << "element (" << r << ", " << c << "), parallel " << s.parallel;
  }
}

TEST(CameraMatchesVTK, RaysProjectOntoPixelCentres)
{
  for (const CameraSetup& s : CameraSetups)
  {
    vtkNew<vtkCamera> camera;
    Configure(camera, s);
    // VTK-only features the kernel must follow because it uses VTK's matrix as is.
    camera->SetWindowCenter(0.1, -0.2);
    camera->SetViewShear(0.05, 0.02, 1.0);
    const int width = int(s.aspectWidth), height = int(s.aspectHeight);
    vtkMatrix4x4* m = camera->GetCompositeProjectionTransformMatrix(double(width) / height, -1, 1);
    const sightline::Camera ours(SightlineKernelConversions::ToKernelMatrix(m), width, height);

    for (const double px : { 0.5, width / 3.0 + 0.5, width - 0.5 })
    {
      for (const double py : { 0.5, height / 2.0 + 0.5, height - 0.5 })
      {
        // The camera's geometry in double: points unprojected at several depths land on the
        // pixel centre through VTK's projection, at the depth they were unprojected from.
        for (const double depth : { 0.0, 0.3, 1.0 })
        {
          const sightline::dvec3 p = ours.unproject(px, py, depth);
          double world[4] = { p.x, p.y, p.z, 1.0 }, clip[4];
          m->MultiplyPoint(world, clip);
          EXPECT_NEAR((clip[0] / clip[3] + 1.0) * 0.5 * width, px, 1e-6);
          EXPECT_NEAR((clip[1] / clip[3] + 1.0) * 0.5 * height, py, 1e-6);
          EXPECT_NEAR(0.5 * clip[2] / clip[3] + 0.5, depth, 1e-9);
          EXPECT_NEAR(ours.windowDepth(p), depth, 1e-9);
        }
        // The float ray is that segment rounded to float: near plane to far plane.
        const sightline::Ray ray = ours.primaryRay(px, py);
        const sightline::dvec3 nearPoint = ours.unproject(px, py, 0.0);
        const sightline::dvec3 farPoint = ours.unproject(px, py, 1.0);
        const sightline::dvec3 direction = glm::normalize(farPoint - nearPoint);
        for (int axis = 0; axis < 3; ++axis)
        {
          EXPECT_NEAR(ray.origin[axis], nearPoint[axis], 1e-6 * (1.0 + glm::length(nearPoint)));
          EXPECT_NEAR(ray.direction[axis], direction[axis], 1e-6);
        }
        EXPECT_NEAR(ray.tfar, glm::length(farPoint - nearPoint), 1e-6 * ray.tfar);
      }
    }
  }
}
