// SPDX-License-Identifier: BSD-3-Clause
// vtkSightlineTensorGlyphMapper: a published 4th-order stiffness tensor (copper) in every layout,
// real diffusion tensors of DIPY's small_64D (the TensorData fixture, scripts/
// make_tensor_data.py) drawn as vtkTensorGlyph's ellipsoids and compared with vtkTensorGlyph
// itself, real generalised-DTI tensors of orders 4, 6 and 8, the paper's own intersection
// methods against the exact one, and bad input. Baselines use vtkTesting's metric, threshold 0.5.
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkDoubleArray.h"
#include "vtkExtractVOI.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkNIFTIImageReader.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSightlineTensorGlyphMapper.h"
#include "vtkSphereSource.h"
#include "vtkTensorGlyph.h"

#include "sightline/math/SymmetricTensor.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace sightline_test;

namespace
{
// Copper at room temperature, GPa (Kittel, Introduction to Solid State Physics, 8th ed., Ch. 3,
// Table 3: C11 = 1.684, C12 = 1.214, C44 = 0.754 in 10^11 N/m^2).
constexpr double kC11 = 168.4, kC12 = 121.4, kC44 = 75.4;

std::string DataFile(const std::string& name)
{
  return std::string(SIGHTLINE_TENSOR_DATA_DIR) + "/" + name;
}

vtkSmartPointer<vtkImageData> ReadAxialSlice(const std::string& name)
{
  vtkNew<vtkNIFTIImageReader> reader;
  reader->SetFileName(DataFile(name).c_str());
  reader->TimeAsVectorOn();
  vtkNew<vtkExtractVOI> voi;
  voi->SetInputConnection(reader->GetOutputPort());
  voi->SetVOI(0, 9, 0, 9, 4, 4);
  voi->Update();
  auto slice = vtkSmartPointer<vtkImageData>::New();
  slice->DeepCopy(voi->GetOutput());
  return slice;
}

using Scene = MapperScene<vtkSightlineTensorGlyphMapper>;

/// The image's slice seen from above (+z), parallel projection.
void ViewSliceFromAbove(vtkRenderer* renderer, vtkImageData* slice)
{
  double bounds[6];
  slice->GetBounds(bounds);
  const double cx = 0.5 * (bounds[0] + bounds[1]), cy = 0.5 * (bounds[2] + bounds[3]);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint(cx, cy, bounds[4]);
  camera->SetPosition(cx, cy, bounds[4] + 50);
  camera->SetViewUp(0, 1, 0);
  camera->ParallelProjectionOn();
  camera->SetParallelScale(0.55 * (bounds[3] - bounds[2] + 2.0));
  renderer->ResetCameraClippingRange(bounds[0] - 2, bounds[1] + 2, bounds[2] - 2, bounds[3] + 2,
    bounds[4] - 2, bounds[5] + 2);
}

/// One point at the origin carrying `values` as the array "T".
vtkSmartPointer<vtkPolyData> SinglePoint(const std::vector<double>& values)
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  poly->SetPoints(points);
  vtkNew<vtkDoubleArray> array;
  array->SetName("T");
  array->SetNumberOfComponents(static_cast<int>(values.size()));
  array->InsertNextTuple(values.data());
  poly->GetPointData()->AddArray(array);
  return poly;
}

/// Copper's full stiffness tensor turned by the rotation R: C'_abcd = R_ai R_bj R_ck R_dl C_ijkl.
std::vector<double> RotatedCopper(const double r[3][3])
{
  double voigt[36] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      voigt[6 * i + j] = i == j ? kC11 : kC12;
  voigt[21] = voigt[28] = voigt[35] = kC44;
  const std::vector<double> c = sightline::stiffnessFromVoigt(voigt);
  std::vector<double> out(81, 0.0);
  auto at = [](int i, int j, int k, int l) { return i + 3 * j + 9 * k + 27 * l; };
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int cc = 0; cc < 3; ++cc)
        for (int d = 0; d < 3; ++d)
        {
          double sum = 0.0;
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              for (int k = 0; k < 3; ++k)
                for (int l = 0; l < 3; ++l)
                  sum += r[a][i] * r[b][j] * r[cc][k] * r[d][l] * c[at(i, j, k, l)];
          out[at(a, b, cc, d)] = sum;
        }
  return out;
}

