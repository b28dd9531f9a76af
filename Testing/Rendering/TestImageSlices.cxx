// SPDX-License-Identifier: BSD-3-Clause
// Image slices without OpenGL (vtkSightlineImageRenderer::AddImageSlice) against the same
// vtkImageSlice drawn by VTK's OpenGL mapper in a window, with Sightline spheres crossing the
// slice plane: window/level and lookup-table colours, nearest and linear interpolation,
// Border on and off, Cropping, an oblique prop matrix, a translucent slice, and the plane's
// depth where it cuts the spheres.
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkImageProperty.h"
#include "vtkImageSlice.h"
#include "vtkImageSliceMapper.h"
#include "vtkLookupTable.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSightlineImageRenderer.h"
#include "vtkSightlineSphereMapper.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>

using namespace sightline_test;

namespace
{
// 16 x 12 x 6 voxels of a value that changes from every voxel to the next (so a texel off by
// one shows), spacing (0.25, 0.2, 0.3), origin (-2, -1.1, -0.75).
vtkSmartPointer<vtkImageData> MakeVolume()
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(16, 12, 6);
  image->SetSpacing(0.25, 0.2, 0.3);
  image->SetOrigin(-2.0, -1.1, -0.75);
  vtkNew<vtkFloatArray> values;
  values->SetName("value");
  values->SetNumberOfTuples(16 * 12 * 6);
  for (int k = 0; k < 6; ++k)
  {
    for (int j = 0; j < 12; ++j)
    {
      for (int i = 0; i < 16; ++i)
      {
        values->SetValue((k * 12 + j) * 16 + i,
          float(100 + 40 * std::sin(0.9 * i) + 5.5 * j + 11 * k + 17 * ((i + j) % 2)));
      }
    }
  }
  image->GetPointData()->SetScalars(values);
  return image;
}

struct Comparison
{
  int pixels = 0;
  int within2 = 0;    // colour within 2 of 255 in every channel
  int planeDepth = 0; // pixels where both show the slice plane nearest
  double worstDepth = 0;
  int edgePixels = 0; // the slice traced here, nothing drawn there
};

// Renders the spheres and `slice` in a window and without OpenGL; counts agreement.
Comparison Compare(vtkImageSlice* slice, vtkActor* spheres, bool parallel,
  const std::function<void(vtkCamera*)>& aim)
{
  const int width = 300, height = 220;
  const double background[3] = { 0.1, 0.12, 0.15 };
  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(spheres);
  renderer->AddViewProp(slice);
  renderer->SetBackground(background);
  vtkNew<vtkRenderWindow> window;
  window->AddRenderer(renderer);
  window->SetSize(width, height);
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetParallelProjection(parallel);
  renderer->ResetCamera();
  aim(camera);
  renderer->ResetCameraClippingRange();
  window->Render();
  auto windowImage = CaptureRGB(window);
  auto windowDepth = CaptureDepth(window);

  vtkNew<vtkSightlineImageRenderer> glFree;
  glFree->AddActor(spheres);
  glFree->AddImageSlice(slice);
  glFree->SetActiveCamera(camera);
  glFree->SetSize(width, height);
  glFree->SetBackground(background[0], background[1], background[2]);
  glFree->Update();
  vtkImageData* image = glFree->GetOutput();

  vtkNew<vtkSightlineImageRenderer> spheresOnly;
  spheresOnly->AddActor(spheres);
  spheresOnly->SetActiveCamera(camera);
  spheresOnly->SetSize(width, height);
  spheresOnly->Update();
  auto* sphereDepth =
    vtkFloatArray::SafeDownCast(spheresOnly->GetOutput()->GetPointData()->GetArray("Depth"));

  Comparison result;
  auto* depth = vtkFloatArray::SafeDownCast(image->GetPointData()->GetArray("Depth"));
  for (int y = 0; y < height; ++y)
  {
    for (int x = 0; x < width; ++x)
    {
      const auto a = Pixel(windowImage, x, y), b = Pixel(image, x, y);
      ++result.pixels;
      result.within2 += std::abs(a[0] - b[0]) <= 2 && std::abs(a[1] - b[1]) <= 2 &&
        std::abs(a[2] - b[2]) <= 2;
      const vtkIdType i = vtkIdType(y) * width + x;
      const double traced = depth->GetValue(i);
      if (traced < 1.0 && traced < sphereDepth->GetValue(i) - 1e-5)
      {
        // The slice is what this pixel shows; the window's quad may leave out a pixel whose
        // centre lies within rounding of its edge (counted by the colour comparison).
        const double drawn = windowDepth->GetPointData()->GetScalars()->GetComponent(i, 0);
        if (drawn < 1.0)
        {
          ++result.planeDepth;
          result.worstDepth = std::max(result.worstDepth, std::abs(traced - drawn));
        }
        else
        {
          ++result.edgePixels;
        }
      }
    }
  }
  return result;
}

