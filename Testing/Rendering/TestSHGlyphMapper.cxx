// SPDX-License-Identifier: BSD-3-Clause
// vtkSightlineSHGlyphMapper on real data: DIPY's small_64D fitted to SH (lmax 8) by
// scripts/make_sh_data.py (the SHData fixture), read with VTK's own vtkNIFTIImageReader.
//
// Independent checks: the same voxel stored by DIPY in descoteaux07 and converted to MRtrix3's
// tournier07 (verified there with MRtrix3's sh2amp) must give the same picture; glyph centres
// must land where the NIfTI header's own sform rows put the voxel; a zonal glyph's box gives
// each normalisation's radius analytically; depth compositing with a vtkImageSlice is checked
// pixel by pixel against the two layers rendered alone. Baselines (vtkTesting metric,
// threshold 0.5) cover the looks: single glyphs, a shadowed real slice, uncertainty and the
// composited scene.
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkImageProperty.h"
#include "vtkImageSlice.h"
#include "vtkImageSliceMapper.h"
#include "vtkLight.h"
#include "vtkLookupTable.h"
#include "vtkMatrix4x4.h"
#include "vtkNIFTIImageHeader.h"
#include "vtkNIFTIImageReader.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSightlineMIFReader.h"
#include "vtkSightlineSHGlyphMapper.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using namespace sightline_test;

namespace
{
const double Black[3] = { 0, 0, 0 };
const double kPi = 3.14159265358979323846;

std::string DataFile(const std::string& name)
{
  return std::string(SIGHTLINE_SH_DATA_DIR) + "/" + name;
}

vtkSmartPointer<vtkNIFTIImageReader> ReadNIfTI(const std::string& name)
{
  auto reader = vtkSmartPointer<vtkNIFTIImageReader>::New();
  reader->SetFileName(DataFile(name).c_str());
  reader->TimeAsVectorOn();
  reader->Update();
  return reader;
}

/// The voxel whose glyph is most anisotropic among the strong ones: a crossing or a sharp fibre.
vtkIdType MostAnisotropicVoxel(vtkImageData* image)
{
  vtkDataArray* sh = image->GetPointData()->GetScalars();
  double strongest = 0.0;
  for (vtkIdType i = 0; i < sh->GetNumberOfTuples(); ++i)
    strongest = std::max(strongest, sh->GetComponent(i, 0));
  vtkIdType best = -1;
  double bestRatio = -1.0;
  for (vtkIdType i = 0; i < sh->GetNumberOfTuples(); ++i)
  {
    const double c0 = sh->GetComponent(i, 0);
    if (c0 < 0.5 * strongest)
      continue;
    double rest = 0.0;
    for (int j = 1; j < sh->GetNumberOfComponents(); ++j)
      rest += sh->GetComponent(i, j) * sh->GetComponent(i, j);
    if (std::sqrt(rest) / c0 > bestRatio)
    {
      bestRatio = std::sqrt(rest) / c0;
      best = i;
    }
  }
  return best;
}

/// One glyph at the origin with the coefficients of one voxel (array "SH").
vtkSmartPointer<vtkPolyData> SingleGlyph(vtkImageData* image, vtkIdType voxel)
{
  vtkDataArray* sh = image->GetPointData()->GetScalars();
  auto glyph = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  glyph->SetPoints(points);
  vtkNew<vtkFloatArray> coefficients;
  coefficients->SetName("SH");
  coefficients->SetNumberOfComponents(sh->GetNumberOfComponents());
  coefficients->InsertNextTuple(sh->GetTuple(voxel));
  glyph->GetPointData()->AddArray(coefficients);
  return glyph;
}

using Scene = MapperScene<vtkSightlineSHGlyphMapper>;

/// Renders the voxel's glyph from the given file and basis, order-truncated.
vtkSmartPointer<vtkImageData> RenderVoxel(
  const std::string& file, bool mrtrix, vtkIdType voxel, int maximumOrder)
{
  auto reader = ReadNIfTI(file);
  auto glyph = SingleGlyph(reader->GetOutput(), voxel);
  Scene scene(240, 240);
  scene.mapper->SetInputDataObject(glyph);
  scene.mapper->SetCoefficientArrayName("SH");
  if (mrtrix)
    scene.mapper->SetBasisToMRtrix3();
  else
    scene.mapper->SetBasisToDIPY();
  scene.mapper->SetMaximumOrder(maximumOrder);
  ViewSingleGlyph(scene.renderer);
  scene.window->Render();
  return CaptureRGB(scene.window);
}

/// A light from the upper left, so that glyphs cast visible shadows on each other.
vtkSmartPointer<vtkLight> ObliqueLight(vtkRenderer* renderer)
{
  double bounds[6];
  renderer->ComputeVisiblePropBounds(bounds);
  const double center[3] = { 0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
    0.5 * (bounds[4] + bounds[5]) };
  auto light = vtkSmartPointer<vtkLight>::New();
  light->SetLightTypeToSceneLight();
  light->SetFocalPoint(center);
  light->SetPosition(center[0] - 40, center[1] + 30, center[2] + 60);
  return light;
}

/// The file's voxel axes in world axes: DIPY fits the data with the b-vectors as given, here in
/// the image's axes. vtkNIFTIImageReader's qform has its third column negated when it reversed
/// the slices (qfac -1); the file's axes need it back.
vtkSmartPointer<vtkMatrix4x4> FileAxesToWorld(vtkNIFTIImageReader* reader)
{
  auto matrix = vtkSmartPointer<vtkMatrix4x4>::New();
  matrix->DeepCopy(reader->GetQFormMatrix());
  for (int row = 0; row < 3; ++row)
    matrix->SetElement(row, 2, matrix->GetElement(row, 2) * reader->GetQFac());
  return matrix;
}

/// Glyphs of an axial slice of the real data, viewed obliquely from above.
void ViewSlice(Scene& scene, vtkNIFTIImageReader* reader)
{
  scene.mapper->SetInputConnection(reader->GetOutputPort());
  scene.mapper->SetDataToWorldMatrix(reader->GetQFormMatrix());
  scene.mapper->SetDirectionToWorldMatrix(FileAxesToWorld(reader));
  scene.mapper->SetBasisToDIPY();
  scene.mapper->SetSliceOrientationToAxial();
  scene.renderer->ResetCamera();
  vtkCamera* camera = scene.renderer->GetActiveCamera();
  camera->SetViewUp(0, 1, 0);
  camera->Elevation(-35);
  camera->OrthogonalizeViewUp();
  camera->Zoom(1.5);
  scene.renderer->ResetCameraClippingRange();
}
} // namespace