/// A rotation by 25 degrees about (1, 2, 3) / |(1, 2, 3)|.
void FixedRotation(double r[3][3])
{
  double axis[3] = { 1, 2, 3 };
  vtkMath::Normalize(axis);
  const double angle = vtkMath::RadiansFromDegrees(25.0);
  double quaternion[4] = { std::cos(angle / 2), std::sin(angle / 2) * axis[0],
    std::sin(angle / 2) * axis[1], std::sin(angle / 2) * axis[2] };
  vtkMath::QuaternionToMatrix3x3(quaternion, r);
}

vtkSmartPointer<vtkImageData> RenderSingle(
  const std::vector<double>& values, int layout, void (*configure)(vtkSightlineTensorGlyphMapper*) = nullptr)
{
  Scene scene(240, 240);
  scene.mapper->SetInputDataObject(SinglePoint(values));
  scene.mapper->SetTensorArrayName("T");
  scene.mapper->SetTensorLayout(layout);
  if (configure)
    configure(scene.mapper);
  ViewSingleGlyph(scene.renderer);
  scene.window->Render();
  return CaptureRGB(scene.window);
}

/// 3x3 symmetric matrix of a unique-order (xx, xy, xz, yy, yz, zz) tuple.
void Matrix(const double* t, double m[3][3])
{
  const double values[3][3] = { { t[0], t[1], t[2] }, { t[1], t[3], t[4] }, { t[2], t[4], t[5] } };
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m[i][j] = values[i][j];
}

/// Pixels covered in `reference` but not in `image` (missed) and the reverse (extra), within
/// `radius` pixels of the image centre (everywhere by default).
std::pair<int, int> Coverage(vtkImageData* reference, vtkImageData* image, int radius = 1 << 20)
{
  int missed = 0, extra = 0;
  const int w = reference->GetDimensions()[0], h = reference->GetDimensions()[1];
  for (int y = std::max(0, h / 2 - radius); y < std::min(h, h / 2 + radius); ++y)
    for (int x = std::max(0, w / 2 - radius); x < std::min(w, w / 2 + radius); ++x)
    {
      const auto pa = Pixel(reference, x, y), pb = Pixel(image, x, y);
      const bool ca = pa[0] + pa[1] + pa[2] > 0, cb = pb[0] + pb[1] + pb[2] > 0;
      missed += ca && !cb;
      extra += cb && !ca;
    }
  return { missed, extra };
}

int Mismatch(vtkImageData* a, vtkImageData* b)
{
  const auto c = Coverage(a, b);
  return c.first + c.second;
}
} // namespace

// Copper's stiffness tensor (a cubic crystal, turned off its axes) given as a Voigt matrix, as
// the full 3x3x3x3 tensor and as unique components draws the same glyph; its largest radius is
// the longitudinal modulus along <111>, (C11 + 2 C12 + 4 C44) / 3 = 237.6 GPa.
TEST(TensorGlyphMapper, CopperStiffnessInEveryLayoutMatchesBaseline)
{
  double r[3][3];
  FixedRotation(r);
  const std::vector<double> full = RotatedCopper(r);
  const std::vector<double> unique = sightline::symmetricPartFromFull(4, full.data());
  std::vector<double> voigt(36);
  const int pairs[6][2] = { { 0, 0 }, { 1, 1 }, { 2, 2 }, { 1, 2 }, { 0, 2 }, { 0, 1 } };
  for (int I = 0; I < 6; ++I)
    for (int J = 0; J < 6; ++J)
      voigt[6 * I + J] = full[pairs[I][0] + 3 * pairs[I][1] + 9 * pairs[J][0] + 27 * pairs[J][1]];

  auto byRadius = [](vtkSightlineTensorGlyphMapper* mapper)
  {
    mapper->SetColoringToRadius();
    mapper->SetRadiusRange(150.0, 240.0);
  };
  auto fromVoigt = RenderSingle(voigt, vtkSightlineTensorGlyphMapper::LAYOUT_VOIGT, byRadius);
  auto fromFull = RenderSingle(full, vtkSightlineTensorGlyphMapper::LAYOUT_AUTOMATIC, byRadius);
  auto fromUnique = RenderSingle(unique, vtkSightlineTensorGlyphMapper::LAYOUT_SYMMETRIC_UNIQUE, byRadius);
  EXPECT_LE(MaxRGBDifference(fromVoigt, fromFull), 1);
  EXPECT_LE(MaxRGBDifference(fromVoigt, fromUnique), 1);
  EXPECT_GT(CoveredPixels(fromVoigt), 15000);
  EXPECT_TRUE(MatchesBaseline(fromVoigt, "TensorGlyphCopper", 0.5));

  Scene scene(64, 64);
  scene.mapper->SetInputDataObject(SinglePoint(voigt));
  scene.mapper->SetTensorArrayName("T");
  scene.mapper->SetColoringToRadius();
  ViewSingleGlyph(scene.renderer);
  scene.window->Render();
  EXPECT_EQ(scene.mapper->GetTensorOrder(), 4);
  EXPECT_NEAR(scene.mapper->GetLastRadiusRange()[1], (kC11 + 2 * kC12 + 4 * kC44) / 3, 0.01);
}