// A slice of `volume` drawn by a vtkImageSliceMapper (returned in `mapper` to configure),
// with this window and level.
vtkSmartPointer<vtkImageSlice> SliceOf(
  vtkImageData* volume, double window, double level, vtkImageSliceMapper*& mapper)
{
  auto sliceMapper = vtkSmartPointer<vtkImageSliceMapper>::New();
  sliceMapper->SetInputData(volume);
  auto slice = vtkSmartPointer<vtkImageSlice>::New();
  slice->SetMapper(sliceMapper);
  slice->GetProperty()->SetColorWindow(window);
  slice->GetProperty()->SetColorLevel(level);
  mapper = sliceMapper;
  return slice;
}

vtkSmartPointer<vtkActor> SpheresThroughThePlane(double z)
{
  auto mapper = vtkSmartPointer<vtkSightlineSphereMapper>::New();
  mapper->SetInputDataObject(
    MakeSpheres({ { -0.6, 0.0, z }, { 0.9, 0.4, z + 0.15 }, { 0.2, -0.7, z - 0.1 } },
      { 0.45, 0.35, 0.3 }));
  mapper->SetRadiusArrayName("radius");
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.9, 0.55, 0.2);
  return actor;
}

void ExpectAgreement(const Comparison& c, const char* what, int minimumPlanePixels = 2000)
{
  // OpenGL picks texels and quad coverage from interpolated float coordinates, so pixels
  // whose centre lies within rounding of a texel or quad edge may take the neighbour (measured:
  // at most 3 of 66000): at most 0.1 % of pixels, every other pixel within 2 levels.
  EXPECT_GE(c.within2, 0.999 * c.pixels) << what << ": " << c.pixels - c.within2 << " of "
                                          << c.pixels << " pixels differ by more than 2";
  EXPECT_GT(c.planeDepth, minimumPlanePixels) << what;
  EXPECT_LE(c.worstDepth, 2e-6) << what << ": plane depth against the window's depth buffer";
  EXPECT_LE(c.edgePixels, c.planeDepth / 200) << what << ": slice pixels the window leaves out";
  std::cout << what << ": " << c.pixels - c.within2 << " of " << c.pixels
            << " pixels differ by more than 2 levels; plane depth within " << c.worstDepth
            << " on " << c.planeDepth << " pixels (" << c.edgePixels
            << " edge pixels the window leaves out)\n";
}
} // namespace

TEST(ImageSlices, WindowLevelNearestMatchesTheWindow)
{
  auto volume = MakeVolume();
  vtkImageSliceMapper* mapper = nullptr;
  auto slice = SliceOf(volume, 120, 130, mapper);
  mapper->SetOrientationToZ();
  mapper->SetSliceNumber(3); // z = 0.15
  mapper->BorderOn();
  slice->GetProperty()->SetInterpolationTypeToNearest();
  auto spheres = SpheresThroughThePlane(0.15);
  for (const bool parallel : { false, true })
  {
    ExpectAgreement(Compare(slice, spheres, parallel,
                      [](vtkCamera* camera)
                      {
                        camera->Elevation(-35);
                        camera->Azimuth(20);
                      }),
      parallel ? "window/level, nearest, parallel" : "window/level, nearest, perspective");
  }
}

