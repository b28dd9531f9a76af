// SPDX-License-Identifier: BSD-3-Clause
// vtkSightlineSphericalVolumeMapper and vtkSightlineSphericalFieldSource: the emission-absorption
// closed form of a homogeneous ball through the whole VTK path, occlusion by opaque geometry
// inside the volume in a window against the kernel with the window's depth, the GL-free path
// against the window, the angle conventions, PREM grids, and bad input.
#include "SightlineTestUtilities.h"

#include "vtkSightlineMapper.h"
#include "vtkSightlineImageRenderer.h"
#include "vtkSightlineSphereMapper.h"
#include "vtkSightlineSphericalFieldSource.h"
#include "vtkSightlineSphericalVolumeMapper.h"

#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkColorTransferFunction.h"
#include "vtkDoubleArray.h"
#include "vtkExtractRectilinearGrid.h"
#include "vtkTransform.h"
#include "vtkFloatArray.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPolyDataMapper.h"
#include "vtkRectilinearGrid.h"
#include "vtkSphereSource.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "sightline/volumes/EarthModel.h"
#include "sightline/core/Framebuffer.h"
#include "sightline/volumes/SphericalFields.h"
#include "sightline/volumes/SphericalVolume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace sightline_test;

namespace
{
using sightline::kPi;

// A volume of the source's output with a colour ramp and opacity per unit distance.
struct VolumeScene
{
  vtkNew<vtkSightlineSphericalFieldSource> source;
  vtkNew<vtkSightlineSphericalVolumeMapper> mapper;
  vtkNew<vtkColorTransferFunction> color;
  vtkNew<vtkPiecewiseFunction> opacity;
  vtkNew<vtkVolumeProperty> property;
  vtkNew<vtkVolume> volume;

  VolumeScene()
  {
    source->SetRadialResolution(12);
    source->SetPolarResolution(12);
    source->SetAzimuthalResolution(24);
    mapper->SetInputConnection(source->GetOutputPort());
    color->AddRGBPoint(1.0, 0.2, 0.4, 1.0);
    color->AddRGBPoint(2.0, 1.0, 0.6, 0.1);
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(1.0, 0.3);
    opacity->AddPoint(2.0, 0.6);
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    property->SetScalarOpacityUnitDistance(0.5);
    property->SetInterpolationTypeToNearest();
    volume->SetMapper(mapper);
    volume->SetProperty(property);
  }

  /// A blue-to-yellow ramp and opacities over PREM's density range (1 to 13.1 g/cm^3).
  void UsePREMDensityColours()
  {
    color->RemoveAllPoints();
    color->AddRGBPoint(1.0, 0.1, 0.2, 0.9);
    color->AddRGBPoint(13.1, 1.0, 0.9, 0.2);
    opacity->RemoveAllPoints();
    opacity->AddPoint(1.0, 0.1);
    opacity->AddPoint(13.1, 0.5);
  }
};

vtkSmartPointer<vtkImageData> RenderVolumeWithoutGL(
  vtkVolume* volume, const std::vector<vtkActor*>& actors, vtkCamera* camera, int width, int height)
{
  vtkNew<vtkSightlineImageRenderer> renderer;
  for (vtkActor* actor : actors)
    renderer->AddActor(actor);
  renderer->AddVolume(volume);
  renderer->SetActiveCamera(camera);
  renderer->SetSize(width, height);
  renderer->SetBackground(0, 0, 0);
  renderer->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(renderer->GetOutput());
  return image;
}

struct Window
{
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;
  Window(int width, int height, int multisamples = 0)
  {
    renderer->SetBackground(0, 0, 0);
    window->AddRenderer(renderer);
    window->SetSize(width, height);
    window->SetOffScreenRendering(1);
    window->SetMultiSamples(multisamples);
  }
};
} // namespace

// A ball of one value seen in parallel projection: every pixel's opacity is
// 1 - exp(-tau 2 sqrt(1 - b^2)) with tau = -ln(1 - a) / unit distance, b the pixel's distance
// from the centre. White over black, so the pixel value is 255 times that.
TEST(SphericalVolumeMapper, HomogeneousBallMatchesTheClosedForm)
{
  VolumeScene scene;
  scene.color->RemoveAllPoints();
  scene.color->AddRGBPoint(0.0, 1.0, 1.0, 1.0);
  scene.opacity->RemoveAllPoints();
  scene.opacity->AddPoint(0.5, 0.4);
  scene.opacity->AddPoint(2.5, 0.4);
  const double unit = 0.8;
  scene.property->SetScalarOpacityUnitDistance(unit);
  const int size = 64;
  const double scale = 1.1;
  auto camera = MakeCamera(true, 10.0, scale);
  vtkSmartPointer<vtkImageData> image = RenderVolumeWithoutGL(scene.volume, {}, camera, size, size);
  const double tau = -std::log(1.0 - 0.4) / unit;
  double worst = 0.0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
    {
      const double wx = ((x + 0.5) / size * 2.0 - 1.0) * scale;
      const double wy = ((y + 0.5) / size * 2.0 - 1.0) * scale;
      const double b2 = wx * wx + wy * wy;
      const double alpha = b2 < 1.0 ? 1.0 - std::exp(-tau * 2.0 * std::sqrt(1.0 - b2)) : 0.0;
      worst = std::max(worst, std::abs(Pixel(image, x, y)[0] - 255.0 * alpha));
    }
  EXPECT_LE(worst, 1.0) << "8-bit rounding is the only error expected";
  EXPECT_GT(scene.mapper->GetLastCellsVisited(), 0);
}