// The same voxel in DIPY's basis and in MRtrix3's (converted by DIPY, checked with sh2amp)
// gives the same picture, at k = 8 and truncated to k = 4.
TEST(SHGlyphMapper, SingleGlyphK8BothBasesAgreeAndMatchBaseline)
{
  auto reader = ReadNIfTI("small_64D_sh_descoteaux07.nii.gz");
  const vtkIdType voxel = MostAnisotropicVoxel(reader->GetOutput());
  ASSERT_GE(voxel, 0);
  auto dipy = RenderVoxel("small_64D_sh_descoteaux07.nii.gz", false, voxel, -1);
  auto mrtrix = RenderVoxel("small_64D_sh_tournier07.nii.gz", true, voxel, -1);
  int differing = 0;
  EXPECT_LE(MaxRGBDifference(dipy, mrtrix, &differing), 2);
  EXPECT_LE(differing, 20);
  EXPECT_GT(CoveredPixels(dipy), 3000);
  EXPECT_TRUE(MatchesBaseline(dipy, "SHGlyphK8", 0.5));
}

TEST(SHGlyphMapper, SingleGlyphK4BothBasesAgreeAndMatchBaseline)
{
  auto reader = ReadNIfTI("small_64D_sh_descoteaux07.nii.gz");
  const vtkIdType voxel = MostAnisotropicVoxel(reader->GetOutput());
  auto dipy = RenderVoxel("small_64D_sh_descoteaux07.nii.gz", false, voxel, 4);
  auto mrtrix = RenderVoxel("small_64D_sh_tournier07.nii.gz", true, voxel, 4);
  int differing = 0;
  EXPECT_LE(MaxRGBDifference(dipy, mrtrix, &differing), 2);
  EXPECT_LE(differing, 20);
  // Truncation changes the shape: k = 4 is not the k = 8 picture.
  auto full = RenderVoxel("small_64D_sh_descoteaux07.nii.gz", false, voxel, -1);
  EXPECT_GT(MaxRGBDifference(dipy, full), 40);
  EXPECT_TRUE(MatchesBaseline(dipy, "SHGlyphK4", 0.5));
}

// A slice of real data with soft shadows from an oblique light; shadows darken pixels that
// the unshadowed frame lights, and never brighten any.
TEST(SHGlyphMapper, RealSliceWithSoftShadowsMatchesBaseline)
{
  auto reader = ReadNIfTI("small_64D_sh_descoteaux07.nii.gz");
  Scene scene(400, 400);
  ViewSlice(scene, reader);
  scene.renderer->AddLight(ObliqueLight(scene.renderer));
  scene.window->Render();
  auto lit = CaptureRGB(scene.window);
  scene.mapper->SetShadowModeToSoft();
  scene.window->Render();
  auto shadowed = CaptureRGB(scene.window);

  int darker = 0, brighter = 0;
  for (int y = 0; y < 400; ++y)
    for (int x = 0; x < 400; ++x)
    {
      const auto a = Pixel(lit, x, y), b = Pixel(shadowed, x, y);
      const int da = a[0] + a[1] + a[2], db = b[0] + b[1] + b[2];
      darker += db < da - 6;
      brighter += db > da + 3;
    }
  EXPECT_GT(darker, 300) << "soft shadows should darken a visible part of the slice";
  EXPECT_EQ(brighter, 0);
  EXPECT_TRUE(MatchesBaseline(shadowed, "SHGlyphSliceSoftShadows", 0.5));
}

