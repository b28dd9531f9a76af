// SPDX-License-Identifier: BSD-3-Clause
// vtkSightlineSphereMapper in a render window: exact silhouettes and depth, scalar colouring
// against a baseline image, camera changes, resizing, viewports, subsampling and progress.
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkFloatArray.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSightlineSphereMapper.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace sightline_test;

namespace
{
const double Black[3] = { 0, 0, 0 };

struct Scene
{
  vtkNew<vtkSightlineSphereMapper> mapper;
  vtkNew<vtkActor> actor;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;

  Scene(vtkPolyData* spheres, int width, int height)
  {
    mapper->SetInputDataObject(spheres);
    mapper->SetRadiusArrayName("radius");
    actor->SetMapper(mapper);
    renderer->AddActor(actor);
    renderer->SetBackground(Black[0], Black[1], Black[2]);
    window->AddRenderer(renderer);
    window->SetSize(width, height);
    window->SetOffScreenRendering(1);
    window->SetMultiSamples(0);
  }
};

vtkSmartPointer<vtkPolyData> SampleSpheres()
{
  return MakeSpheres({ { 0, 0, 0 }, { 1.6, 0.4, -0.5 }, { -1.4, -0.8, 0.3 }, { 0.2, 1.5, -1 },
                       { -0.9, 1.1, 0.8 }, { 1.1, -1.3, 0.6 }, { 0, -0.2, 1.4 } },
    { 1.0, 0.6, 0.7, 0.5, 0.45, 0.55, 0.3 });
}
} // namespace

TEST(SphereMapper, ScalarColouredSpheresMatchBaseline)
{
  auto spheres = SampleSpheres();
  Scene scene(spheres, 300, 300);
  scene.mapper->SetScalarModeToUsePointFieldData();
  scene.mapper->SelectColorArray("value");
  scene.mapper->SetScalarRange(0, 6);
  scene.mapper->ScalarVisibilityOn();
  scene.actor->GetProperty()->SetSpecular(0.4);
  scene.actor->GetProperty()->SetSpecularPower(30);
  scene.actor->GetProperty()->SetAmbient(0.1);
  scene.renderer->SetBackground(0.1, 0.1, 0.15);
  scene.renderer->ResetCamera();
  scene.renderer->GetActiveCamera()->Elevation(20);
  scene.renderer->GetActiveCamera()->Azimuth(30);
  scene.renderer->ResetCameraClippingRange();
  scene.window->Render();
  // Tolerance: vtkTesting's thresholded image difference; 0.5 admits no visible change.
  EXPECT_TRUE(MatchesBaseline(CaptureRGB(scene.window), "SphereMapper", 0.5));
}

TEST(SphereMapper, SilhouetteCoversTheAnalyticDisc)
{
  // A unit sphere under a parallel camera covers pi r^2 of the image; only pixels on the
  // boundary may differ, so the count must be within the perimeter's pixel count.
  auto spheres = MakeSpheres({ { 0, 0, 0 } }, { 1.0 });
  const int size = 201;
  Scene scene(spheres, size, size);
  scene.renderer->SetActiveCamera(MakeCamera(true, 10.0, 2.0));
  scene.window->Render();
  const double pixel = 4.0 / size;
  const double discPixels = M_PI / (pixel * pixel);
  const double perimeterPixels = 2.0 * M_PI / pixel;
  EXPECT_NEAR(CoveredPixels(CaptureRGB(scene.window)), discPixels, 0.25 * perimeterPixels);
}

TEST(SphereMapper, DepthBufferHoldsTheExactDepth)
{
  for (const bool parallel : { true, false })
  {
    auto spheres = MakeSpheres({ { 0, 0, 0 } }, { 1.0 });
    const int size = 201; // odd: the centre pixel looks exactly at the sphere's front point
    Scene scene(spheres, size, size);
    vtkSmartPointer<vtkCamera> camera = MakeCamera(parallel, 10.0, 2.0);
    scene.renderer->SetActiveCamera(camera);
    scene.window->Render();
    auto depth = CaptureDepth(scene.window);
    const float measured = depth->GetPointData()->GetScalars()->GetComponent(
      vtkIdType(size / 2) * size + size / 2, 0);

    // Expected: the front point (0, 0, 1) through VTK's projection.
    vtkMatrix4x4* m = camera->GetCompositeProjectionTransformMatrix(1.0, -1, 1);
    double front[4] = { 0, 0, 1, 1 }, clip[4];
    m->MultiplyPoint(front, clip);
    const double expected = 0.5 * clip[2] / clip[3] + 0.5;
    EXPECT_NEAR(measured, expected, 1e-6) << (parallel ? "parallel" : "perspective");
    // Background keeps the cleared depth.
    EXPECT_EQ(depth->GetPointData()->GetScalars()->GetComponent(0, 0), 1.0);
  }
}

