// SPDX-License-Identifier: BSD-3-Clause
// The GL-free path (vtkSightlineImageRenderer) against the window path (vtkSightlineMapper in
// a vtkRenderWindow): the same pixels within one 8-bit level and the same depth within the
// depth buffer's resolution, for perspective and parallel cameras, several actors and actor
// transforms.
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSightlineSphereMapper.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace sightline_test;

TEST(ImageRendererMatchesWindow, ColourAndDepthAgree)
{
  auto cloud = MakeSpheres({ { 0, 0, 0 }, { 1.5, 0.2, -0.4 }, { -1.2, -0.6, 0.9 }, { 0.3, 1.4, 0.2 } },
    { 0.9, 0.5, 0.7, 0.4 });
  vtkNew<vtkSightlineSphereMapper> colouredMapper;
  colouredMapper->SetInputDataObject(cloud);
  colouredMapper->SetRadiusArrayName("radius");
  colouredMapper->SetScalarModeToUsePointFieldData();
  colouredMapper->SelectColorArray("value");
  colouredMapper->SetScalarRange(0, 3);
  vtkNew<vtkActor> coloured;
  coloured->SetMapper(colouredMapper);
  coloured->GetProperty()->SetAmbient(0.15);
  coloured->GetProperty()->SetSpecular(0.5);
  coloured->GetProperty()->SetSpecularPower(20);

  // A second actor with its own transform (rotation, non-uniform scale, translation).
  vtkNew<vtkSightlineSphereMapper> plainMapper;
  plainMapper->SetInputDataObject(MakeSpheres({ { 0, 0, 0 }, { 0.8, 0, 0 } }, { 0.5, 0.3 }));
  plainMapper->SetRadiusArrayName("radius");
  plainMapper->ScalarVisibilityOff();
  vtkNew<vtkActor> transformed;
  transformed->SetMapper(plainMapper);
  transformed->SetPosition(0.5, -1.2, 0.6);
  transformed->SetOrientation(10, 40, -20);
  transformed->SetScale(1.0, 1.6, 0.8);
  transformed->GetProperty()->SetColor(0.9, 0.9, 0.3);

  const double background[3] = { 0.2, 0.25, 0.3 };
  for (const bool parallel : { false, true })
  {
    vtkNew<vtkRenderer> renderer;
    renderer->AddActor(coloured);
    renderer->AddActor(transformed);
    renderer->SetBackground(background);
    vtkNew<vtkRenderWindow> window;
    window->AddRenderer(renderer);
    window->SetSize(320, 240);
    window->SetOffScreenRendering(1);
    window->SetMultiSamples(0);
    renderer->GetActiveCamera()->SetParallelProjection(parallel);
    renderer->ResetCamera();
    renderer->GetActiveCamera()->Azimuth(25);
    renderer->GetActiveCamera()->Elevation(-15);
    renderer->ResetCameraClippingRange();
    window->Render();

    auto windowImage = CaptureRGB(window);
    auto windowDepth = CaptureDepth(window);
    auto image = RenderWithoutGL({ coloured, transformed }, renderer->GetActiveCamera(), 320, 240, background);

    int differing = 0;
    EXPECT_LE(MaxRGBDifference(windowImage, image, &differing), 1) << (parallel ? "parallel" : "perspective");
    auto* depth = vtkFloatArray::SafeDownCast(image->GetPointData()->GetArray("Depth"));
    ASSERT_NE(depth, nullptr);
    double worst = 0;
    int hits = 0;
    for (vtkIdType i = 0; i < depth->GetNumberOfTuples(); ++i)
    {
      const double expected = depth->GetValue(i);
      const double measured = windowDepth->GetPointData()->GetScalars()->GetComponent(i, 0);
      worst = std::max(worst, std::abs(expected - measured));
      hits += expected < 1.0;
    }
    // A 24-bit depth buffer resolves 6e-8; allow a few steps.
    EXPECT_LE(worst, 1e-6) << (parallel ? "parallel" : "perspective");
    EXPECT_GT(hits, 320 * 240 / 10) << "the scene should cover a good part of the image";
  }
}