// VTK's 6-component order, the 9-component full tensor, unique components and a non-symmetric
// full tensor with the same symmetric part give one glyph.
TEST(TensorGlyphMapper, SecondOrderLayoutsAgree)
{
  const double xx = 3, xy = 0.5, xz = -0.4, yy = 1.2, yz = 0.3, zz = 0.6;
  const std::vector<double> unique = { xx, xy, xz, yy, yz, zz };
  const std::vector<double> vtkOrder = { xx, yy, zz, xy, yz, xz };
  const std::vector<double> full = { xx, xy, xz, xy, yy, yz, xz, yz, zz };
  std::vector<double> skew = full;
  skew[1] += 0.7; // xy
  skew[3] -= 0.7; // yx
  skew[5] += 0.2;
  skew[7] -= 0.2;
  auto a = RenderSingle(unique, vtkSightlineTensorGlyphMapper::LAYOUT_SYMMETRIC_UNIQUE);
  auto b = RenderSingle(vtkOrder, vtkSightlineTensorGlyphMapper::LAYOUT_AUTOMATIC);
  auto c = RenderSingle(full, vtkSightlineTensorGlyphMapper::LAYOUT_AUTOMATIC);
  auto d = RenderSingle(skew, vtkSightlineTensorGlyphMapper::LAYOUT_FULL);
  EXPECT_GT(CoveredPixels(a), 5000);
  EXPECT_LE(MaxRGBDifference(a, b), 1);
  EXPECT_LE(MaxRGBDifference(a, c), 1);
  EXPECT_LE(MaxRGBDifference(a, d), 1);
}