// Uncertainty glyphs blend every pixel they cover towards grey: pixels change only where
// the uncertainty volume lies, and move towards (0.5, 0.5, 0.5).
TEST(SHGlyphMapper, UncertaintyVolumeBlendsTowardsGreyAndMatchesBaseline)
{
  auto reader = ReadNIfTI("small_64D_sh_descoteaux07.nii.gz");
  auto uncertaintyReader = ReadNIfTI("small_64D_sh_uncertainty_descoteaux07.nii.gz");
  vtkNew<vtkImageData> image;
  image->ShallowCopy(reader->GetOutput());
  vtkDataArray* uncertainty = uncertaintyReader->GetOutput()->GetPointData()->GetScalars();
  uncertainty->SetName("uncertainty");
  image->GetPointData()->AddArray(uncertainty);

  Scene scene(400, 400);
  scene.mapper->SetInputDataObject(image);
  scene.mapper->SetDataToWorldMatrix(reader->GetQFormMatrix());
  scene.mapper->SetDirectionToWorldMatrix(FileAxesToWorld(reader));
  scene.mapper->SetBasisToDIPY();
  scene.renderer->ResetCamera();
  scene.renderer->GetActiveCamera()->Zoom(1.5);
  scene.window->Render();
  auto plain = CaptureRGB(scene.window);
  scene.mapper->SetUncertaintyArrayName("uncertainty");
  scene.mapper->SetUncertaintyExtinction(1.5);
  scene.window->Render();
  auto uncertain = CaptureRGB(scene.window);

  int changed = 0, towardsGrey = 0;
  for (int y = 0; y < 400; ++y)
    for (int x = 0; x < 400; ++x)
    {
      const auto a = Pixel(plain, x, y), b = Pixel(uncertain, x, y);
      double before = 0.0, after = 0.0;
      bool differs = false;
      for (int c = 0; c < 3; ++c)
      {
        before += std::abs(a[c] - 127.5);
        after += std::abs(b[c] - 127.5);
        differs = differs || std::abs(a[c] - b[c]) > 2;
      }
      changed += differs;
      towardsGrey += differs && after < before;
    }
  EXPECT_GT(changed, 1000);
  EXPECT_GE(towardsGrey, int(0.99 * changed));
  EXPECT_TRUE(MatchesBaseline(uncertain, "SHGlyphUncertainty", 0.5));
}

// Glyphs and an anatomical slice (vtkImageSlice, same data, same affine) composite by depth:
// every pixel shows the layer that is nearer when each is rendered alone.
TEST(SHGlyphMapper, CompositesWithImageSliceByDepth)
{
  auto reader = ReadNIfTI("small_64D_sh_descoteaux07.nii.gz");
  auto fa = ReadNIfTI("small_64D_fa.nii.gz");
  Scene scene(400, 400);
  ViewSlice(scene, reader);
  scene.window->Render();
  const int slice = scene.mapper->GetDrawnExtent()[4];
  ASSERT_EQ(scene.mapper->GetSliceAxis(), 2);

  vtkNew<vtkImageSliceMapper> sliceMapper;
  sliceMapper->SetInputConnection(fa->GetOutputPort());
  sliceMapper->SetOrientation(2);
  sliceMapper->SetSliceNumber(slice);
  vtkNew<vtkImageSlice> anatomy;
  anatomy->SetMapper(sliceMapper);
  anatomy->SetUserMatrix(fa->GetQFormMatrix());
  anatomy->GetProperty()->SetColorWindow(1.0);
  anatomy->GetProperty()->SetColorLevel(0.5);
  anatomy->GetProperty()->SetInterpolationTypeToNearest();

  // Each layer alone, then both.
  auto glyphColor = CaptureRGB(scene.window);
  auto glyphDepth = CaptureDepth(scene.window);
  scene.actor->VisibilityOff();
  scene.renderer->AddViewProp(anatomy);
  scene.window->Render();
  auto sliceColor = CaptureRGB(scene.window);
  auto sliceDepth = CaptureDepth(scene.window);
  scene.actor->VisibilityOn();
  scene.window->Render();
  auto both = CaptureRGB(scene.window);

  auto depth = [](vtkImageData* image, int x, int y)
  { return image->GetScalarComponentAsDouble(x, y, 0, 0); };
  int glyphInFront = 0, sliceInFront = 0, wrong = 0;
  for (int y = 0; y < 400; ++y)
    for (int x = 0; x < 400; ++x)
    {
      const double g = depth(glyphDepth, x, y), s = depth(sliceDepth, x, y);
      if (std::abs(g - s) < 1e-3 || (g >= 1.0 && s >= 1.0))
        continue; // too close to call, or background
      const auto expected = g < s ? Pixel(glyphColor, x, y) : Pixel(sliceColor, x, y);
      const auto actual = Pixel(both, x, y);
      int d = 0;
      for (int c = 0; c < 3; ++c)
        d = std::max(d, std::abs(expected[c] - actual[c]));
      (g < s ? glyphInFront : sliceInFront) += 1;
      wrong += d > 2;
    }
  EXPECT_GT(glyphInFront, 2000) << "glyph halves above the slice";
  EXPECT_GT(sliceInFront, 2000) << "the slice hides the lower halves and the background";
  EXPECT_LE(wrong, (glyphInFront + sliceInFront) / 200);
  EXPECT_TRUE(MatchesBaseline(both, "SHGlyphWithImageSlice", 0.5));
}

// The same scene through vtkSightlineImageRenderer (no OpenGL) and in a window.
TEST(SHGlyphMapper, WindowAndGLFreeAgree)
{
  auto reader = ReadNIfTI("small_64D_sh_descoteaux07.nii.gz");
  Scene scene(320, 240);
  ViewSlice(scene, reader);
  scene.mapper->SetNegativeLobesToColor();
  scene.window->Render();
  auto window = CaptureRGB(scene.window);
  auto glFree = RenderWithoutGL({ scene.actor }, scene.renderer->GetActiveCamera(), 320, 240, Black);
  int differing = 0;
  EXPECT_LE(MaxRGBDifference(window, glFree, &differing), 1);
  EXPECT_GT(CoveredPixels(window), 5000);
}

