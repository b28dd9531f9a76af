// SPDX-License-Identifier: BSD-3-Clause
// Ray-traced spheres composite with ordinary VTK geometry through the depth buffer.
// Two unit spheres centred at x = 0 and x = 0.8 intersect in the plane x = 0.4; seen along -z
// with a parallel camera, the nearer surface changes exactly at x = 0.4 on every row, whichever
// of the two spheres is ray-traced and whichever is rasterised by vtkPolyDataMapper.
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkNew.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSightlineSphereMapper.h"
#include "vtkSphereSource.h"

#include <gtest/gtest.h>

using namespace sightline_test;

namespace
{
const int Size = 301;
const double Scale = 2.0; // parallel scale: the image spans [-2, 2] in x and y

struct TwoSpheres
{
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkSightlineSphereMapper> traced;
  vtkNew<vtkPolyDataMapper> rasterised;
  vtkNew<vtkSphereSource> source;
  vtkNew<vtkActor> tracedActor;
  vtkNew<vtkActor> rasterisedActor;

  // tracedX and rasterisedX: the two spheres' centres on the x axis.
  TwoSpheres(double tracedX, double rasterisedX)
  {
    traced->SetInputDataObject(MakeSpheres({ { tracedX, 0, 0 } }, {}));
    traced->SetRadius(1.0);
    tracedActor->SetMapper(traced);
    tracedActor->GetProperty()->SetColor(1.0, 0.5, 0.0);
    source->SetCenter(rasterisedX, 0, 0);
    source->SetRadius(1.0);
    source->SetThetaResolution(256);
    source->SetPhiResolution(256);
    rasterised->SetInputConnection(source->GetOutputPort());
    rasterisedActor->SetMapper(rasterised);
    rasterisedActor->GetProperty()->SetColor(0.0, 0.4, 1.0);
    renderer->AddActor(tracedActor);
    renderer->AddActor(rasterisedActor);
    renderer->SetActiveCamera(MakeCamera(true, 10.0, Scale));
    window->AddRenderer(renderer);
    window->SetSize(Size, Size);
    window->SetOffScreenRendering(1);
    window->SetMultiSamples(0);
    window->Render();
  }
};

bool IsOrange(const std::array<int, 3>& p) { return p[0] > p[2]; }

double WorldX(int column) { return (column + 0.5) / Size * 2 * Scale - Scale; }

/// Along row y, checks that pixels left of x = 0.4 show the sphere at x = 0 and pixels to
/// the right the one at x = 0.8; returns the world x where the colour changes.
double Boundary(vtkImageData* image, int row, bool leftIsOrange)
{
  int firstRight = -1;
  for (int x = 0; x < Size; ++x)
  {
    const auto p = Pixel(image, x, row);
    if (p[0] + p[1] + p[2] == 0)
      continue; // background
    if (IsOrange(p) != leftIsOrange && firstRight < 0)
      firstRight = x;
    if (firstRight >= 0)
    {
      EXPECT_NE(IsOrange(p), leftIsOrange) << "row " << row << " column " << x;
    }
  }
  return firstRight < 0 ? 1e9 : WorldX(firstRight);
}
} // namespace

TEST(Compositing, IntersectionCurveWithRayTracedSphereOnEitherSide)
{
  const double pixel = 2 * Scale / Size;
  for (const bool tracedOnLeft : { true, false })
  {
    TwoSpheres scene(tracedOnLeft ? 0.0 : 0.8, tracedOnLeft ? 0.8 : 0.0);
    auto image = CaptureRGB(scene.window);
    // Rows through the lens-shaped overlap (|y| < 0.9 keeps clear of the silhouettes' tips).
    for (const double y : { 0.0, 0.5, -0.8 })
    {
      const int row = int((y + Scale) / (2 * Scale) * Size);
      const double boundary = Boundary(image, row, tracedOnLeft);
      EXPECT_NEAR(boundary, 0.4, 1.5 * pixel) << "row at y = " << y << (tracedOnLeft ? ", traced sphere on the left" : ", traced sphere on the right");
    }
  }
}

TEST(Compositing, PerspectiveViewMatchesBaseline)
{
  TwoSpheres scene(0.0, 0.8);
  vtkCamera* camera = scene.renderer->GetActiveCamera();
  camera->SetParallelProjection(false);
  camera->Azimuth(35);
  camera->Elevation(25);
  scene.renderer->ResetCamera();
  scene.window->Render();
  EXPECT_TRUE(MatchesBaseline(CaptureRGB(scene.window), "Compositing", 0.5));
}