// Real diffusion tensors drawn as ellipsoids have vtkTensorGlyph's shape: the tessellated
// ellipsoids' silhouettes converge to ours as the sphere source gets finer, and at 64 x 64
// they differ in under 1 % of the covered pixels.
TEST(TensorGlyphMapper, DTIEllipsoidsMatchVTKTensorGlyph)
{
  auto slice = ReadAxialSlice("small_64D_dti.nii.gz");
  vtkDataArray* tensors = slice->GetPointData()->GetScalars();
  ASSERT_NE(tensors, nullptr);
  ASSERT_EQ(tensors->GetNumberOfComponents(), 6);
  // vtkTensorGlyph takes 9-component tensors; the common scale makes the largest semi-axis
  // of the slice ScaleFactor.
  double largest = 0.0;
  vtkNew<vtkDoubleArray> nine;
  nine->SetName("D9");
  nine->SetNumberOfComponents(9);
  for (vtkIdType i = 0; i < tensors->GetNumberOfTuples(); ++i)
  {
    double t[6], m[3][3], w[3], v[3][3];
    tensors->GetTuple(i, t);
    Matrix(t, m);
    vtkMath::Diagonalize3x3(m, w, v);
    for (double e : w)
      largest = std::max(largest, std::abs(e));
    nine->InsertNextTuple9(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]);
  }
  ASSERT_GT(largest, 0.0);
  slice->GetPointData()->AddArray(nine);
  const double worldScale = 0.9 * 0.5 * slice->GetSpacing()[0]; // ScaleFactor 0.9, half a voxel

  auto ours = [&](bool solid)
  {
    Scene scene(400, 400);
    scene.mapper->SetInputDataObject(slice);
    scene.mapper->SetTensorArrayName("NIFTI");
    scene.mapper->SetTensorLayoutToSymmetricUnique();
    scene.mapper->SetShapeToEllipsoid();
    scene.mapper->SetNormalizationToGlobal();
    scene.mapper->SetScaleFactor(0.9);
    if (solid)
      scene.mapper->SetColoringToSolid();
    ViewSliceFromAbove(scene.renderer, slice);
    scene.window->Render();
    return CaptureRGB(scene.window);
  };
  auto tessellated = [&](int resolution)
  {
    vtkNew<vtkSphereSource> sphere;
    sphere->SetRadius(1.0); // the unit sphere (the source's default radius is 0.5)
    sphere->SetThetaResolution(resolution);
    sphere->SetPhiResolution(resolution);
    vtkNew<vtkTensorGlyph> glyphs;
    glyphs->SetInputData(slice);
    glyphs->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "D9");
    glyphs->SetSourceConnection(sphere->GetOutputPort());
    glyphs->SetScaleFactor(worldScale / largest);
    glyphs->ClampScalingOff();
    glyphs->ColorGlyphsOff();
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(glyphs->GetOutputPort());
    mapper->ScalarVisibilityOff();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    vtkNew<vtkRenderer> renderer;
    renderer->AddActor(actor);
    renderer->SetBackground(0, 0, 0);
    vtkNew<vtkRenderWindow> window;
    window->AddRenderer(renderer);
    window->SetSize(400, 400);
    window->SetOffScreenRendering(1);
    window->SetMultiSamples(0);
    ViewSliceFromAbove(renderer, slice);
    window->Render();
    return CaptureRGB(window);
  };
  auto exact = ours(true);
  const int covered = CoveredPixels(exact);
  {
    // The ellipsoids and the converted tensors are counted: more than the 6 doubles per voxel.
    Scene scene(32, 32);
    scene.mapper->SetInputDataObject(slice);
    scene.mapper->SetTensorLayoutToSymmetricUnique();
    scene.mapper->SetShapeToEllipsoid();
    scene.window->Render();
    EXPECT_GT(scene.mapper->GetMemoryBytes(), vtkIdType(6 * sizeof(double) * slice->GetNumberOfPoints()));
  }
  EXPECT_GT(covered, 8000);
  const int coarse = Mismatch(exact, tessellated(8));
  const int fine = Mismatch(exact, tessellated(64));
  std::cout << "ellipsoid silhouettes: " << covered << " covered pixels; differing from "
            << "vtkTensorGlyph at sphere resolution 8: " << coarse << ", 64: " << fine << "\n";
  EXPECT_LT(fine, coarse);
  EXPECT_LT(fine, covered / 100);
  EXPECT_TRUE(MatchesBaseline(ours(false), "TensorGlyphDTIEllipsoids", 0.5));
}

// The same tensors as the tensor function x^T D x (the paper's glyph for n = 2): a different,
// pinched shape, whose longest radius is the ellipsoid's longest semi-axis.
TEST(TensorGlyphMapper, DTIOrder2GlyphMatchesBaseline)
{
  auto slice = ReadAxialSlice("small_64D_dti.nii.gz");
  Scene scene(400, 400);
  scene.mapper->SetInputDataObject(slice);
  scene.mapper->SetTensorLayoutToSymmetricUnique();
  scene.mapper->SetScaleFactor(0.9);
  ViewSliceFromAbove(scene.renderer, slice);
  scene.window->Render();
  auto image = CaptureRGB(scene.window);
  EXPECT_EQ(scene.mapper->GetTensorOrder(), 2);
  EXPECT_GT(CoveredPixels(image), 5000);
  EXPECT_TRUE(MatchesBaseline(image, "TensorGlyphDTIOrder2", 0.5));
}

// Generalised DTI (Ozarslan and Mareci) of orders 4, 6 and 8 fitted to the same DWI.
TEST(TensorGlyphMapper, GeneralisedDTIOrders468MatchBaselines)
{
  for (int order : { 4, 6, 8 })
  {
    auto slice = ReadAxialSlice("small_64D_gdti" + std::to_string(order) + ".nii.gz");
    Scene scene(400, 400);
    scene.mapper->SetInputDataObject(slice);
    scene.mapper->SetScaleFactor(0.9);
    ViewSliceFromAbove(scene.renderer, slice);
    scene.window->Render();
    auto image = CaptureRGB(scene.window);
    EXPECT_EQ(scene.mapper->GetTensorOrder(), order);
    EXPECT_GT(CoveredPixels(image), 5000) << "order " << order;
    EXPECT_TRUE(MatchesBaseline(image, "TensorGlyphGDTI" + std::to_string(order), 0.5))
      << "order " << order;
  }
}