// Slices follow the affine (small_64D's voxel axes are permuted and rotated), boxes are cached
// per voxel, and an extent shows every voxel of it.
TEST(SHGlyphMapper, SlicesFollowTheAffineAndReuseCachedBoxes)
{
  auto reader = ReadNIfTI("small_64D_sh_descoteaux07.nii.gz");
  vtkNew<vtkSightlineSHGlyphMapper> mapper;
  mapper->SetInputConnection(reader->GetOutputPort());
  mapper->SetDataToWorldMatrix(reader->GetQFormMatrix());

  // The voxel axis whose world direction is closest to z, y and x.
  vtkMatrix4x4* q = reader->GetQFormMatrix();
  auto closest = [&](int world)
  {
    int best = 0;
    for (int axis = 1; axis < 3; ++axis)
      if (std::abs(q->GetElement(world, axis)) > std::abs(q->GetElement(world, best)))
        best = axis;
    return best;
  };
  mapper->SetSliceOrientationToAxial();
  EXPECT_EQ(mapper->GetSliceAxis(), closest(2));
  mapper->SetSliceOrientationToCoronal();
  EXPECT_EQ(mapper->GetSliceAxis(), closest(1));
  mapper->SetSliceOrientationToSagittal();
  EXPECT_EQ(mapper->GetSliceAxis(), closest(0));
  EXPECT_NE(closest(0), closest(1));
  EXPECT_NE(closest(1), closest(2));

  mapper->SetSliceOrientationToAxial();
  mapper->SetSliceNumber(4);
  mapper->GetBounds();
  const vtkIdType first = mapper->GetLastComputedBoxes();
  EXPECT_EQ(first, mapper->GetNumberOfPrimitives());
  EXPECT_GT(first, 20);
  const int axis = mapper->GetSliceAxis();
  EXPECT_EQ(mapper->GetDrawnExtent()[2 * axis], 4);
  EXPECT_EQ(mapper->GetDrawnExtent()[2 * axis + 1], 4);

  mapper->SetSliceNumber(5);
  mapper->GetBounds();
  EXPECT_GT(mapper->GetLastComputedBoxes(), 0);
  // Back to slice 4, another scale and normalisation: every box comes from the cache.
  mapper->SetSliceNumber(4);
  mapper->SetScaleFactor(0.7);
  mapper->SetNormalizationToCoefficientNorm();
  mapper->GetBounds();
  EXPECT_EQ(mapper->GetLastComputedBoxes(), 0);
  EXPECT_EQ(mapper->GetNumberOfPrimitives(), first);

  // An extent of 2 x 3 x 2 voxels; a mask from the data generator removes background.
  mapper->SetSliceOrientationToExtent();
  mapper->SetDisplayExtent(3, 4, 3, 5, 4, 5);
  mapper->GetBounds();
  EXPECT_LE(mapper->GetNumberOfPrimitives(), 12);
  EXPECT_EQ(mapper->GetDrawnExtent()[1], 4);
  EXPECT_EQ(mapper->GetDrawnExtent()[3], 5);
}

// Frustum culling on the whole volume: a close-up boxes only the glyphs in view and draws the
// same picture as without culling; a still frame that shows more boxes those then (an
// interactive one does not ask for it).
TEST(SHGlyphMapper, FrustumCullingBoxesOnlyWhatTheViewShows)
{
  auto reader = ReadNIfTI("small_64D_sh_descoteaux07.nii.gz");
  Scene culled(240, 180), plain(240, 180);
  for (Scene* scene : { &culled, &plain })
  {
    scene->mapper->SetInputConnection(reader->GetOutputPort());
    scene->mapper->SetDataToWorldMatrix(reader->GetQFormMatrix());
    scene->mapper->SetDirectionToWorldMatrix(FileAxesToWorld(reader));
    scene->mapper->SetBasisToDIPY();
    scene->mapper->SetSliceOrientationToExtent();
  }
  culled.mapper->FrustumCullingOn();
  EXPECT_FALSE(plain.mapper->GetFrustumCulling());
  // One camera for both, framed on the plain mapper's (tight) bounds, then a close-up.
  plain.renderer->ResetCamera();
  vtkCamera* camera = plain.renderer->GetActiveCamera();
  camera->Elevation(-30);
  camera->OrthogonalizeViewUp();
  camera->Zoom(10.0);
  plain.renderer->ResetCameraClippingRange();
  culled.renderer->GetActiveCamera()->DeepCopy(camera);

  auto renderBoth = [&](const char* view)
  {
    SCOPED_TRACE(view);
    culled.window->Render();
    plain.window->Render();
    auto a = CaptureRGB(culled.window), b = CaptureRGB(plain.window);
    EXPECT_LE(MaxRGBDifference(a, b), 1);
    EXPECT_GT(CoveredPixels(b), 2000);
  };
  renderBoth("close-up");
  const vtkIdType total = plain.mapper->GetNumberOfPrimitives();
  EXPECT_EQ(culled.mapper->GetNumberOfPrimitives(), total);
  EXPECT_EQ(plain.mapper->GetLastLooseBoxes(), 0);
  EXPECT_GT(total, 500);
  EXPECT_GT(culled.mapper->GetLastLooseBoxes(), total / 2) << "the close-up sees a small part";
  EXPECT_EQ(culled.mapper->GetLastComputedBoxes() + culled.mapper->GetLastLooseBoxes(), total);
  EXPECT_GT(culled.mapper->GetLastComputedBoxes(), 0);
  std::cout << "[ culling  ] close-up of " << total << " glyphs: " << culled.mapper->GetLastComputedBoxes()
            << " boxes computed, " << culled.mapper->GetLastLooseBoxes() << " loose" << std::endl;

  // Zoomed out: an interactive view keeps the loose boxes, a still one computes them.
  camera->Zoom(0.1);
  plain.renderer->ResetCameraClippingRange();
  culled.renderer->GetActiveCamera()->DeepCopy(camera);
  const vtkMTimeType before = culled.mapper->GetMTime();
  culled.mapper->SetView(culled.actor, culled.renderer->GetActiveCamera(), 240.0 / 180.0, true);
  EXPECT_EQ(culled.mapper->GetMTime(), before);
  const vtkIdType loose = culled.mapper->GetLastLooseBoxes();
  renderBoth("whole field");
  EXPECT_EQ(culled.mapper->GetLastLooseBoxes(), 0);
  EXPECT_EQ(culled.mapper->GetLastComputedBoxes(), loose) << "only the boxes not seen before";
}

