// Shared helpers of the VTK-layer tests: scenes, window capture, baseline comparison and
// collection of VTK error/warning messages.
#pragma once

#include "vtkCommand.h"
#include "vtkImageData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <array>
#include <string>
#include <vector>

class vtkActor;
class vtkCamera;
class vtkRenderWindow;

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

/// Collects the error and warning messages VTK objects emit while it observes them.
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
