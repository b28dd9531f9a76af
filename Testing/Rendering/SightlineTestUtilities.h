// SPDX-License-Identifier: BSD-3-Clause
// Shared helpers of the VTK-layer tests: scenes, window capture, baseline comparison and
// collection of VTK error/warning messages.
#pragma once

#include "vtkActor.h"
#include "vtkCommand.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"

#include <array>
#include <string>
#include <vector>

namespace sightline
{
class Framebuffer;
}

class vtkCamera;

namespace sightline_test
{
/// Points with a "radius" point-data array (omitted when radii is empty) and a "value" array.
vtkSmartPointer<vtkPolyData> MakeSpheres(
  const std::vector<std::array<double, 3>>& centers, const std::vector<double>& radii);

/// A parallel or perspective camera looking down -z at the origin, with explicit clipping.
vtkSmartPointer<vtkCamera> MakeCamera(bool parallel, double distance = 10.0, double scale = 2.0);

/// The window's RGB pixels (bottom row first), captured after rendering.
vtkSmartPointer<vtkImageData> CaptureRGB(vtkRenderWindow* window);
/// The window's depth buffer (float, [0, 1]).
vtkSmartPointer<vtkImageData> CaptureDepth(vtkRenderWindow* window);

/// Renders actors through vtkSightlineImageRenderer (no OpenGL).
vtkSmartPointer<vtkImageData> RenderWithoutGL(const std::vector<vtkActor*>& actors,
  vtkCamera* camera, int width, int height, const double background[3]);

/// RGB of a pixel of an RGB or RGBA unsigned-char image.
std::array<int, 3> Pixel(vtkImageData* image, int x, int y);

/// Number of pixels that are not black (the background of the tests).
int CoveredPixels(vtkImageData* image);

/// Largest per-channel RGB difference between two images of the same size.
int MaxRGBDifference(vtkImageData* a, vtkImageData* b, int* differingPixels = nullptr);

/// Compares an image with Testing/Data/Baseline/<name>.png using vtkTesting's regression
/// metric; a missing baseline fails and leaves the image in Testing/Temporary/.
bool MatchesBaseline(vtkImageData* image, const std::string& name, double threshold);

/// Two regions' images (the one every ray crosses first, then the other) blended front to
/// back ("over") must be `whole`: opacity within `alphaTolerance` at every pixel, premultiplied
/// colour within `colourTolerance` where `whole` is covered. Counts the covered pixels and
/// those with layers in both regions.
void ExpectFrontOverBackIsWhole(const sightline::Framebuffer& front, const sightline::Framebuffer& back,
  const sightline::Framebuffer& whole, float alphaTolerance, float colourTolerance, int& covered, int& both);

/// Collects the error and warning messages VTK objects emit while it observes them.
/// A glyph mapper in an actor (ambient 0.15, specular 0.4, power 40) in an offscreen window
/// without multisampling, on black: the setting of the glyph mapper tests.
template <class Mapper>
struct MapperScene
{
  vtkNew<Mapper> mapper;
  vtkNew<vtkActor> actor;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;

  MapperScene(int width, int height)
  {
    actor->SetMapper(mapper);
    actor->GetProperty()->SetAmbient(0.15);
    actor->GetProperty()->SetSpecular(0.4);
    actor->GetProperty()->SetSpecularPower(40);
    renderer->AddActor(actor);
    renderer->SetBackground(0, 0, 0);
    window->AddRenderer(renderer);
    window->SetSize(width, height);
    window->SetOffScreenRendering(1);
    window->SetMultiSamples(0);
  }
};

/// An oblique, fixed parallel view of one glyph of radius up to 1 at the origin.
void ViewSingleGlyph(vtkRenderer* renderer);

class MessageCollector : public vtkCommand
{
public:
  static MessageCollector* New() { return new MessageCollector; }
  void Execute(vtkObject*, unsigned long event, void* data) override;
  void Observe(vtkObject* object);
  bool Contains(const std::string& fragment) const;
  std::vector<std::string> Errors;
  std::vector<std::string> Warnings;
};
} // namespace sightline_test