// Glyph centres are where the NIfTI header's sform rows put the voxels (read raw here, not
// through the reader's qform/slice handling), with the affine given as DataToWorldMatrix.
TEST(SHGlyphMapper, CentresFollowTheNIfTIAffine)
{
  auto reader = ReadNIfTI("small_64D_sh_descoteaux07.nii.gz");
  vtkNIFTIImageHeader* header = reader->GetNIFTIHeader();
  double rows[3][4];
  header->GetSRowX(rows[0]);
  header->GetSRowY(rows[1]);
  header->GetSRowZ(rows[2]);
  const int dims[3] = { int(header->GetDim(1)), int(header->GetDim(2)), int(header->GetDim(3)) };

  vtkImageData* image = reader->GetOutput();
  vtkNew<vtkSightlineSHGlyphMapper> mapper;
  mapper->SetInputDataObject(image);
  mapper->SetDataToWorldMatrix(reader->GetQFormMatrix());
  mapper->SetSliceOrientationToExtent();
  mapper->SetNormalizationToMaxAmplitude();
  mapper->SetScaleFactor(0.2);

  // Try voxels until a non-background one is found; its glyph's box centre is the voxel.
  int checked = 0;
  for (int n = 0; n < 40 && checked < 3; ++n)
  {
    const int i = (3 + 7 * n) % dims[0], j = (5 + 3 * n) % dims[1], k = (4 + n) % dims[2];
    // vtkNIFTIImageReader stores slices in reverse when qfac is -1.
    const int vtkK = reader->GetQFac() < 0 ? dims[2] - 1 - k : k;
    mapper->SetDisplayExtent(i, i, j, j, vtkK, vtkK);
    double* bounds = mapper->GetBounds();
    if (!vtkMath::AreBoundsInitialized(bounds) || mapper->GetNumberOfPrimitives() != 1)
      continue;
    for (int axis = 0; axis < 3; ++axis)
    {
      const double expected = rows[axis][0] * i + rows[axis][1] * j + rows[axis][2] * k + rows[axis][3];
      EXPECT_NEAR(0.5 * (bounds[2 * axis] + bounds[2 * axis + 1]), expected, 1e-3)
        << "voxel " << i << " " << j << " " << k << " axis " << axis;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 3);
}

// A zonal glyph c00 Y00 + c20 Y20 peaks on the z axis, where its box's half height is the
// padded radius: every normalisation's radius is checked analytically.
TEST(SHGlyphMapper, NormalisationsGiveTheAnalyticRadius)
{
  vtkNew<vtkPolyData> glyphs;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  points->InsertNextPoint(10, 0, 0);
  glyphs->SetPoints(points);
  vtkNew<vtkDoubleArray> sh;
  sh->SetName("SH");
  sh->SetNumberOfComponents(6);
  const double y00 = 0.5 / std::sqrt(kPi), y20 = std::sqrt(5.0 / (4.0 * kPi));
  const double first[6] = { 1.0, 0, 0, 0.8, 0, 0 }, second[6] = { 0.5, 0, 0, 0.4, 0, 0 };
  sh->InsertNextTuple(first);
  sh->InsertNextTuple(second);
  glyphs->GetPointData()->AddArray(sh);
  const double pole = 1.0 * y00 + 0.8 * y20; // |F| on the z axis of the first glyph
  const double padding = 1.025;              // the box margin of Peters et al., Sec. 4.2

  vtkNew<vtkSightlineSHGlyphMapper> mapper;
  mapper->SetInputDataObject(glyphs);
  mapper->SetCoefficientArrayName("SH");
  mapper->SetBasisToMRtrix3();
  mapper->SetScaleFactor(2.0);
  auto heights = [&]()
  {
    double* b = mapper->GetBounds();
    return 0.5 * (b[5] - b[4]); // both glyphs are centred at z = 0: the taller one decides
  };
  mapper->SetNormalizationToNone();
  EXPECT_NEAR(heights(), padding * 2.0 * pole, 1e-4);
  mapper->SetNormalizationToMaxAmplitude();
  EXPECT_NEAR(heights(), padding * 2.0, 1e-4);
  mapper->SetNormalizationToCoefficientNorm();
  EXPECT_NEAR(heights(), padding * 2.0 * pole / std::sqrt(1.0 + 0.64), 1e-4);
  mapper->SetNormalizationToGlobal();
  EXPECT_NEAR(heights(), padding * 2.0, 1e-4);
  // With the global normalisation the second glyph keeps half the first one's size.
  double* b = mapper->GetBounds();
  EXPECT_NEAR(b[1] - 10.0, 0.5 * -b[0], 1e-4);
}

// Colour by a scalar array through the lookup table; negative lobes coloured or hidden.
TEST(SHGlyphMapper, ScalarColouringAndNegativeLobes)
{
  vtkNew<vtkPolyData> glyphs;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  glyphs->SetPoints(points);
  vtkNew<vtkDoubleArray> sh;
  sh->SetName("SH");
  sh->SetNumberOfComponents(6);
  // F = 0.2 Y00 - 1.0 Y20: negative along z (a polar lobe pair), positive around the equator.
  const double c[6] = { 0.2, 0, 0, -1.0, 0, 0 };
  sh->InsertNextTuple(c);
  glyphs->GetPointData()->AddArray(sh);
  vtkNew<vtkDoubleArray> value;
  value->SetName("value");
  value->InsertNextValue(1.0);
  glyphs->GetPointData()->AddArray(value);

  Scene scene(200, 200);
  scene.mapper->SetInputDataObject(glyphs);
  scene.mapper->SetCoefficientArrayName("SH");
  scene.mapper->SetNormalizationToMaxAmplitude();
  vtkCamera* camera = scene.renderer->GetActiveCamera();
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(10, 0, 0); // looking along -x: the polar lobes are above and below
  camera->SetViewUp(0, 0, 1);
  camera->ParallelProjectionOn();
  camera->SetParallelScale(1.2);
  scene.renderer->ResetCameraClippingRange(-2, 2, -2, 2, -2, 2);
  const int topX = 100, topY = 100 + 60; // on the upper (negative) lobe

  scene.mapper->SetNegativeLobesToColor();
  scene.mapper->SetNegativeLobeColor(1, 0, 0);
  scene.mapper->SetColoringToSolid();
  scene.actor->GetProperty()->SetColor(0, 1, 0);
  scene.actor->GetProperty()->SetSpecular(0.0);
  scene.window->Render();
  auto colored = CaptureRGB(scene.window);
  auto top = Pixel(colored, topX, topY);
  EXPECT_GT(top[0], 100);
  EXPECT_LT(top[1], 30);

  scene.mapper->SetNegativeLobesToHide();
  scene.window->Render();
  top = Pixel(CaptureRGB(scene.window), topX, topY);
  EXPECT_EQ(top[0] + top[1] + top[2], 0);

  // Scalar colouring: the lookup table's colour for 1.0 in [0, 1] is pure blue here.
  vtkNew<vtkLookupTable> lut;
  lut->SetHueRange(0.667, 0.667);
  lut->SetSaturationRange(1, 1);
  lut->SetValueRange(1, 1);
  lut->Build();
  scene.mapper->SetLookupTable(lut);
  scene.mapper->SetScalarRange(0, 1);
  scene.mapper->SetScalarModeToUsePointFieldData();
  scene.mapper->SelectColorArray("value");
  scene.mapper->SetColoringToScalars();
  scene.mapper->SetNegativeLobesToShow();
  scene.actor->GetProperty()->SetAmbient(1.0);
  scene.actor->GetProperty()->SetDiffuse(0.0);
  scene.actor->GetProperty()->SetSpecular(0.0);
  scene.window->Render();
  const auto equator = Pixel(CaptureRGB(scene.window), 100 + 30, 100);
  EXPECT_LE(equator[0], 2);
  EXPECT_LE(equator[1], 2);
  EXPECT_GE(equator[2], 253);
}

// Bad input is reported by name; nothing crashes; valid glyphs still render.
TEST(SHGlyphMapper, BadInputIsReportedByName)
{
  vtkNew<MessageCollector> messages;
  auto check = [&](vtkDataObject* input, const char* array, const std::string& fragment)
  {
    vtkNew<vtkSightlineSHGlyphMapper> mapper;
    messages->Errors.clear();
    messages->Warnings.clear();
    messages->Observe(mapper);
    mapper->SetInputDataObject(input);
    mapper->SetCoefficientArrayName(array);
    mapper->GetBounds();
    EXPECT_TRUE(messages->Contains(fragment)) << "expected a message containing '" << fragment << "'";
    return mapper->GetNumberOfPrimitives();
  };

  vtkNew<vtkPolyData> glyphs;
  vtkNew<vtkPoints> points;
  for (int i = 0; i < 3; ++i)
    points->InsertNextPoint(3.0 * i, 0, 0);
  glyphs->SetPoints(points);
  vtkNew<vtkFloatArray> wrong;
  wrong->SetName("wrong");
  wrong->SetNumberOfComponents(44);
  wrong->SetNumberOfTuples(3);
  wrong->Fill(0.1f);
  glyphs->GetPointData()->AddArray(wrong);
  vtkNew<vtkFloatArray> sh;
  sh->SetName("SH");
  sh->SetNumberOfComponents(45);
  sh->SetNumberOfTuples(3);
  sh->Fill(0.0f);
  for (int i = 0; i < 3; ++i)
  {
    sh->SetComponent(i, 0, 1.0f);
    sh->SetComponent(i, 3, 0.5f);
  }
  sh->SetComponent(1, 7, std::numeric_limits<float>::quiet_NaN());
  glyphs->GetPointData()->AddArray(sh);

  EXPECT_EQ(check(glyphs, "wrong", "'wrong' has 44 components"), 0);
  EXPECT_TRUE(messages->Contains("45 (order 8)"));
  EXPECT_EQ(check(glyphs, "missing", "'missing'"), 0);
  EXPECT_EQ(check(glyphs, "SH", "at point 1"), 2); // the NaN glyph is skipped, two render

  // An empty input is no error (ParaView creates mappers before data arrives): nothing is
  // drawn and nothing said (TestMapperInput checks every mapper and kind of emptiness).
  {
    vtkNew<vtkImageData> empty;
    vtkNew<vtkSightlineSHGlyphMapper> mapper;
    messages->Errors.clear();
    messages->Warnings.clear();
    messages->Observe(mapper);
    mapper->SetInputDataObject(empty);
    mapper->SetCoefficientArrayName("SH");
    mapper->GetBounds();
    EXPECT_EQ(mapper->GetNumberOfPrimitives(), 0);
    EXPECT_TRUE(messages->Errors.empty() && messages->Warnings.empty());
  }

  vtkNew<vtkSightlineSHGlyphMapper> mapper;
  messages->Errors.clear();
  messages->Observe(mapper);
  EXPECT_FALSE(mapper->SetBasisByName("spherical-bessel"));
  EXPECT_TRUE(messages->Contains("spherical-bessel"));
  EXPECT_EQ(std::string(mapper->GetBasisAsString()), "descoteaux07");
  EXPECT_TRUE(mapper->SetBasisByName("tournier07"));
  EXPECT_EQ(mapper->GetBasis(), vtkSightlineSHGlyphMapper::TOURNIER07);

  // A missing mask and a bad scale are errors; a wrong uncertainty array leaves the glyphs.
  mapper->SetInputDataObject(glyphs);
  mapper->SetCoefficientArrayName("SH");
  mapper->SetMaskArrayName("nomask");
  mapper->SetUncertaintyArrayName("wrong");
  mapper->GetBounds();
  EXPECT_TRUE(messages->Contains("'nomask'"));
  EXPECT_TRUE(messages->Contains("uncertainty array 'wrong' has 44 components"));
  EXPECT_EQ(mapper->GetNumberOfPrimitives(), 2);
  mapper->SetScaleFactor(-1.0);
  mapper->GetBounds();
  EXPECT_TRUE(messages->Contains("ScaleFactor must be positive"));
  EXPECT_EQ(mapper->GetNumberOfPrimitives(), 0);

  std::ostringstream print;
  mapper->Print(print);
  EXPECT_NE(print.str().find("Normalization: MaxAmplitude"), std::string::npos);
}

// Box computation and the frame both report progress, each ending at 1.
TEST(SHGlyphMapper, ReportsProgress)
{
  auto reader = ReadNIfTI("small_64D_sh_descoteaux07.nii.gz");
  Scene scene(200, 200);
  std::vector<double> fractions;
  vtkNew<vtkCallbackCommand> progress;
  progress->SetClientData(&fractions);
  progress->SetCallback([](vtkObject*, unsigned long, void* client, void* data)
    { static_cast<std::vector<double>*>(client)->push_back(*static_cast<double*>(data)); });
  scene.mapper->AddObserver(vtkCommand::ProgressEvent, progress);
  ViewSlice(scene, reader);
  const std::size_t afterBoxes = fractions.size();
  ASSERT_GE(afterBoxes, 1u);
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  scene.window->Render();
  ASSERT_GT(fractions.size(), afterBoxes + 1);
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
}

// Directions in the image's axes turn with DirectionToWorldMatrix: a prolate zonal glyph along the data's
// z axis lies along world x when DataToWorldMatrix maps z to x (and stays along z when the
// directions are taken as world directions). A scaled matrix (sform-like) does not distort it.
TEST(SHGlyphMapper, DirectionFrameTurnsGlyphsWithTheImage)
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(1, 1, 1);
  vtkNew<vtkDoubleArray> sh;
  sh->SetNumberOfComponents(6);
  const double zonal[6] = { 1.0, 0, 0, 0.8, 0, 0 };
  sh->InsertNextTuple(zonal);
  image->GetPointData()->SetScalars(sh);
  vtkNew<vtkMatrix4x4> zToX; // columns: data x -> world -y, data y -> world z, data z -> world x
  const double elements[16] = { 0, 0, 3, 5, -3, 0, 0, 0, 0, 3, 0, 0, 0, 0, 0, 1 };
  zToX->DeepCopy(elements);

  vtkNew<vtkSightlineSHGlyphMapper> mapper;
  mapper->SetInputDataObject(image);
  mapper->SetBasisToMRtrix3();
  mapper->SetDataToWorldMatrix(zToX);
  auto halfSizes = [&]()
  {
    double* b = mapper->GetBounds();
    return std::array<double, 3>{ 0.5 * (b[1] - b[0]), 0.5 * (b[3] - b[2]), 0.5 * (b[5] - b[4]) };
  };
  const auto world = halfSizes();
  EXPECT_GT(world[2], 1.3 * world[0]);
  EXPECT_NEAR(world[0], world[1], 1e-4);
  mapper->SetDirectionToWorldMatrix(zToX);
  const auto data = halfSizes();
  EXPECT_NEAR(data[0], world[2], 1e-4);
  EXPECT_NEAR(data[1], world[0], 1e-4);
  EXPECT_NEAR(data[2], world[1], 1e-4);
  double* b = mapper->GetBounds();
  EXPECT_NEAR(0.5 * (b[0] + b[1]), 5.0, 1e-5); // the centre moved by the matrix
}