// An opaque sphere inside the volume: the window must show the volume in front of the sphere
// over the sphere, i.e. the kernel's frame with rays stopped at the sphere's depth, blended
// over what OpenGL drew.
TEST(SphericalVolumeMapper, OpaqueGeometryInsideOccludesInTheWindow)
{
  const int width = 160, height = 120;
  VolumeScene scene;
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(0.25, 0.2, 0.1);
  sphere->SetRadius(0.35);
  sphere->SetThetaResolution(64);
  sphere->SetPhiResolution(64);
  vtkNew<vtkPolyDataMapper> sphereMapper;
  sphereMapper->SetInputConnection(sphere->GetOutputPort());
  vtkNew<vtkActor> sphereActor;
  sphereActor->SetMapper(sphereMapper);
  sphereActor->GetProperty()->SetColor(0.1, 0.9, 0.2);
  auto camera = MakeCamera(false, 5.0);
  camera->SetPosition(1.5, -3.0, 3.5);
  camera->SetClippingRange(2.0, 8.0);

  // The sphere alone: its colour and depth.
  Window alone(width, height);
  alone.renderer->AddActor(sphereActor);
  alone.renderer->SetActiveCamera(camera);
  alone.window->Render();
  vtkSmartPointer<vtkImageData> behind = CaptureRGB(alone.window);
  vtkSmartPointer<vtkImageData> depth = CaptureDepth(alone.window);

  Window both(width, height);
  both.renderer->AddActor(sphereActor);
  both.renderer->AddVolume(scene.volume);
  both.renderer->SetActiveCamera(camera);
  both.window->Render();
  vtkSmartPointer<vtkImageData> shown = CaptureRGB(both.window);
  ASSERT_GT(scene.mapper->GetLastCellsVisited(), 0);

  // The kernel's frame with the sphere's depth as the limit.
  std::vector<float> limit(static_cast<std::size_t>(width) * height);
  auto* depthValues = vtkFloatArray::SafeDownCast(depth->GetPointData()->GetScalars());
  ASSERT_NE(depthValues, nullptr);
  std::copy(depthValues->GetPointer(0), depthValues->GetPointer(0) + limit.size(), limit.begin());
  sightline::Framebuffer expected, unoccluded;
  ASSERT_TRUE(scene.mapper->RayTrace(scene.volume, camera, nullptr, width, height, expected, &limit));
  ASSERT_TRUE(scene.mapper->RayTrace(scene.volume, camera, nullptr, width, height, unoccluded));

  int worst = 0, sphereMarkers = 0, occlusionVisible = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
    {
      const sightline::vec4 f = expected.Color[expected.index(x, y)];
      const std::array<int, 3> s = Pixel(behind, x, y), w = Pixel(shown, x, y);
      for (int c = 0; c < 3; ++c)
      {
        const double value = 255.0 * f[c] * f.a + (1.0 - f.a) * s[c];
        worst = std::max(worst, int(std::lround(std::abs(w[c] - value))));
      }
      if (limit[expected.index(x, y)] < 1.0f)
      {
        ++sphereMarkers;
        // Without the limit the ray would go on through the sphere: that frame differs.
        const sightline::vec4 u = unoccluded.Color[unoccluded.index(x, y)];
        if (std::abs(u.a - f.a) > 0.05f)
          ++occlusionVisible;
      }
    }
  EXPECT_LE(worst, 3) << "window differs from volume-over-sphere beyond 8-bit rounding";
  EXPECT_GT(sphereMarkers, 500);
  EXPECT_GT(occlusionVisible, sphereMarkers / 2) << "the scene does not exercise occlusion";
}