TEST(SphereMapper, FollowsCameraResizeAndViewports)
{
  auto spheres = SampleSpheres();
  Scene scene(spheres, 240, 180);
  scene.renderer->ResetCamera();
  scene.window->Render();
  std::vector<vtkActor*> actors{ scene.actor };
  vtkCamera* camera = scene.renderer->GetActiveCamera();
  EXPECT_LE(MaxRGBDifference(CaptureRGB(scene.window), RenderWithoutGL(actors, camera, 240, 180, Black)), 1);

  // An interactive camera change re-traces.
  camera->Azimuth(40);
  camera->Roll(15);
  scene.renderer->ResetCameraClippingRange();
  scene.window->Render();
  EXPECT_LE(MaxRGBDifference(CaptureRGB(scene.window), RenderWithoutGL(actors, camera, 240, 180, Black)), 1);

  // A resize re-traces at the new size and aspect.
  scene.window->SetSize(160, 220);
  scene.window->Render();
  EXPECT_LE(MaxRGBDifference(CaptureRGB(scene.window), RenderWithoutGL(actors, camera, 160, 220, Black)), 1);

  // Two viewports with their own cameras: each half matches its own GL-free image.
  vtkNew<vtkRenderer> right;
  vtkNew<vtkActor> rightActor;
  rightActor->SetMapper(scene.mapper);
  rightActor->GetProperty()->SetColor(0.2, 0.8, 0.3);
  right->AddActor(rightActor);
  right->SetViewport(0.5, 0, 1, 1);
  scene.renderer->SetViewport(0, 0, 0.5, 1);
  scene.window->AddRenderer(right);
  scene.window->SetSize(320, 200);
  right->ResetCamera();
  right->GetActiveCamera()->Elevation(60);
  right->ResetCameraClippingRange();
  scene.window->Render();
  auto both = CaptureRGB(scene.window);
  auto left = RenderWithoutGL(actors, camera, 160, 200, Black);
  std::vector<vtkActor*> rightActors{ rightActor };
  auto rightImage = RenderWithoutGL(rightActors, right->GetActiveCamera(), 160, 200, Black);
  int worst = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 320; ++x)
    {
      const auto window = Pixel(both, x, y);
      const auto expected = x < 160 ? Pixel(left, x, y) : Pixel(rightImage, x - 160, y);
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(window[c] - expected[c]));
    }
  EXPECT_LE(worst, 1);
}

TEST(SphereMapper, SubsamplesWhileInteractingThenRefines)
{
  auto spheres = SampleSpheres();
  Scene scene(spheres, 200, 200);
  scene.renderer->ResetCamera();
  std::vector<vtkActor*> actors{ scene.actor };
  auto full = RenderWithoutGL(actors, scene.renderer->GetActiveCamera(), 200, 200, Black);

  scene.window->SetDesiredUpdateRate(15.0); // what the interactor asks while dragging
  scene.mapper->SetInteractiveSubsampling(4);
  scene.window->Render();
  int differing = 0;
  MaxRGBDifference(CaptureRGB(scene.window), full, &differing);
  EXPECT_GT(differing, 0) << "an interactive frame is traced at a quarter resolution";

  scene.window->SetDesiredUpdateRate(0.0001); // still again
  scene.window->Render();
  EXPECT_LE(MaxRGBDifference(CaptureRGB(scene.window), full), 1);
}

TEST(SphereMapper, ReportsProgress)
{
  auto spheres = SampleSpheres();
  Scene scene(spheres, 256, 256);
  scene.renderer->ResetCamera();
  std::vector<double> fractions;
  vtkNew<vtkCallbackCommand> progress;
  progress->SetClientData(&fractions);
  progress->SetCallback([](vtkObject*, unsigned long, void* client, void* data)
    { static_cast<std::vector<double>*>(client)->push_back(*static_cast<double*>(data)); });
  scene.mapper->AddObserver(vtkCommand::ProgressEvent, progress);
  scene.window->Render();
  ASSERT_GE(fractions.size(), 2u);
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  for (std::size_t i = 1; i < fractions.size(); ++i)
    EXPECT_GE(fractions[i], fractions[i - 1]);

  // An unchanged view reuses the cached frame: no new tracing, no progress.
  fractions.clear();
  scene.window->Render();
  EXPECT_TRUE(fractions.empty());
}