// MRtrix3's own file format through vtkSightlineMIFReader (the gzipped copy is stored with
// reversed, permuted strides) gives the same slice of glyphs as the equivalent NIfTI.
TEST(SHGlyphMapper, MRtrixFileGivesTheSameGlyphsAsTheNIfTI)
{
  auto nifti = ReadNIfTI("small_64D_sh_tournier07.nii.gz");
  Scene fromNIfTI(300, 300);
  ViewSlice(fromNIfTI, nifti);
  fromNIfTI.mapper->SetBasisToMRtrix3();
  fromNIfTI.window->Render();
  auto expected = CaptureRGB(fromNIfTI.window);

  vtkNew<vtkSightlineMIFReader> mif;
  mif->SetFileName(DataFile("small_64D_sh_tournier07.mif.gz").c_str());
  mif->Update();
  vtkNew<vtkMatrix4x4> axes; // the file's axes, as FileAxesToWorld does for the NIfTI reader
  axes->DeepCopy(mif->GetTransformMatrix());
  for (int row = 0; row < 3; ++row)
    axes->SetElement(row, 2, axes->GetElement(row, 2) * (mif->GetSlicesReversed() ? -1 : 1));
  Scene fromMIF(300, 300);
  fromMIF.mapper->SetInputConnection(mif->GetOutputPort());
  fromMIF.mapper->SetDataToWorldMatrix(mif->GetTransformMatrix());
  fromMIF.mapper->SetDirectionToWorldMatrix(axes);
  fromMIF.mapper->SetBasisToMRtrix3();
  fromMIF.renderer->SetActiveCamera(fromNIfTI.renderer->GetActiveCamera());
  fromMIF.window->Render();
  EXPECT_EQ(fromMIF.mapper->GetNumberOfPrimitives(), fromNIfTI.mapper->GetNumberOfPrimitives());
  EXPECT_LE(MaxRGBDifference(CaptureRGB(fromMIF.window), expected), 1);
  EXPECT_GT(CoveredPixels(expected), 5000);
}