// Multisampled windows (VTK's default) must still give the rays the opaque depth.
TEST(SphericalVolumeMapper, DrawsInMultisampledWindows)
{
  VolumeScene scene;
  Window window(100, 100, 8);
  window.renderer->AddVolume(scene.volume);
  window.renderer->SetActiveCamera(MakeCamera(true, 10.0, 1.2));
  window.window->Render();
  EXPECT_GT(scene.mapper->GetLastCellsVisited(), 1000);
  const std::array<int, 3> centre = Pixel(CaptureRGB(window.window), 50, 50);
  EXPECT_GT(centre[0] + centre[1] + centre[2], 100);
}

// The GL-free renderer gives the window's pixels: a Sightline sphere inside the volume.
TEST(SphericalVolumeMapper, ImageRendererMatchesWindow)
{
  const int width = 120, height = 100;
  VolumeScene scene;
  scene.property->ShadeOn();
  vtkNew<vtkSightlineSphereMapper> sphereMapper;
  sphereMapper->SetInputDataObject(MakeSpheres({ { 0.2, -0.1, 0.3 } }, { 0.3 }));
  sphereMapper->SetRadiusArrayName("radius");
  vtkNew<vtkActor> sphereActor;
  sphereActor->SetMapper(sphereMapper);
  auto camera = MakeCamera(false, 5.0);
  camera->SetPosition(-2.0, 3.0, 3.0);
  camera->SetClippingRange(2.0, 8.0);

  Window window(width, height);
  window.renderer->AddActor(sphereActor);
  window.renderer->AddVolume(scene.volume);
  window.renderer->SetActiveCamera(camera);
  window.window->Render();
  vtkSmartPointer<vtkImageData> shown = CaptureRGB(window.window);
  vtkSmartPointer<vtkImageData> batch =
    RenderVolumeWithoutGL(scene.volume, { sphereActor.Get() }, camera, width, height);
  int differing = 0;
  EXPECT_LE(MaxRGBDifference(shown, batch, &differing), 2);
  EXPECT_GT(CoveredPixels(batch), width * height / 4);
}

// Degrees and latitude describe the same grid as radians and colatitude: identical images.
TEST(SphericalVolumeMapper, AngleConventionsAgree)
{
  VolumeScene scene;
  scene.source->SetFieldToPREMDensity();
  scene.source->SetAzimuthRange(0.0, 1.5 * kPi);
  scene.source->Update();
  scene.UsePREMDensityColours();
  auto camera = MakeCamera(false, 5.0);
  camera->SetPosition(3.0, -2.0, 2.5);
  camera->SetClippingRange(2.0, 8.0);
  vtkSmartPointer<vtkImageData> reference = RenderVolumeWithoutGL(scene.volume, {}, camera, 80, 80);

  // The same grid in degrees of latitude, rows of cells in reverse order.
  vtkRectilinearGrid* radians = scene.source->GetOutput();
  vtkNew<vtkRectilinearGrid> degrees;
  const int* dims = radians->GetDimensions();
  degrees->SetDimensions(dims[0], dims[1], dims[2]);
  degrees->SetXCoordinates(radians->GetXCoordinates());
  vtkNew<vtkDoubleArray> latitude, azimuth;
  for (int j = dims[1] - 1; j >= 0; --j)
    latitude->InsertNextValue(90.0 - radians->GetYCoordinates()->GetComponent(j, 0) * 180.0 / kPi);
  for (int k = 0; k < dims[2]; ++k)
    azimuth->InsertNextValue(radians->GetZCoordinates()->GetComponent(k, 0) * 180.0 / kPi);
  degrees->SetYCoordinates(latitude);
  degrees->SetZCoordinates(azimuth);
  vtkDataArray* values = radians->GetCellData()->GetScalars();
  vtkNew<vtkDoubleArray> reordered;
  reordered->SetName("density");
  reordered->SetNumberOfTuples(values->GetNumberOfTuples());
  const int nr = dims[0] - 1, nt = dims[1] - 1, np = dims[2] - 1;
  for (int k = 0; k < np; ++k)
    for (int j = 0; j < nt; ++j)
      for (int i = 0; i < nr; ++i)
        reordered->SetValue(i + nr * ((nt - 1 - j) + nt * k), values->GetComponent(i + nr * (j + nt * k), 0));
  degrees->GetCellData()->SetScalars(reordered);
  scene.mapper->SetInputDataObject(degrees);
  scene.mapper->SetAngleUnitsToDegrees();
  scene.mapper->SetPolarAngleToLatitude();
  vtkSmartPointer<vtkImageData> converted = RenderVolumeWithoutGL(scene.volume, {}, camera, 80, 80);
  EXPECT_LE(MaxRGBDifference(reference, converted), 1);
  EXPECT_GT(CoveredPixels(reference), 1000);
}