// The paper's methods through the mapper: fine marching and reduced affine arithmetic give the
// exact picture; interval arithmetic misses nothing but, overestimating, reports hits up to a few
// hundredths of the radius early near silhouettes (measured: 26 extra pixels, colours off by up
// to 36 levels at tolerance 1e-4). The recommended step 0.2 misses parts of a glyph whose lobes
// touch the centre (the paper's singularity), with or without its finer centre steps.
TEST(TensorGlyphMapper, PaperMethodsAgreeWithExact)
{
  double r[3][3];
  FixedRotation(r);
  const std::vector<double> copper = RotatedCopper(r);
  auto exact = RenderSingle(copper, vtkSightlineTensorGlyphMapper::LAYOUT_FULL);
  auto fineMarching = RenderSingle(copper, vtkSightlineTensorGlyphMapper::LAYOUT_FULL,
    [](vtkSightlineTensorGlyphMapper* m)
    {
      m->SetIntersectionMethodToMarching();
      m->SetMarchingStepSize(0.01);
      m->SetMarchingBisectionSteps(8);
    });
  auto affine = RenderSingle(copper, vtkSightlineTensorGlyphMapper::LAYOUT_FULL,
    [](vtkSightlineTensorGlyphMapper* m) { m->SetIntersectionMethodToAffine(); });
  auto interval = RenderSingle(copper, vtkSightlineTensorGlyphMapper::LAYOUT_FULL,
    [](vtkSightlineTensorGlyphMapper* m) { m->SetIntersectionMethodToInterval(); });
  const char* names[3] = { "marching 0.01", "affine", "interval" };
  int index = 0;
  for (auto* image : { fineMarching.Get(), affine.Get(), interval.Get() })
  {
    int differing = 0;
    const int largest = MaxRGBDifference(exact, image, &differing);
    const auto coverage = Coverage(exact, image);
    std::cout << names[index] << ": " << coverage.first << " pixels missed, " << coverage.second
              << " extra, " << differing << " differ, by at most " << largest << "\n";
    if (index < 2)
    {
      EXPECT_LE(coverage.first + coverage.second, 2);
      EXPECT_LE(largest, 2);
    }
    else
    {
      EXPECT_EQ(coverage.first, 0); // guaranteed: never rejects surface
      EXPECT_LE(coverage.second, CoveredPixels(exact) / 200);
    }
    ++index;
  }

  // A glyph pinched at the centre, seen side on: T(w) = w_z^4 - 0.2 w_x^4 (lobes meet at 0).
  std::vector<double> pinched(15, 0.0);
  pinched[14] = 1.0;  // zzzz
  pinched[0] = -0.2;  // xxxx
  auto touching = [&](double step, bool centre, int method)
  {
    Scene scene(240, 240);
    scene.mapper->SetInputDataObject(SinglePoint(pinched));
    scene.mapper->SetTensorArrayName("T");
    scene.mapper->SetIntersectionMethod(method);
    scene.mapper->SetMarchingStepSize(step);
    scene.mapper->SetMarchingCentreRefinement(centre);
    vtkCamera* camera = scene.renderer->GetActiveCamera();
    camera->SetFocalPoint(0, 0, 0);
    camera->SetPosition(0.3, -5, 0.2);
    camera->SetViewUp(0, 0, 1);
    camera->ParallelProjectionOn();
    camera->SetParallelScale(1.1);
    scene.renderer->ResetCameraClippingRange(-2, 2, -2, 2, -2, 2);
    scene.window->Render();
    return CaptureRGB(scene.window);
  };
  auto reference = touching(0.2, true, vtkSightlineTensorGlyphMapper::INTERSECT_EXACT);
  auto plainImage = touching(0.2, false, vtkSightlineTensorGlyphMapper::INTERSECT_MARCHING);
  auto refinedImage = touching(0.2, true, vtkSightlineTensorGlyphMapper::INTERSECT_MARCHING);
  // Near the centre: the square of +-30 pixels (about +-0.27 radii) holds the small lobes.
  const auto plain = Coverage(reference, plainImage, 30);
  const auto refined = Coverage(reference, refinedImage, 30);
  std::cout << "pinched glyph, step 0.2, centre square: " << plain.first << " missed / "
            << plain.second << " extra pixels without centre steps, " << refined.first << " / "
            << refined.second << " with; whole image " << Mismatch(reference, plainImage) << " / "
            << Mismatch(reference, refinedImage) << " wrong of " << CoveredPixels(reference)
            << " covered\n";
  // Finer steps near the centre are not a fix: they shift the coarse samples behind the centre
  // ball, so other thin parts are missed instead (46 vs 81 missed pixels here).
  EXPECT_GT(plain.first, 0);
  EXPECT_GT(refined.first, 0);
}