// Every point array must describe every point: a coefficient or uncertainty array with fewer
// tuples than points is an error naming it, its tuple count and the point count, and nothing
// is drawn (it used to be read past its end, or to crash with 0 tuples). A short mask is an
// error too, and the glyphs are drawn without it.
TEST(SHGlyphMapper, ArraysShorterThanThePointsAreErrorsNotCrashes)
{
  auto array = [](const char* name, vtkIdType tuples)
  {
    auto values = vtkSmartPointer<vtkFloatArray>::New();
    values->SetName(name);
    values->SetNumberOfComponents(6);
    values->SetNumberOfTuples(tuples);
    values->Fill(0.0f);
    for (vtkIdType i = 0; i < tuples; ++i)
      values->SetComponent(i, 0, 1.0f);
    return values;
  };
  auto image = [&](vtkIdType coefficientTuples)
  {
    auto grid = vtkSmartPointer<vtkImageData>::New();
    grid->SetDimensions(3, 3, 1);
    grid->GetPointData()->AddArray(array("SH", coefficientTuples));
    return grid;
  };
  vtkNew<MessageCollector> messages;
  auto build = [&](vtkDataObject* input, const char* uncertainty, const char* mask)
  {
    vtkNew<vtkSightlineSHGlyphMapper> mapper;
    messages->Errors.clear();
    messages->Warnings.clear();
    messages->Observe(mapper);
    mapper->SetInputDataObject(input);
    mapper->SetCoefficientArrayName("SH");
    mapper->SetUncertaintyArrayName(uncertainty);
    mapper->SetMaskArrayName(mask);
    mapper->GetBounds();
    return mapper->GetNumberOfPrimitives();
  };

  for (vtkIdType tuples : { 0, 4 })
  {
    const std::string count = std::to_string(tuples) + " tuples for 9 points";
    EXPECT_EQ(build(image(tuples), nullptr, nullptr), 0);
    EXPECT_TRUE(messages->Contains("coefficient array 'SH' has " + count)) << tuples;

    auto withUncertainty = image(9);
    withUncertainty->GetPointData()->AddArray(array("U", tuples));
    EXPECT_EQ(build(withUncertainty, "U", nullptr), 0);
    EXPECT_TRUE(messages->Contains("uncertainty array 'U' has " + count)) << tuples;

    auto withMask = image(9);
    withMask->GetPointData()->AddArray(array("M", tuples));
    EXPECT_EQ(build(withMask, nullptr, "M"), 9) << "a short mask is ignored, not read";
    EXPECT_TRUE(messages->Contains("mask array 'M' has " + count)) << tuples;
  }

  // Any data set, not only images: three points, two coefficient tuples.
  vtkNew<vtkPolyData> glyphs;
  vtkNew<vtkPoints> points;
  for (int i = 0; i < 3; ++i)
    points->InsertNextPoint(3.0 * i, 0, 0);
  glyphs->SetPoints(points);
  glyphs->GetPointData()->AddArray(array("SH", 2));
  EXPECT_EQ(build(glyphs, nullptr, nullptr), 0);
  EXPECT_TRUE(messages->Contains("'SH' has 2 tuples for 3 points"));
}