// Two MPI ranks' share of a volume, as vtkSightlineSphericalVolumeRepresentation makes them:
// each half of space draws only the cells ComputeCellRangeInBox gives for its box (moved into
// the grid's own frame by the volume's matrix), clipped to the half (SetRegion, in world
// space); the front half's image over the back half's is the whole image.
TEST(SphericalVolumeMapper, RegionHalvesOfTheirCellsBlendToTheWholeImage)
{
  VolumeScene scene;
  scene.source->SetFieldToPREMDensity();
  scene.source->SetAzimuthRange(0.5 * kPi, 2.5 * kPi); // the seam on +y, away from the cut
  scene.source->Update();
  scene.UsePREMDensityColours();
  scene.property->ShadeOn(); // the shading gradients need the neighbours of every cell drawn
  vtkNew<vtkTransform> placement; // a matrix that is not the identity: regions are in world space
  placement->Translate(0.4, -0.3, 0.2);
  placement->RotateZ(90.0); // boxes stay boxes in the grid's frame
  placement->Scale(1.2, 1.2, 1.2);
  scene.volume->SetUserTransform(placement);
  auto camera = MakeCamera(false, 5.0);
  camera->SetFocalPoint(0.4, -0.3, 0.2);
  camera->SetPosition(-3.0, 1.5, 2.0);
  camera->SetClippingRange(1.0, 9.0);
  const int size = 96;
  sightline::Framebuffer whole;
  ASSERT_TRUE(scene.mapper->RayTrace(scene.volume, camera, nullptr, size, size, whole));

  vtkRectilinearGrid* grid = scene.source->GetOutput();
  const int* dims = grid->GetDimensions();
  const double cut = 0.55, inf = std::numeric_limits<double>::infinity();
  const double halves[2][6] = { { -inf, cut, -inf, inf, -inf, inf }, { cut, inf, -inf, inf, -inf, inf } };
  sightline::Framebuffer parts[2];
  vtkIdType heldCells[2] = { 0, 0 };
  for (int h = 0; h < 2; ++h)
  {
    // The half's box around the volume, its corners in the grid's frame.
    double world[6];
    scene.volume->GetBounds(world);
    world[0] = std::max(world[0], halves[h][0]);
    world[1] = std::min(world[1], halves[h][1]);
    double box[6] = { inf, -inf, inf, -inf, inf, -inf };
    vtkNew<vtkTransform> toGrid;
    toGrid->SetMatrix(scene.volume->GetMatrix());
    toGrid->Inverse();
    for (int corner = 0; corner < 8; ++corner)
    {
      double p[3] = { world[corner & 1 ? 1 : 0], world[corner & 2 ? 3 : 2], world[corner & 4 ? 5 : 4] };
      toGrid->TransformPoint(p, p);
      for (int axis = 0; axis < 3; ++axis)
      {
        box[2 * axis] = std::min(box[2 * axis], p[axis]);
        box[2 * axis + 1] = std::max(box[2 * axis + 1], p[axis]);
      }
    }
    // With one cell more on each side: the shading gradients' neighbours.
    int range[6];
    ASSERT_TRUE(scene.mapper->ComputeCellRangeInBox(grid, box, range, 1));
    vtkNew<vtkExtractRectilinearGrid> extract;
    extract->SetInputData(grid);
    extract->SetVOI(range[0], range[1] + 1, range[2], range[3] + 1, range[4], range[5] + 1);
    extract->Update();
    heldCells[h] = extract->GetOutput()->GetNumberOfCells();
    scene.mapper->SetInputConnection(extract->GetOutputPort());
    scene.mapper->SetRegion(const_cast<double*>(halves[h]));
    ASSERT_TRUE(scene.mapper->RayTrace(scene.volume, camera, nullptr, size, size, parts[h]));
  }
  // The camera is at x < cut: every ray crosses the lower half first.
  int covered = 0, both = 0;
  // Opacity and colour within 2.5e-3: early ray termination at 0.002.
  ExpectFrontOverBackIsWhole(parts[0], parts[1], whole, 2.5e-3f, 2.5e-3f, covered, both);
  EXPECT_GT(covered, 3000);
  EXPECT_GT(both, 1000);
  EXPECT_LT(heldCells[0] + heldCells[1], 2 * grid->GetNumberOfCells()) << "each half holds less than the whole";
  std::printf("%d covered pixels, %d with layers in both halves; the halves hold %lld and %lld of %lld cells\n",
    covered, both, static_cast<long long>(heldCells[0]), static_cast<long long>(heldCells[1]),
    static_cast<long long>(grid->GetNumberOfCells()));

  // A box across the seam (on +y here) gets a run of azimuth cells across it, first > last,
  // which the margin widens around the circle; a margin that would close the circle gives all.
  const int azimuthCells = dims[2] - 1;
  const double acrossSeam[6] = { -0.3, 0.3, 0.5, 1.0, -0.2, 0.2 }; // about 60 to 120 degrees
  int seamRange[6], widened[6], all[6];
  ASSERT_TRUE(scene.mapper->ComputeCellRangeInBox(grid, acrossSeam, seamRange));
  EXPECT_GT(seamRange[4], seamRange[5]) << "a run across the seam";
  EXPECT_LT(seamRange[5] + 1 + azimuthCells - seamRange[4], azimuthCells / 2) << "not every azimuth";
  ASSERT_TRUE(scene.mapper->ComputeCellRangeInBox(grid, acrossSeam, widened, 2));
  EXPECT_EQ(widened[4], seamRange[4] - 2);
  EXPECT_EQ(widened[5], seamRange[5] + 2);
  ASSERT_TRUE(scene.mapper->ComputeCellRangeInBox(grid, acrossSeam, all, azimuthCells / 2));
  EXPECT_EQ(all[4], 0);
  EXPECT_EQ(all[5], azimuthCells - 1);

  // Latitude input lists its polar cells from the south: the range follows.
  vtkNew<vtkRectilinearGrid> latitude;
  latitude->SetDimensions(dims[0], dims[1], dims[2]);
  latitude->SetXCoordinates(grid->GetXCoordinates());
  latitude->SetZCoordinates(grid->GetZCoordinates());
  vtkNew<vtkDoubleArray> latitudes;
  for (int j = dims[1] - 1; j >= 0; --j)
    latitudes->InsertNextValue(0.5 * kPi - grid->GetYCoordinates()->GetComponent(j, 0));
  latitude->SetYCoordinates(latitudes);
  const double cap[6] = { -0.2, 0.3, 0.1, 0.5, 0.6, 1.0 };
  int colatitudeRange[6], latitudeRange[6];
  ASSERT_TRUE(scene.mapper->ComputeCellRangeInBox(grid, cap, colatitudeRange));
  scene.mapper->SetPolarAngleToLatitude();
  ASSERT_TRUE(scene.mapper->ComputeCellRangeInBox(latitude, cap, latitudeRange));
  EXPECT_EQ(latitudeRange[2], dims[1] - 2 - colatitudeRange[3]);
  EXPECT_EQ(latitudeRange[3], dims[1] - 2 - colatitudeRange[2]);
  EXPECT_LT(colatitudeRange[3], dims[1] / 2) << "a cap near the north pole";
  double bounds[6];
  EXPECT_TRUE(scene.mapper->ComputeSectionBounds(latitude, bounds));
  EXPECT_NEAR(bounds[5], grid->GetXCoordinates()->GetRange()[1], 1e-9);

  // Bad regions and grids are reported by name.
  vtkNew<MessageCollector> messages;
  messages->Observe(scene.mapper);
  scene.mapper->SetPolarAngleToColatitude();
  scene.mapper->SetInputConnection(scene.source->GetOutputPort());
  scene.mapper->SetRegion(0.0, 1.0, 2.0, std::nan(""), -inf, inf);
  EXPECT_FALSE(scene.mapper->RayTrace(scene.volume, camera, nullptr, size, size, whole));
  EXPECT_TRUE(messages->Contains("region's y range"));
  EXPECT_FALSE(scene.mapper->ComputeCellRangeInBox(latitude, cap, latitudeRange));
  EXPECT_TRUE(messages->Contains("not a spherical grid"));
  scene.mapper->SetRegionToAllOfSpace();
  EXPECT_TRUE(scene.mapper->RayTrace(scene.volume, camera, nullptr, size, size, whole));
}