TEST(TensorGlyphMapper, BadInputIsReportedByName)
{
  auto render = [](vtkPolyData* input, void (*configure)(vtkSightlineTensorGlyphMapper*))
  {
    Scene scene(64, 64);
    vtkNew<MessageCollector> messages;
    messages->Observe(scene.mapper);
    scene.mapper->SetInputDataObject(input);
    scene.mapper->SetTensorArrayName("T");
    if (configure)
      configure(scene.mapper);
    ViewSingleGlyph(scene.renderer);
    scene.window->Render();
    return std::make_pair(std::vector<std::string>(messages->Errors), std::vector<std::string>(messages->Warnings));
  };
  auto contains = [](const std::vector<std::string>& list, const std::string& text)
  {
    for (const std::string& m : list)
      if (m.find(text) != std::string::npos)
        return true;
    return false;
  };
  auto seven = render(SinglePoint(std::vector<double>(7, 1.0)), nullptr);
  EXPECT_TRUE(contains(seven.first, "7 components")) << "no error naming the component count";
  auto wrongLayout = render(SinglePoint(std::vector<double>(15, 1.0)),
    [](vtkSightlineTensorGlyphMapper* m) { m->SetTensorLayoutToVTKSymmetric(); });
  EXPECT_TRUE(contains(wrongLayout.first, "VTKSymmetric"));
  auto ellipsoid4 = render(SinglePoint(std::vector<double>(15, 1.0)),
    [](vtkSightlineTensorGlyphMapper* m) { m->SetShapeToEllipsoid(); });
  EXPECT_TRUE(contains(ellipsoid4.first, "second-order"));
  auto missing = render(SinglePoint(std::vector<double>(6, 1.0)),
    [](vtkSightlineTensorGlyphMapper* m) { m->SetTensorArrayName("nothing"); });
  EXPECT_TRUE(contains(missing.first, "'nothing'"));
  std::vector<double> nan(15, 1.0);
  nan[3] = std::numeric_limits<double>::quiet_NaN();
  auto withNaN = render(SinglePoint(nan), nullptr);
  EXPECT_TRUE(contains(withNaN.second, "NaN")) << "no warning about the NaN tensor";
}

// A tensor array with fewer tuples than points is an error naming it, its tuple count and the
// point count, for both shapes, and nothing is drawn (it used to be read past its end, or to
// crash with 0 tuples).
TEST(TensorGlyphMapper, TensorArraysShorterThanThePointsAreErrorsNotCrashes)
{
  for (int shape : { vtkSightlineTensorGlyphMapper::SHAPE_TENSOR_FUNCTION,
         vtkSightlineTensorGlyphMapper::SHAPE_ELLIPSOID })
  {
    for (vtkIdType tuples : { 0, 4 })
    {
      vtkNew<vtkImageData> grid;
      grid->SetDimensions(3, 3, 1);
      vtkNew<vtkDoubleArray> tensors;
      tensors->SetName("T");
      tensors->SetNumberOfComponents(6);
      tensors->SetNumberOfTuples(tuples);
      tensors->Fill(1.0);
      grid->GetPointData()->AddArray(tensors);
      vtkNew<vtkSightlineTensorGlyphMapper> mapper;
      vtkNew<MessageCollector> messages;
      messages->Observe(mapper);
      mapper->SetInputDataObject(grid);
      mapper->SetTensorArrayName("T");
      mapper->SetShape(shape);
      mapper->GetBounds();
      EXPECT_EQ(mapper->GetNumberOfPrimitives(), 0);
      EXPECT_TRUE(messages->Contains(
        "tensor array 'T' has " + std::to_string(tuples) + " tuples for 9 points"))
        << "shape " << shape << ", " << tuples << " tuples";
    }
  }
}
