// SPDX-License-Identifier: BSD-3-Clause
// What every benchmark scene shares: options, images and their comparison, timing, the
// machine description, and the results a scene hands back to the harness.
#pragma once

#include "vtkSmartPointer.h"

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

class vtkImageData;
class vtkRenderWindow;

namespace sightline
{
class Framebuffer;
}

namespace sightline_benchmark
{
constexpr double kNotMeasured = std::numeric_limits<double>::quiet_NaN();

/// Command-line settings shared by all scenes.
struct Options
{
  std::string scene;
  /// Primitive counts to run, one CSV row group each; empty means the scene's default.
  std::vector<long long> counts;
  int width = 1920;
  int height = 1080;
  int runs = 5;
  std::string outputDirectory = "sightline-benchmark-results";
  /// Theta/phi resolutions of the tessellated baselines.
  std::vector<int> tessellations{ 8, 16, 32 };
  /// Tessellations with more triangles are skipped so the largest scenes fit in memory.
  long long maxTriangles = 100000000;
  unsigned seed = 20240601;
  /// Where scenes that read real data find or generate it; empty: a folder in the output
  /// directory (sh-glyph-window: the tiled NIfTI of scripts/make_sh_data.py and DIPY's spheres).
  std::string dataDirectory;
  /// sh-glyphs, tensor-glyphs and tubes: run only the methods whose name contains one of these (the
  /// reference and the method the ratios divide by always run); empty: all.
  std::vector<std::string> methodFilter;
  /// Whether --methods leaves `method` in.
  bool wantsMethod(const std::string& method) const
  {
    if (methodFilter.empty())
      return true;
    for (const std::string& part : methodFilter)
      if (method.find(part) != std::string::npos)
        return true;
    return false;
  }
  bool plot = true;
  std::string python;
  std::string plotScript;
};

/// Colour and window depth of one rendered view, bottom row first (as OpenGL and vtkImageData).
struct Image
{
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb; ///< 3 bytes per pixel
  std::vector<float> depth;      ///< window depth in [0, 1]; 1 where nothing was hit
  bool empty() const { return rgb.empty(); }
  std::size_t pixelCount() const { return static_cast<std::size_t>(width) * height; }
};

/// From vtkSightlineImageRenderer's output ("Colors" scalars and "Depth" array).
Image imageFromSightlineOutput(vtkImageData* output);
/// From a kernel framebuffer composited over `background`.
Image imageFromFramebuffer(const sightline::Framebuffer& framebuffer, const double background[3]);
/// What the window shows now (colour and z-buffer), without rendering again.
Image captureWindow(vtkRenderWindow* window);

/// Differences of an image from the reference image of the same size.
struct ImageError
{
  double rgbMeanAbsDiff = kNotMeasured;      ///< mean |difference| over pixels and channels, 0-255
  double coverageDiffPercent = kNotMeasured; ///< pixels hit in one image but not the other
  double depthMaxAbsDiff = kNotMeasured;     ///< max window-depth difference where both hit
  double depthP99AbsDiff = kNotMeasured;     ///< its 99th percentile (max is set by silhouettes)
};
ImageError compareImages(const Image& image, const Image& reference);
/// Percentage of pixels where something was hit.
double hitPercent(const Image& image);

/// Writes `image` as PNG (halved until at most maxWidth wide) and, next to it, a centre crop
/// enlarged `zoom` times with nearest-neighbour sampling so individual pixels can be inspected.
void writeImagePNGs(const Image& image, const std::string& path, const std::string& cropPath,
  int maxWidth = 1920, int zoom = 4);

/// Writes |image - reference| per channel, amplified `gain` times, as PNG: where a method
/// differs from the reference (black where it agrees).
void writeDifferencePNG(
  const Image& image, const Image& reference, const std::string& path, int gain = 4);

/// Median and minimum of several frames.
struct FrameTiming
{
  double medianSeconds = kNotMeasured;
  double minSeconds = kNotMeasured;
  int runs = 0;
};
/// Calls `frame` `runs` times and times each call.
FrameTiming timeFrames(int runs, const std::function<void()>& frame);
/// Seconds `work` takes.
double timeOnce(const std::function<void()>& work);

/// The machine the numbers were measured on.
struct MachineDescription
{
  std::string cpuModel;
  int logicalCores = 0;
  int tbbThreads = 0;
  double memoryGiB = 0.0;
  /// 1-minute load average when the run started: other busy processes make timings noisy.
  double loadAverage = 0.0;
  std::string glRenderer = "not used";
  std::string glVersion = "not used";
  std::string vtkVersion;
  std::string embreeVersion;
  std::string date;

  /// Everything but OpenGL, which is known only once a window has been rendered.
  static MachineDescription probe();
  /// Records the OpenGL renderer and version strings of a rendered window (first call wins).
  void describeOpenGL(vtkRenderWindow* window);
};

/// Whether OpenGL windows can be opened (VTK's X11 windows need a display, e.g. xvfb-run).
bool openGLAvailable();
/// An offscreen window of the given size without multisampling, so that rasterisation samples
/// pixel centres as the ray tracers do.
vtkSmartPointer<vtkRenderWindow> makeOffscreenWindow(int width, int height);

/// One row of the results: a method of rendering a scene.
struct MethodResult
{
  std::string method;
  bool skipped = false;
  bool isReference = false;
  long long primitives = 0;
  long long triangles = 0; ///< 0 for exact primitives
  int width = 0;
  int height = 0;
  double buildSeconds = kNotMeasured;      ///< acceleration structure / tessellation + upload
  double firstImageSeconds = kNotMeasured; ///< from the scene's data to the first image
  FrameTiming frame;
  /// Frames while the window asks for an interactive rate (SetDesiredUpdateRate(15)); scenes
  /// that do not measure it leave it empty.
  FrameTiming interactiveFrame;
  double bytesPerPrimitive = kNotMeasured;
  double memoryBytes = kNotMeasured;      ///< everything the method holds (not per primitive)
  double rssIncreaseBytes = kNotMeasured; ///< process VmRSS after the first image minus before
  /// A scene-specific update and the frame after it (sh-glyph-window: a ScaleFactor change,
  /// i.e. rebuilding the glyphs from cached boxes, the BVH and the frame).
  double updateSeconds = kNotMeasured;
  /// Scenes that integrate along rays (spherical-*): the root mean square and the largest
  /// absolute difference of the methods' ray integrals from the exact ones.
  double integralRmsError = kNotMeasured;
  double integralMaxError = kNotMeasured;
  ImageError error;                 ///< filled in by the harness
  double hitPercent = kNotMeasured; ///< filled in by the harness
  std::string notes;
  Image image; ///< compared with the reference and written as PNG by the harness
};

/// Prints a progress line to stderr (stdout is kept for the results table).
void logProgress(const std::string& message);
} // namespace sightline_benchmark