// PREM grids: every layer boundary is a breakpoint and cells hold PREM's density at their
// midpoint, perturbed only in the mantle.
TEST(SphericalFieldSource, PremGridFollowsTheLayers)
{
  vtkNew<vtkSightlineSphericalFieldSource> source;
  source->SetFieldToPREMDensity();
  source->SetRadiusRange(0.0, 6371.0);
  source->SetRadialResolution(40);
  source->SetPolarResolution(6);
  source->SetAzimuthalResolution(8);
  source->SetPerturbationAmplitude(0.1);
  source->Update();
  vtkRectilinearGrid* grid = source->GetOutput();
  vtkDataArray* r = grid->GetXCoordinates();
  for (const auto& layer : sightline::premLayers())
  {
    bool found = false;
    for (vtkIdType i = 0; i < r->GetNumberOfTuples(); ++i)
      found = found || std::abs(r->GetComponent(i, 0) - layer.outerRadiusKm) < 1e-9;
    EXPECT_TRUE(found) << layer.name << " boundary at " << layer.outerRadiusKm << " km";
  }
  vtkDataArray* density = grid->GetCellData()->GetArray("density");
  ASSERT_NE(density, nullptr);
  const int* dims = grid->GetDimensions();
  const int nr = dims[0] - 1, nt = dims[1] - 1;
  for (int k : { 0, 3 })
    for (int j : { 0, 2 })
      for (int i = 0; i < nr; ++i)
      {
        const double rm = 0.5 * (r->GetComponent(i, 0) + r->GetComponent(i + 1, 0));
        const double theta = (j + 0.5) * kPi / nt, phi = (k + 0.5) * 2.0 * kPi / 8;
        double expected = sightline::premDensity(rm);
        if (rm > 3480.0 && rm < 6346.6)
          expected *= 1.0 + 0.1 * std::sin(theta) * std::sin(theta) * std::cos(2.0 * phi);
        EXPECT_NEAR(density->GetComponent(i + nr * (j + nt * k), 0), expected, 1e-12 * expected);
      }
}