TEST(ImageSlices, LookupTableLinearObliqueMatchesTheWindow)
{
  auto volume = MakeVolume();
  vtkImageSliceMapper* mapper = nullptr;
  auto slice = SliceOf(volume, 150, 120, mapper);
  mapper->SetOrientationToZ();
  mapper->SetSliceNumber(2); // z = -0.15 in data coordinates
  mapper->BorderOff();
  vtkNew<vtkLookupTable> table;
  table->SetHueRange(0.66, 0.0);
  table->Build();
  slice->GetProperty()->SetLookupTable(table);
  slice->GetProperty()->SetInterpolationTypeToLinear();
  slice->SetOrientation(25, -10, 5); // an oblique plane, as a NIfTI affine gives
  slice->SetPosition(0.1, -0.2, 0.3);
  auto spheres = SpheresThroughThePlane(0.15);
  ExpectAgreement(Compare(slice, spheres, false,
                    [](vtkCamera* camera)
                    {
                      camera->Elevation(-30);
                      camera->Azimuth(-15);
                    }),
    "lookup table, linear, oblique");
}

TEST(ImageSlices, CroppedSagittalAndTranslucentMatchTheWindow)
{
  auto volume = MakeVolume();
  vtkImageSliceMapper* mapper = nullptr;
  auto slice = SliceOf(volume, 150, 120, mapper);
  mapper->SetOrientationToX();
  mapper->SetSliceNumber(8); // x = 0
  mapper->CroppingOn();
  mapper->SetCroppingRegion(0, 15, 2, 9, 1, 5);
  mapper->BorderOn();
  slice->GetProperty()->SetInterpolationTypeToNearest();
  auto spheres = SpheresThroughThePlane(0.0);
  auto aim = [](vtkCamera* camera)
  {
    camera->Azimuth(70);
    camera->Elevation(15);
    camera->OrthogonalizeViewUp();
  };
  ExpectAgreement(Compare(slice, spheres, false, aim), "cropped sagittal", 1000);
  slice->GetProperty()->SetOpacity(0.6);
  const Comparison translucent = Compare(slice, spheres, false, aim);
  // A translucent slice writes no depth: only colours are compared.
  EXPECT_GE(translucent.within2, 0.999 * translucent.pixels) << "translucent slice";
}

TEST(ImageSlices, SliceFacingTheCameraAtTheFocalPointMatchesTheWindow)
{
  // SliceFacesCamera and SliceAtFocalPoint: the mapper picks the axis and slice from the camera
  // at render time; the GL-free path must pick the same ones. The spacing is anisotropic, so an
  // axis weighed by its spacing would pick another one.
  auto volume = MakeVolume();
  vtkImageSliceMapper* mapper = nullptr;
  auto slice = SliceOf(volume, 150, 120, mapper);
  mapper->SliceFacesCameraOn();
  mapper->SliceAtFocalPointOn();
  mapper->BorderOn();
  slice->GetProperty()->SetInterpolationTypeToNearest();
  auto spheres = SpheresThroughThePlane(0.0);
  // View directions (data coordinates) whose largest component is x, but whose z component
  // weighed by the spacing (0.3 against 0.25) would win; and one mostly along y.
  for (const auto& direction : { std::array<double, 3>{ 1.0, 0.1, 0.9 },
         std::array<double, 3>{ 0.3, -1.0, 0.5 } })
  {
    ExpectAgreement(Compare(slice, spheres, false,
                      [direction](vtkCamera* camera)
                      {
                        camera->SetFocalPoint(0.3, 0.1, 0.2);
                        camera->SetPosition(0.3 + 8 * direction[0], 0.1 + 8 * direction[1],
                          0.2 + 8 * direction[2]);
                        camera->SetViewUp(0, 0, 1);
                        camera->OrthogonalizeViewUp();
                      }),
      direction[1] > 0 ? "facing the camera, mostly along x" : "facing the camera, along y", 1000);
  }
}

TEST(ImageSlices, NamesWhatItCannotDraw)
{
  vtkNew<vtkSightlineImageRenderer> renderer;
  vtkNew<vtkImageSlice> slice; // no mapper: skipped with a warning, the rest still renders
  renderer->AddImageSlice(slice);
  renderer->AddActor(SpheresThroughThePlane(0.0));
  renderer->ResetCamera();
  renderer->SetSize(64, 48);
  vtkNew<MessageCollector> messages;
  messages->Observe(renderer);
  renderer->Update();
  EXPECT_EQ(messages->Warnings.size(), 1u);
  EXPECT_TRUE(messages->Contains("vtkImageSliceMapper")) << "the warning names what can be drawn";
  EXPECT_GT(CoveredPixels(renderer->GetOutput()), 100);
}
