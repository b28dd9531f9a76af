// SPDX-License-Identifier: BSD-3-Clause
// Bad input is reported by name and never crashes; the valid part still renders.
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSightlineImageRenderer.h"
#include "vtkSightlineSphereMapper.h"
#include "vtkSightlineSphericalVolumeMapper.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

using namespace sightline_test;

namespace
{
const double NaN = std::numeric_limits<double>::quiet_NaN();

struct Probe
{
  vtkNew<vtkSightlineSphereMapper> mapper;
  vtkNew<vtkActor> actor;
  vtkNew<MessageCollector> messages;

  explicit Probe(vtkPolyData* input)
  {
    mapper->SetInputDataObject(input);
    mapper->SetRadiusArrayName("radius");
    actor->SetMapper(mapper);
    messages->Observe(mapper);
  }

  /// Renders in a window and returns the number of non-background pixels.
  int RenderedPixels()
  {
    vtkNew<vtkRenderer> renderer;
    renderer->AddActor(actor);
    renderer->SetActiveCamera(MakeCamera(true, 10.0, 3.0));
    vtkNew<vtkRenderWindow> window;
    window->AddRenderer(renderer);
    window->SetSize(120, 120);
    window->SetOffScreenRendering(1);
    window->Render();
    auto image = CaptureRGB(window);
    int covered = 0;
    for (int y = 0; y < 120; ++y)
      for (int x = 0; x < 120; ++x)
      {
        const auto p = Pixel(image, x, y);
        covered += p[0] + p[1] + p[2] > 0;
      }
    return covered;
  }
};
} // namespace

// Empty input is not bad input: ParaView hands mappers empty datasets before data arrives
// and for empty blocks. Nothing is drawn and nothing said (see TestMapperInput for every
// mapper and kind of emptiness).
TEST(BadInput, EmptyInputRendersNothingQuietly)
{
  vtkNew<vtkPolyData> empty;
  Probe probe(empty);
  EXPECT_EQ(probe.RenderedPixels(), 0);
  EXPECT_TRUE(probe.messages->Errors.empty());
  EXPECT_TRUE(probe.messages->Warnings.empty());
}

TEST(BadInput, NaNPositionIsSkippedByName)
{
  auto spheres = MakeSpheres({ { -1, 0, 0 }, { NaN, 0, 0 }, { 1, 0, 0 } }, { 0.5, 0.5, 0.5 });
  Probe probe(spheres);
  const int covered = probe.RenderedPixels();
  EXPECT_TRUE(probe.messages->Contains("NaN or infinite centre"));
  EXPECT_TRUE(probe.messages->Contains("point 1"));
  EXPECT_EQ(probe.mapper->GetNumberOfPrimitives(), 2);
  EXPECT_GT(covered, 0) << "the valid spheres still render";
}

TEST(BadInput, NonPositiveAndNaNRadiiAreSkippedByName)
{
  auto spheres = MakeSpheres({ { -1, 0, 0 }, { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } },
    { 0.5, -0.2, 0.0, NaN });
  Probe probe(spheres);
  EXPECT_GT(probe.RenderedPixels(), 0);
  EXPECT_TRUE(probe.messages->Contains("3 sphere(s) with a radius that is not positive"));
  EXPECT_TRUE(probe.messages->Contains("point 1"));
  EXPECT_EQ(probe.mapper->GetNumberOfPrimitives(), 1);
}

TEST(BadInput, MissingRadiusArrayIsAnErrorAndFallsBackToRadius)
{
  auto spheres = MakeSpheres({ { 0, 0, 0 } }, {});
  Probe probe(spheres);
  probe.mapper->SetRadiusArrayName("thickness");
  probe.mapper->SetRadius(0.75);
  EXPECT_GT(probe.RenderedPixels(), 0);
  ASSERT_FALSE(probe.messages->Errors.empty());
  EXPECT_TRUE(probe.messages->Contains("'thickness' is not in the input's point data"));
}

TEST(BadInput, RadiusArrayOfWrongShapeIsAnError)
{
  auto spheres = MakeSpheres({ { 0, 0, 0 }, { 1, 0, 0 } }, {});
  vtkNew<vtkDoubleArray> vectors;
  vectors->SetName("radius");
  vectors->SetNumberOfComponents(3);
  vectors->InsertNextTuple3(1, 1, 1);
  vectors->InsertNextTuple3(1, 1, 1);
  spheres->GetPointData()->AddArray(vectors);
  Probe probe(spheres);
  EXPECT_GT(probe.RenderedPixels(), 0);
  EXPECT_TRUE(probe.messages->Contains("has 3 components"));

  auto shortArray = MakeSpheres({ { 0, 0, 0 }, { 1, 0, 0 } }, {});
  vtkNew<vtkDoubleArray> radius;
  radius->SetName("radius");
  radius->InsertNextValue(0.5);
  shortArray->GetPointData()->AddArray(radius);
  Probe probeShort(shortArray);
  EXPECT_GT(probeShort.RenderedPixels(), 0);
  EXPECT_TRUE(probeShort.messages->Contains("has 1 values for 2 points"));
}