TEST(SphericalVolumeMapper, BadInputIsReportedByName)
{
  auto makeGrid = [](std::vector<double> r, std::vector<double> theta, std::vector<double> phi, bool withScalars)
  {
    auto grid = vtkSmartPointer<vtkRectilinearGrid>::New();
    grid->SetDimensions(int(r.size()), int(theta.size()), int(phi.size()));
    for (auto [values, setter] : { std::make_pair(&r, 0), std::make_pair(&theta, 1), std::make_pair(&phi, 2) })
    {
      vtkNew<vtkDoubleArray> array;
      for (double v : *values)
        array->InsertNextValue(v);
      if (setter == 0)
        grid->SetXCoordinates(array);
      else if (setter == 1)
        grid->SetYCoordinates(array);
      else
        grid->SetZCoordinates(array);
    }
    if (withScalars)
    {
      vtkNew<vtkDoubleArray> values;
      values->SetName("values");
      values->SetNumberOfTuples(grid->GetNumberOfCells());
      values->Fill(1.0);
      grid->GetCellData()->SetScalars(values);
    }
    return grid;
  };
  struct Case
  {
    vtkSmartPointer<vtkRectilinearGrid> grid;
    std::string message;
  };
  const std::vector<Case> cases{
    { makeGrid({ 0.0, 0.6, 0.5, 1.0 }, { 0.0, kPi }, { 0.0, kPi }, true), "increasing" },
    { makeGrid({ -0.5, 1.0 }, { 0.0, kPi }, { 0.0, kPi }, true), "below 0" },
    { makeGrid({ 0.0, 1.0 }, { 0.0, 4.0 }, { 0.0, kPi }, true), "polar angle" },
    { makeGrid({ 0.0, 1.0 }, { 0.0, kPi }, { 0.0, 7.0 }, true), "2 pi" },
    { makeGrid({ 0.0, 1.0 }, { 0.0, kPi }, { 0.0, kPi }, false), "no scalars" },
  };
  for (const Case& c : cases)
  {
    VolumeScene scene;
    vtkNew<MessageCollector> messages;
    messages->Observe(scene.mapper);
    scene.mapper->SetInputDataObject(c.grid);
    sightline::Framebuffer frame;
    EXPECT_FALSE(scene.mapper->RayTrace(scene.volume, MakeCamera(true), nullptr, 16, 16, frame));
    ASSERT_FALSE(messages->Errors.empty()) << c.message;
    EXPECT_TRUE(messages->Contains(c.message)) << messages->Errors.front();
  }
  // Blend modes other than composite, and a cell array of the wrong size.
  {
    VolumeScene scene;
    vtkNew<MessageCollector> messages;
    messages->Observe(scene.mapper);
    scene.mapper->SetBlendModeToMaximumIntensity();
    sightline::Framebuffer frame;
    EXPECT_FALSE(scene.mapper->RayTrace(scene.volume, MakeCamera(true), nullptr, 16, 16, frame));
    EXPECT_TRUE(messages->Contains("not supported"));
  }
  {
    VolumeScene scene;
    vtkNew<MessageCollector> messages;
    messages->Observe(scene.mapper);
    auto grid = makeGrid({ 0.0, 0.5, 1.0 }, { 0.0, kPi }, { 0.0, kPi }, false);
    vtkNew<vtkDoubleArray> values;
    values->SetNumberOfTuples(5);
    values->Fill(1.0);
    grid->GetCellData()->SetScalars(values);
    scene.mapper->SetInputDataObject(grid);
    sightline::Framebuffer frame;
    EXPECT_FALSE(scene.mapper->RayTrace(scene.volume, MakeCamera(true), nullptr, 16, 16, frame));
    EXPECT_TRUE(messages->Contains("tuples"));
  }
  // Infinite and huge cell values are drawn empty with a warning (they were accepted silently;
  // 1e308 overflows the mean of a cell's corners and the span of the transfer table).
  {
    VolumeScene scene;
    vtkNew<MessageCollector> messages;
    messages->Observe(scene.mapper);
    auto grid = makeGrid({ 0.0, 0.5, 1.0 }, { 0.0, kPi }, { 0.0, kPi }, true);
    grid->GetCellData()->GetScalars()->SetComponent(0, 0, std::numeric_limits<double>::infinity());
    grid->GetCellData()->GetScalars()->SetComponent(1, 0, 1e308);
    scene.mapper->SetInputDataObject(grid);
    sightline::Framebuffer frame;
    EXPECT_TRUE(scene.mapper->RayTrace(scene.volume, MakeCamera(true), nullptr, 16, 16, frame));
    EXPECT_TRUE(messages->Contains("2 cells have NaN, infinite or out-of-range values"));
  }
  // Bad source settings.
  {
    vtkNew<vtkSightlineSphericalFieldSource> source;
    vtkNew<MessageCollector> messages;
    messages->Observe(source);
    source->SetPolarRange(0.0, 5.0);
    source->Update();
    EXPECT_TRUE(messages->Contains("polar angle"));
  }
}

