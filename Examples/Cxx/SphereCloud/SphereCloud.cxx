// SPDX-License-Identifier: BSD-3-Clause
// SphereCloud: ray-trace one exact sphere per point of a VTK point set.
//
//   SphereCloud [--input FILE.vtp|.vtk] [--radius-array NAME] [--radius R]
//               [--size W H] [--output DIR] [--interactive]
//
// Without --input it renders a generated cloud: points on a spiral sphere with radii and
// scalars varying along it. It shows the two paths every Sightline mapper offers:
// - a VTK render window (ray-traced colour and depth composited with a VTK axes actor),
//   saved as DIR/sphere_cloud_window.png, interactive with --interactive;
// - the GL-free path, vtkSightlineMapper::RayTrace, whose colour and depth are saved as
//   DIR/sphere_cloud.exr (channels R, G, B, A, Z = ray distance, depth.Z = window depth).
#include "vtkActor.h"
#include "vtkAxesActor.h"
#include "vtkCamera.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataReader.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkSightlineSphereMapper.h"
#include "vtkWindowToImageFilter.h"
#include "vtkXMLPolyDataReader.h"

#include "sightline/core/Framebuffer.h"
#include "sightline/core/ImageIO.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

namespace
{
vtkSmartPointer<vtkPolyData> SpiralCloud(int count)
{
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> radius;
  radius->SetName("radius");
  vtkNew<vtkDoubleArray> height;
  height->SetName("height");
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i)
  {
    const double z = 1.0 - 2.0 * (i + 0.5) / count;
    const double r = std::sqrt(1.0 - z * z);
    points->InsertNextPoint(r * std::cos(golden * i), r * std::sin(golden * i), z);
    radius->InsertNextValue(0.03 + 0.04 * (0.5 + 0.5 * std::sin(8.0 * z)));
    height->InsertNextValue(z);
  }
  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  cloud->SetPoints(points);
  cloud->GetPointData()->AddArray(radius);
  cloud->GetPointData()->SetScalars(height);
  return cloud;
}

vtkSmartPointer<vtkPolyData> ReadCloud(const std::string& path)
{
  auto ends = [&](const char* suffix)
  {
    const std::string s(suffix);
    return path.size() >= s.size() && path.compare(path.size() - s.size(), s.size(), s) == 0;
  };
  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  if (ends(".vtp"))
  {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    cloud->ShallowCopy(reader->GetOutput());
  }
  else if (ends(".vtk"))
  {
    vtkNew<vtkPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    cloud->ShallowCopy(reader->GetOutput());
  }
  else
  {
    std::cerr << "SphereCloud: unsupported file '" << path << "' (use .vtp or .vtk)\n";
    return nullptr;
  }
  return cloud;
}
} // namespace

int main(int argc, char* argv[])
{
  std::string input, radiusArray = "radius", output = "output";
  double radius = 0.05;
  int width = 800, height = 600;
  bool interactive = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string
    {
      if (i + 1 >= argc)
      {
        std::cerr << "SphereCloud: " << arg << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--input")
      input = next();
    else if (arg == "--radius-array")
      radiusArray = next();
    else if (arg == "--radius")
      radius = std::stod(next());
    else if (arg == "--size")
    {
      width = std::stoi(next());
      height = std::stoi(next());
    }
    else if (arg == "--output")
      output = next();
    else if (arg == "--interactive")
      interactive = true;
    else
    {
      std::cerr << "usage: SphereCloud [--input FILE] [--radius-array NAME] [--radius R] "
                   "[--size W H] [--output DIR] [--interactive]\n";
      return arg == "--help" ? 0 : 2;
    }
  }

  vtkSmartPointer<vtkPolyData> cloud = input.empty() ? SpiralCloud(1500) : ReadCloud(input);
  if (!cloud)
    return 1;

  vtkNew<vtkSightlineSphereMapper> mapper;
  mapper->SetInputDataObject(cloud);
  mapper->SetRadius(radius);
  if (cloud->GetPointData()->GetArray(radiusArray.c_str()))
    mapper->SetRadiusArrayName(radiusArray.c_str());
  if (cloud->GetPointData()->GetScalars())
    mapper->SetScalarRange(cloud->GetPointData()->GetScalars()->GetRange());
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetSpecular(0.4);
  actor->GetProperty()->SetSpecularPower(30);

  vtkNew<vtkAxesActor> axes; // ordinary VTK geometry, depth-composited with the spheres
  axes->SetTotalLength(1.3, 1.3, 1.3);
  axes->AxisLabelsOff();

  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->AddActor(axes);
  renderer->SetBackground(0.1, 0.1, 0.12);
  vtkNew<vtkRenderWindow> window;
  window->AddRenderer(renderer);
  window->SetSize(width, height);
  window->SetOffScreenRendering(!interactive);
  renderer->ResetCamera();
  renderer->GetActiveCamera()->Elevation(25);
  renderer->GetActiveCamera()->Azimuth(30);
  renderer->ResetCameraClippingRange();
  window->Render();

  std::filesystem::create_directories(output);
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(grab->GetOutputPort());
  const std::string png = output + "/sphere_cloud_window.png";
  writer->SetFileName(png.c_str());
  writer->Write();

  // The GL-free path: colour and depth straight from the ray tracer, kept as OpenEXR.
  sightline::Framebuffer frame;
  if (!mapper->RayTrace(actor, renderer->GetActiveCamera(), nullptr, width, height, frame))
    return 1;
  const std::string exr = output + "/sphere_cloud.exr";
  sightline::writeEXR(exr, frame);

  std::cout << "spheres: " << mapper->GetNumberOfPrimitives() << "\n"
            << "BVH build: " << mapper->GetLastBuildSeconds() * 1e3 << " ms\n"
            << "frame (" << width << "x" << height << "): " << mapper->GetLastFrameSeconds() * 1e3
            << " ms\n"
            << "wrote " << png << " and " << exr << "\n";

  if (interactive)
  {
    vtkNew<vtkRenderWindowInteractor> interactor;
    interactor->SetRenderWindow(window);
    window->Render();
    interactor->Start();
  }
  return 0;
}