TEST(BadInput, InvalidConstantRadiusIsAnError)
{
  auto spheres = MakeSpheres({ { 0, 0, 0 } }, {});
  Probe probe(spheres);
  probe.mapper->SetRadiusArrayName(nullptr);
  probe.mapper->SetRadius(-1.0);
  EXPECT_EQ(probe.RenderedPixels(), 0);
  EXPECT_TRUE(probe.messages->Contains("Radius must be positive and finite"));
}

// No input connection yet, as a mapper has before a pipeline is connected: quietly nothing.
TEST(BadInput, MissingInputRendersNothingQuietly)
{
  vtkNew<vtkSightlineSphereMapper> mapper;
  vtkNew<MessageCollector> messages;
  messages->Observe(mapper);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  vtkNew<vtkRenderWindow> window;
  window->AddRenderer(renderer);
  window->SetOffScreenRendering(1);
  window->SetSize(64, 64);
  window->Render();
  EXPECT_TRUE(messages->Errors.empty());
  EXPECT_TRUE(messages->Warnings.empty());
}

TEST(BadInput, ZeroSizeViewportAndImageAreReported)
{
  auto spheres = MakeSpheres({ { 0, 0, 0 } }, { 1.0 });
  Probe probe(spheres);
  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(probe.actor);
  renderer->SetViewport(0.5, 0.5, 0.5, 0.5); // no area
  vtkNew<vtkRenderWindow> window;
  window->AddRenderer(renderer);
  window->SetOffScreenRendering(1);
  window->SetSize(64, 64);
  window->Render();
  EXPECT_TRUE(probe.messages->Contains("viewport has no pixels"));

  vtkNew<vtkSightlineImageRenderer> image;
  vtkNew<MessageCollector> imageMessages;
  imageMessages->Observe(image);
  image->AddActor(probe.actor);
  image->SetActiveCamera(MakeCamera(false));
  image->SetSize(0, 10);
  image->Update();
  EXPECT_TRUE(imageMessages->Contains("image size must be positive"));

  vtkNew<vtkSightlineImageRenderer> noCamera;
  vtkNew<MessageCollector> noCameraMessages;
  noCameraMessages->Observe(noCamera);
  noCamera->AddActor(probe.actor);
  noCamera->Update();
  EXPECT_TRUE(noCameraMessages->Contains("No camera"));
}

// Both kinds of mapper share one implementation of the interactive settings: out-of-range
// steps are clamped, an unchanged value does not modify the mapper, PrintSelf shows them.
template <typename Mapper>
void ExpectInteractiveSettings()
{
  vtkNew<Mapper> mapper;
  EXPECT_EQ(mapper->GetInteractiveSubsampling(), 2);
  EXPECT_EQ(mapper->GetInteractiveUpdateRate(), 1.0);
  mapper->SetInteractiveSubsampling(0);
  EXPECT_EQ(mapper->GetInteractiveSubsampling(), 1);
  mapper->SetInteractiveSubsampling(40);
  EXPECT_EQ(mapper->GetInteractiveSubsampling(), 16);
  const vtkMTimeType time = mapper->GetMTime();
  mapper->SetInteractiveSubsampling(16);
  mapper->SetInteractiveUpdateRate(1.0);
  EXPECT_EQ(mapper->GetMTime(), time);
  mapper->SetInteractiveUpdateRate(5.0);
  EXPECT_GT(mapper->GetMTime(), time);
  std::ostringstream printed;
  mapper->Print(printed);
  EXPECT_NE(printed.str().find("InteractiveSubsampling: 16"), std::string::npos);
  EXPECT_NE(printed.str().find("InteractiveUpdateRate: 5"), std::string::npos);
}

TEST(BadInput, InteractiveSettingsAreClampedAndPrintedByBothMapperKinds)
{
  ExpectInteractiveSettings<vtkSightlineSphereMapper>();
  ExpectInteractiveSettings<vtkSightlineSphericalVolumeMapper>();
}

// A huge image size is an error before anything is allocated (it used to abort with an
// uncaught std::bad_alloc in Framebuffer::resize), and the renderer still works afterwards.
TEST(BadInput, HugeImageSizeIsRefusedByTheImageRenderer)
{
  auto spheres = MakeSpheres({ { 0, 0, 0 } }, { 0.5 });
  Probe probe(spheres);
  vtkNew<vtkSightlineImageRenderer> image;
  vtkNew<MessageCollector> messages;
  messages->Observe(image);
  image->AddActor(probe.actor);
  image->SetActiveCamera(MakeCamera(true, 10.0, 3.0));
  for (const int size : { 46341, 100000 })
  {
    image->SetSize(size, size);
    image->Update();
    EXPECT_TRUE(messages->Contains("pixels needs")) << size;
    EXPECT_TRUE(messages->Contains("beyond the renderer's budget of 8 GiB")) << size;
  }
  messages->Errors.clear();
  image->SetSize(40, 30);
  image->Update();
  EXPECT_TRUE(messages->Errors.empty());
  int dims[3];
  image->GetOutput()->GetDimensions(dims);
  EXPECT_EQ(dims[0], 40);
  EXPECT_EQ(dims[1], 30);
}