// Regression image: a PREM Earth with a quarter cut away around an opaque inner core, shaded,
// in a window. Look at Testing/Data/Baseline/SphericalVolumeEarth.png when it changes.
TEST(SphericalVolumeMapper, EarthMatchesBaseline)
{
  VolumeScene scene;
  scene.source->SetFieldToPREMDensity();
  scene.source->SetRadiusRange(1221.5 / 6371.0, 1.0);
  scene.source->SetRadialResolution(40);
  scene.source->SetPolarResolution(24);
  scene.source->SetAzimuthalResolution(36);
  scene.source->SetAzimuthRange(0.0, 1.5 * kPi);
  scene.color->RemoveAllPoints();
  scene.color->AddRGBPoint(2.6, 0.55, 0.45, 0.35);
  scene.color->AddRGBPoint(3.3, 0.95, 0.85, 0.45);
  scene.color->AddRGBPoint(5.6, 0.60, 0.10, 0.15);
  scene.color->AddRGBPoint(9.9, 0.25, 0.45, 0.85);
  scene.opacity->RemoveAllPoints();
  scene.opacity->AddPoint(1.0, 0.0);
  scene.opacity->AddPoint(3.3, 0.35);
  scene.opacity->AddPoint(5.6, 0.55);
  scene.opacity->AddPoint(9.9, 0.06);
  scene.property->SetScalarOpacityUnitDistance(0.06);
  scene.property->ShadeOn();
  vtkNew<vtkSightlineSphereMapper> core;
  core->SetInputDataObject(MakeSpheres({ { 0.0, 0.0, 0.0 } }, { 1221.5 / 6371.0 }));
  core->SetRadiusArrayName("radius");
  vtkNew<vtkActor> coreActor;
  coreActor->SetMapper(core);
  Window window(240, 200);
  window.renderer->AddActor(coreActor);
  window.renderer->AddVolume(scene.volume);
  vtkCamera* camera = window.renderer->GetActiveCamera();
  camera->SetPosition(2.4, -2.9, 1.5);
  camera->SetViewUp(0, 0, 1);
  window.renderer->ResetCamera();
  camera->Dolly(1.5);
  window.renderer->ResetCameraClippingRange();
  window.window->Render();
  EXPECT_TRUE(MatchesBaseline(CaptureRGB(window.window), "SphericalVolumeEarth", 0.5));
}

