// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkRenderWindow.h"
#include "vtkSightlineImageRenderer.h"
#include "vtkTesting.h"
#include "vtkTrivialProducer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include "sightline/core/Framebuffer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>

namespace sightline_test
{
vtkSmartPointer<vtkPolyData> MakeSpheres(
  const std::vector<std::array<double, 3>>& centers, const std::vector<double>& radii)
{
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> radius;
  radius->SetName("radius");
  vtkNew<vtkDoubleArray> value;
  value->SetName("value");
  for (std::size_t i = 0; i < centers.size(); ++i)
  {
    points->InsertNextPoint(centers[i].data());
    if (!radii.empty())
    {
      radius->InsertNextValue(radii[i]);
    }
    value->InsertNextValue(double(i));
  }
  auto polydata = vtkSmartPointer<vtkPolyData>::New();
  polydata->SetPoints(points);
  if (!radii.empty())
  {
    polydata->GetPointData()->AddArray(radius);
  }
  polydata->GetPointData()->AddArray(value);
  return polydata;
}

vtkSmartPointer<vtkCamera> MakeCamera(bool parallel, double distance, double scale)
{
  auto camera = vtkSmartPointer<vtkCamera>::New();
  camera->SetPosition(0, 0, distance);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetViewUp(0, 1, 0);
  camera->SetParallelProjection(parallel);
  camera->SetParallelScale(scale);
  camera->SetViewAngle(30);
  camera->SetClippingRange(distance - 4.0, distance + 4.0);
  return camera;
}

vtkSmartPointer<vtkImageData> CaptureRGB(vtkRenderWindow* window)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grab->GetOutput());
  return image;
}

vtkSmartPointer<vtkImageData> CaptureDepth(vtkRenderWindow* window)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToZBuffer();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grab->GetOutput());
  return image;
}

vtkSmartPointer<vtkImageData> RenderWithoutGL(const std::vector<vtkActor*>& actors,
  vtkCamera* camera, int width, int height, const double background[3])
{
  vtkNew<vtkSightlineImageRenderer> renderer;
  for (vtkActor* actor : actors)
  {
    renderer->AddActor(actor);
  }
  renderer->SetActiveCamera(camera);
  renderer->SetSize(width, height);
  renderer->SetBackground(background[0], background[1], background[2]);
  renderer->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(renderer->GetOutput());
  return image;
}

std::array<int, 3> Pixel(vtkImageData* image, int x, int y)
{
  auto* scalars = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  const int components = scalars->GetNumberOfComponents();
  const int* extent = image->GetExtent();
  const vtkIdType index = vtkIdType(y - extent[2]) * (extent[1] - extent[0] + 1) + (x - extent[0]);
  const unsigned char* p = scalars->GetPointer(index * components);
  return { p[0], p[1], p[2] };
}

int CoveredPixels(vtkImageData* image)
{
  int dims[3];
  image->GetDimensions(dims);
  int covered = 0;
  for (int y = 0; y < dims[1]; ++y)
    for (int x = 0; x < dims[0]; ++x)
    {
      const auto p = Pixel(image, x, y);
      covered += (p[0] + p[1] + p[2]) > 0;
    }
  return covered;
}

int MaxRGBDifference(vtkImageData* a, vtkImageData* b, int* differingPixels)
{
  int dims[3], dimsB[3];
  a->GetDimensions(dims);
  b->GetDimensions(dimsB);
  if (dims[0] != dimsB[0] || dims[1] != dimsB[1])
  {
    return 256;
  }
  int largest = 0, differing = 0;
  for (int y = 0; y < dims[1]; ++y)
  {
    for (int x = 0; x < dims[0]; ++x)
    {
      const auto pa = Pixel(a, x, y);
      const auto pb = Pixel(b, x, y);
      int d = 0;
      for (int c = 0; c < 3; ++c)
      {
        d = std::max(d, std::abs(pa[c] - pb[c]));
      }
      largest = std::max(largest, d);
      differing += d > 0;
    }
  }
  if (differingPixels)
  {
    *differingPixels = differing;
  }
  return largest;
}

bool MatchesBaseline(vtkImageData* image, const std::string& name, double threshold)
{
  vtkNew<vtkTesting> testing;
  const std::string baseline = std::string(SIGHTLINE_BASELINE_DIR) + "/" + name + ".png";
  testing->AddArgument("-V");
  testing->AddArgument(baseline.c_str());
  testing->AddArgument("-T");
  testing->AddArgument(SIGHTLINE_TEST_TEMP_DIR);
  vtkNew<vtkTrivialProducer> producer;
  producer->SetOutput(image);
  const int result = testing->RegressionTest(producer, threshold, std::cout);
  return result == vtkTesting::PASSED;
}

void MessageCollector::Execute(vtkObject*, unsigned long event, void* data)
{
  const std::string message = data ? static_cast<const char*>(data) : "";
  (event == vtkCommand::ErrorEvent ? Errors : Warnings).push_back(message);
}

void MessageCollector::Observe(vtkObject* object)
{
  object->AddObserver(vtkCommand::ErrorEvent, this);
  object->AddObserver(vtkCommand::WarningEvent, this);
}

bool MessageCollector::Contains(const std::string& fragment) const
{
  auto has = [&](const std::string& m) { return m.find(fragment) != std::string::npos; };
  return std::any_of(Errors.begin(), Errors.end(), has) ||
    std::any_of(Warnings.begin(), Warnings.end(), has);
}
void ViewSingleGlyph(vtkRenderer* renderer)
{
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(3, -4, 5);
  camera->SetViewUp(0, 0, 1);
  camera->ParallelProjectionOn();
  camera->SetParallelScale(1.15);
  renderer->ResetCameraClippingRange(-2, 2, -2, 2, -2, 2);
}
void ExpectFrontOverBackIsWhole(const sightline::Framebuffer& front, const sightline::Framebuffer& back,
  const sightline::Framebuffer& whole, float alphaTolerance, float colourTolerance, int& covered, int& both)
{
  covered = both = 0;
  for (std::size_t i = 0; i < whole.pixelCount(); ++i)
  {
    const sightline::vec4 f = front.Color[i], b = back.Color[i], expected = whole.Color[i];
    const float alpha = f.a + (1.0f - f.a) * b.a;
    ASSERT_NEAR(alpha, expected.a, alphaTolerance) << "pixel " << i;
    if (expected.a == 0.0f)
      continue;
    ++covered;
    both += f.a > 0.0f && b.a > 0.0f;
    const sightline::vec3 blended = f.a * sightline::vec3(f) + (1.0f - f.a) * b.a * sightline::vec3(b);
    EXPECT_NEAR(glm::length(blended - expected.a * sightline::vec3(expected)), 0.0f, colourTolerance)
      << "pixel " << i;
  }
}
} // namespace sightline_test
