// SPDX-License-Identifier: BSD-3-Clause
// The mappers far from the world origin: spheres, tubes and SH glyphs placed 1e2, 1e4 and 1e6
// sizes away (at offsets float cannot hold exactly), seen by a camera moved with them, give the image and the depths they give at the
// origin. The kernel intersects each primitive in its own frame with double rays; the mappers
// hand it positions relative to a double origin (SightlineKernelConversions::ToLocalFrame).
// Before that, float world positions cost 1e-2 of a size in depth at 1e4 and misses at 1e6.
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSightlineImageRenderer.h"
#include "vtkSightlineSHGlyphMapper.h"
#include "vtkSightlineSphereMapper.h"
#include "vtkSightlineTubeMapper.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>

using namespace sightline_test;

namespace
{
constexpr int Size = 96;

struct Frame
{
  std::vector<int> rgba;
  std::vector<float> depth;
};

/// Renders the mapper's actor GL-free with a camera 8 units in front of `offset` + (0.5, 0.5, 0).
Frame Render(vtkMapper* mapper, double offset)
{
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<vtkCamera> camera;
  camera->SetFocalPoint(offset + 0.5, offset + 0.5, offset);
  camera->SetPosition(offset + 2.5, offset - 1.5, offset + 8.0);
  camera->SetViewUp(0, 1, 0);
  camera->SetViewAngle(20);
  camera->SetClippingRange(4.0, 14.0);
  vtkNew<vtkSightlineImageRenderer> image;
  image->AddActor(actor);
  image->SetActiveCamera(camera);
  image->SetSize(Size, Size);
  image->Update();
  Frame frame;
  vtkUnsignedCharArray* colors =
    vtkUnsignedCharArray::SafeDownCast(image->GetOutput()->GetPointData()->GetScalars());
  vtkFloatArray* depth =
    vtkFloatArray::SafeDownCast(image->GetOutput()->GetPointData()->GetArray("Depth"));
  EXPECT_TRUE(colors && depth);
  if (!colors || !depth)
    return frame;
  frame.rgba.assign(colors->GetPointer(0), colors->GetPointer(0) + 4 * Size * Size);
  frame.depth.assign(depth->GetPointer(0), depth->GetPointer(0) + Size * Size);
  return frame;
}

/// Renders the scene at the origin and at each offset; the same pixels must be covered, colours
/// may differ by one level, window depths by 1e-6 (a millionth of the clipping range).
void ExpectSameFarAway(const std::function<vtkSmartPointer<vtkMapper>(double)>& scene)
{
  const Frame reference = Render(scene(0.0), 0.0);
  int covered = 0;
  for (float d : reference.depth)
    covered += d < 1.0f;
  ASSERT_GT(covered, 200) << "the scene should fill part of the image";
  // Offsets and positions that float cannot hold exactly (1e6 + 0.8 rounds by 0.05).
  for (const double offset : { 123.4567, 12345.678, 1234567.8 })
  {
    const Frame far = Render(scene(offset), offset);
    ASSERT_EQ(far.depth.size(), reference.depth.size());
    int coverage = 0, colour = 0;
    double depth = 0.0;
    for (std::size_t i = 0; i < reference.depth.size(); ++i)
    {
      const bool a = reference.depth[i] < 1.0f, b = far.depth[i] < 1.0f;
      coverage += a != b;
      if (a && b)
        depth = std::max(depth, double(std::abs(reference.depth[i] - far.depth[i])));
      for (int c = 0; c < 3; ++c)
        colour += std::abs(reference.rgba[4 * i + c] - far.rgba[4 * i + c]) > 1;
    }
    EXPECT_EQ(coverage, 0) << "pixels hit at one place and not at the other, offset " << offset;
    EXPECT_EQ(colour, 0) << "colour channels off by more than one level, offset " << offset;
    EXPECT_LE(depth, 1e-6) << "window depth, offset " << offset;
  }
}
} // namespace

TEST(FarFromOrigin, SpheresLookTheSame)
{
  ExpectSameFarAway(
    [](double offset)
    {
      const std::vector<std::array<double, 3>> centres{ { offset + 0.13, offset + 0.07, offset + 0.02 },
        { offset + 1.11, offset + 0.03, offset - 0.05 }, { offset - 0.09, offset + 1.07, offset + 0.53 } };
      auto spheres = MakeSpheres(centres, { 0.45, 0.3, 0.35 });
      // Double points: float ones far away would already be rounded.
      vtkNew<vtkPoints> exact;
      exact->SetDataTypeToDouble();
      for (const auto& c : centres)
        exact->InsertNextPoint(c.data());
      spheres->SetPoints(exact);
      vtkNew<vtkSightlineSphereMapper> mapper;
      mapper->SetInputDataObject(spheres);
      mapper->SetRadiusArrayName("radius");
      return vtkSmartPointer<vtkMapper>(mapper.Get());
    });
}

TEST(FarFromOrigin, TubesLookTheSame)
{
  ExpectSameFarAway(
    [](double offset)
    {
      auto line = vtkSmartPointer<vtkPolyData>::New();
      vtkNew<vtkPoints> points;
      points->SetDataTypeToDouble(); // float points far away would already be rounded
      vtkNew<vtkCellArray> lines;
      lines->InsertNextCell(4);
      for (const auto& p : { std::array<double, 3>{ 0.03, 0.01, 0.07 }, { 1.01, 0.23, 0.01 },
             { 1.21, 1.03, 0.33 }, { 0.21, 1.13, -0.17 } })
        lines->InsertCellPoint(points->InsertNextPoint(offset + p[0], offset + p[1], offset + p[2]));
      line->SetPoints(points);
      line->SetLines(lines);
      vtkNew<vtkSightlineTubeMapper> mapper;
      mapper->SetInputDataObject(line);
      mapper->SetRadius(0.15);
      return vtkSmartPointer<vtkMapper>(mapper.Get());
    });
}

TEST(FarFromOrigin, SHGlyphsLookTheSame)
{
  ExpectSameFarAway(
    [](double offset)
    {
      // A 2 x 2 slice of order-4 glyphs (descoteaux07, 15 coefficients), 1 apart.
      auto image = vtkSmartPointer<vtkImageData>::New();
      image->SetDimensions(2, 2, 1);
      image->SetOrigin(offset + 0.03, offset + 0.07, offset + 0.01);
      vtkNew<vtkDoubleArray> sh;
      sh->SetName("SH");
      sh->SetNumberOfComponents(15);
      sh->SetNumberOfTuples(4);
      for (vtkIdType g = 0; g < 4; ++g)
        for (int c = 0; c < 15; ++c)
          sh->SetComponent(g, c, c == 0 ? 1.0 : 0.35 * std::sin(1.7 * c + 2.3 * g));
      image->GetPointData()->AddArray(sh);
      vtkNew<vtkSightlineSHGlyphMapper> mapper;
      mapper->SetInputDataObject(image);
      mapper->SetCoefficientArrayName("SH");
      mapper->SetBasisToDescoteaux07();
      return vtkSmartPointer<vtkMapper>(mapper.Get());
    });
}