// A homogeneous cylinder (rho < 0.8, |z| < 0.6) read as a cylindrical grid, seen along its axis
// (vertical rays: the chord is the height) and from the side (the chord is 2 sqrt(0.64 - x^2)
// where |z| < 0.6): opacity 1 - exp(-tau chord) per pixel.
TEST(SphericalVolumeMapper, CylindricalGridMatchesTheClosedForm)
{
  auto grid = vtkSmartPointer<vtkRectilinearGrid>::New();
  const std::vector<double> rho{ 0.0, 0.3, 0.55, 0.8 }, phi{ 0.0, 1.0, 2.5, 4.0, 2.0 * kPi },
    z{ -0.6, -0.1, 0.2, 0.6 };
  grid->SetDimensions(int(rho.size()), int(phi.size()), int(z.size()));
  int axis = 0;
  for (const std::vector<double>* b : { &rho, &phi, &z })
  {
    vtkNew<vtkDoubleArray> array;
    for (double v : *b)
      array->InsertNextValue(v);
    if (axis == 0)
      grid->SetXCoordinates(array);
    else if (axis == 1)
      grid->SetYCoordinates(array);
    else
      grid->SetZCoordinates(array);
    ++axis;
  }
  vtkNew<vtkDoubleArray> values;
  values->SetNumberOfTuples(grid->GetNumberOfCells());
  values->Fill(1.0);
  grid->GetCellData()->SetScalars(values);

  VolumeScene scene;
  scene.mapper->SetInputDataObject(grid);
  scene.mapper->SetCoordinateSystemToCylindrical();
  scene.color->RemoveAllPoints();
  scene.color->AddRGBPoint(0.0, 1.0, 1.0, 1.0);
  scene.opacity->RemoveAllPoints();
  scene.opacity->AddPoint(0.0, 0.4);
  scene.opacity->AddPoint(2.0, 0.4);
  const double unit = 0.8, tau = -std::log(1.0 - 0.4) / unit;
  scene.property->SetScalarOpacityUnitDistance(unit);
  const double* bounds = scene.mapper->GetBounds();
  EXPECT_NEAR(bounds[0], -0.8, 1e-12);
  EXPECT_NEAR(bounds[3], 0.8, 1e-12);
  EXPECT_NEAR(bounds[5], 0.6, 1e-12);

  const int size = 48;
  const double scale = 1.0;
  for (const bool side : { false, true })
  {
    auto camera = MakeCamera(true, 10.0, scale);
    if (side)
    {
      camera->SetPosition(0.0, -10.0, 0.0); // looking along +y, z up
      camera->SetViewUp(0.0, 0.0, 1.0);
    }
    vtkSmartPointer<vtkImageData> image = RenderVolumeWithoutGL(scene.volume, {}, camera, size, size);
    double worst = 0.0;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x)
      {
        const double u = ((x + 0.5) / size * 2.0 - 1.0) * scale, v = ((y + 0.5) / size * 2.0 - 1.0) * scale;
        double chord;
        if (side)
          chord = std::abs(v) < 0.6 && std::abs(u) < 0.8 ? 2.0 * std::sqrt(0.64 - u * u) : 0.0;
        else
          chord = u * u + v * v < 0.64 ? 1.2 : 0.0;
        const double alpha = 1.0 - std::exp(-tau * chord);
        worst = std::max(worst, std::abs(Pixel(image, x, y)[0] - 255.0 * alpha));
      }
    EXPECT_LE(worst, 1.0) << (side ? "side view" : "along the axis");
  }
}

// Point data through the interpolating path: a field r^2 at the points of the unit ball with
// extinction proportional to the value (opacity table linear in the value) against the kernel's
// exact integral of r^2 along each ray, 1 - exp(-k integral), within 1/255 at the automatic
// sample distance; and constant point data equals the homogeneous ball's closed form.
TEST(SphericalVolumeMapper, PointDataIsInterpolated)
{
  VolumeScene scene;
  scene.source->SetFieldToRadiusSquared();
  scene.source->OutputCellDataOff();
  scene.source->SetRadialResolution(16);
  scene.color->RemoveAllPoints();
  scene.color->AddRGBPoint(0.0, 1.0, 1.0, 1.0);
  scene.opacity->RemoveAllPoints();
  // Opacity per unit distance u such that the extinction -ln(1 - a(v)) / u is 1.5 v: a(v) is
  // not linear, so give the table many points.
  const double k = 1.5, unit = 1.0;
  for (int i = 0; i <= 64; ++i)
  {
    const double v = i / 64.0;
    scene.opacity->AddPoint(v, 1.0 - std::exp(-k * v * unit));
  }
  scene.property->SetScalarOpacityUnitDistance(unit);
  const int size = 40;
  auto camera = MakeCamera(true, 10.0, 1.1);
  vtkSmartPointer<vtkImageData> image = RenderVolumeWithoutGL(scene.volume, {}, camera, size, size);
  const sightline::RadiusSquaredField r2{ 1.0 };
  double worst = 0.0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
    {
      const sightline::dvec3 o(((x + 0.5) / size * 2.0 - 1.0) * 1.1, ((y + 0.5) / size * 2.0 - 1.0) * 1.1, 5.0);
      const double alpha = 1.0 - std::exp(-k * r2.rayIntegral(o, sightline::dvec3(0, 0, -1), 0.0, 10.0));
      worst = std::max(worst, std::abs(Pixel(image, x, y)[0] - 255.0 * alpha));
    }
  EXPECT_LE(worst, 1.5) << "interpolated r^2 against its exact integral (0-255)";

  // The per-cell mean is visibly coarser for this field.
  scene.mapper->InterpolatePointDataOff();
  vtkSmartPointer<vtkImageData> averaged = RenderVolumeWithoutGL(scene.volume, {}, camera, size, size);
  EXPECT_GT(MaxRGBDifference(image, averaged), 2);
}
