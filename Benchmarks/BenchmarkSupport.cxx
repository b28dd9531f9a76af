// SPDX-License-Identifier: BSD-3-Clause
#include "BenchmarkSupport.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVersion.h"
#include "vtkWindowToImageFilter.h"

#include "sightline/core/Framebuffer.h"

#include "sightline/core/EmbreeApi.h" // RTC_VERSION_STRING
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace sightline_benchmark
{
namespace
{
using Clock = std::chrono::steady_clock;

bool isHit(float windowDepth)
{
  return windowDepth < 1.0f;
}

// Halves the image (2x2 box filter) until it is at most maxWidth wide.
Image downsample(const Image& image, int maxWidth)
{
  Image current = image;
  while (current.width > maxWidth && current.width >= 2 && current.height >= 2)
  {
    Image half;
    half.width = current.width / 2;
    half.height = current.height / 2;
    half.rgb.resize(half.pixelCount() * 3);
    for (int y = 0; y < half.height; ++y)
    {
      for (int x = 0; x < half.width; ++x)
      {
        for (int c = 0; c < 3; ++c)
        {
          int sum = 0;
          for (int dy = 0; dy < 2; ++dy)
          {
            for (int dx = 0; dx < 2; ++dx)
            {
              const std::size_t source =
                static_cast<std::size_t>(2 * y + dy) * current.width + (2 * x + dx);
              sum += current.rgb[3 * source + c];
            }
          }
          half.rgb[3 * (static_cast<std::size_t>(y) * half.width + x) + c] =
            static_cast<std::uint8_t>((sum + 2) / 4);
        }
      }
    }
    current = std::move(half);
  }
  return current;
}

void writePNG(const std::vector<std::uint8_t>& rgb, int width, int height, const std::string& path)
{
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(static_cast<vtkIdType>(width) * height);
  std::copy(rgb.begin(), rgb.end(), colors->GetPointer(0));
  vtkNew<vtkImageData> data;
  data->SetExtent(0, width - 1, 0, height - 1, 0, 0);
  data->GetPointData()->SetScalars(colors);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(data);
  writer->SetFileName(path.c_str());
  writer->Write();
  if (writer->GetErrorCode() != 0)
  {
    throw std::runtime_error("could not write " + path);
  }
}

std::string firstLineValue(const std::string& file, const std::string& key)
{
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
  {
    if (line.compare(0, key.size(), key) == 0)
    {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos)
      {
        const std::size_t start = line.find_first_not_of(" \t", colon + 1);
        return start == std::string::npos ? std::string() : line.substr(start);
      }
    }
  }
  return {};
}

std::string lineAfter(const std::string& text, const std::string& key)
{
  const std::size_t at = text.find(key);
  if (at == std::string::npos)
  {
    return {};
  }
  const std::size_t start = text.find_first_not_of(" \t", at + key.size());
  const std::size_t end = text.find('\n', at);
  return start == std::string::npos ? std::string() : text.substr(start, end - start);
}
} // namespace

//------------------------------------------------------------------------------
Image imageFromSightlineOutput(vtkImageData* output)
{
  int dims[3];
  output->GetDimensions(dims);
  auto* colors = vtkUnsignedCharArray::SafeDownCast(output->GetPointData()->GetScalars());
  auto* depth = vtkFloatArray::SafeDownCast(output->GetPointData()->GetArray("Depth"));
  if (!colors || colors->GetNumberOfComponents() != 4 || !depth)
  {
    throw std::runtime_error("vtkSightlineImageRenderer output lacks RGBA colours or Depth");
  }
  Image image;
  image.width = dims[0];
  image.height = dims[1];
  image.rgb.resize(image.pixelCount() * 3);
  image.depth.resize(image.pixelCount());
  for (std::size_t i = 0; i < image.pixelCount(); ++i)
  {
    const unsigned char* c = colors->GetPointer(4 * i);
    std::copy(c, c + 3, &image.rgb[3 * i]);
    image.depth[i] = depth->GetValue(i);
  }
  return image;
}

//------------------------------------------------------------------------------
Image imageFromFramebuffer(const sightline::Framebuffer& framebuffer, const double background[3])
{
  const std::vector<std::uint8_t> rgba =
    framebuffer.toRGBA8(sightline::vec3(background[0], background[1], background[2]));
  Image image;
  image.width = framebuffer.width();
  image.height = framebuffer.height();
  image.rgb.resize(image.pixelCount() * 3);
  for (std::size_t i = 0; i < image.pixelCount(); ++i)
  {
    std::copy(&rgba[4 * i], &rgba[4 * i] + 3, &image.rgb[3 * i]);
  }
  image.depth = framebuffer.Depth;
  return image;
}

//------------------------------------------------------------------------------
Image captureWindow(vtkRenderWindow* window)
{
  // Read back what the last Render() drew; rendering again here would time nothing and
  // could change what is compared.
  auto grab = [window](bool zbuffer)
  {
    vtkNew<vtkWindowToImageFilter> grabber;
    grabber->SetInput(window);
    grabber->ShouldRerenderOff();
    grabber->ReadFrontBufferOff();
    if (zbuffer)
    {
      grabber->SetInputBufferTypeToZBuffer();
    }
    else
    {
      grabber->SetInputBufferTypeToRGB();
    }
    grabber->Update();
    vtkSmartPointer<vtkImageData> copy = vtkSmartPointer<vtkImageData>::New();
    copy->ShallowCopy(grabber->GetOutput());
    return copy;
  };
  vtkSmartPointer<vtkImageData> colorImage = grab(false);
  vtkSmartPointer<vtkImageData> depthImage = grab(true);

  int dims[3];
  colorImage->GetDimensions(dims);
  auto* colors = vtkUnsignedCharArray::SafeDownCast(colorImage->GetPointData()->GetScalars());
  vtkDataArray* depth = depthImage->GetPointData()->GetScalars();
  if (!colors || colors->GetNumberOfComponents() != 3 || !depth)
  {
    throw std::runtime_error("could not read colour and depth back from the render window");
  }
  Image image;
  image.width = dims[0];
  image.height = dims[1];
  image.rgb.assign(colors->GetPointer(0), colors->GetPointer(0) + image.pixelCount() * 3);
  image.depth.resize(image.pixelCount());
  for (std::size_t i = 0; i < image.pixelCount(); ++i)
  {
    image.depth[i] = static_cast<float>(depth->GetComponent(i, 0));
  }
  return image;
}

//------------------------------------------------------------------------------
ImageError compareImages(const Image& image, const Image& reference)
{
  if (image.width != reference.width || image.height != reference.height)
  {
    throw std::runtime_error("cannot compare images of different sizes");
  }
  ImageError error;
  double rgbSum = 0.0;
  std::size_t coverageDiffers = 0;
  std::vector<float> depthDiffs;
  depthDiffs.reserve(image.pixelCount());
  for (std::size_t i = 0; i < image.pixelCount(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      rgbSum += std::abs(int(image.rgb[3 * i + c]) - int(reference.rgb[3 * i + c]));
    }
    const bool hit = isHit(image.depth[i]);
    const bool referenceHit = isHit(reference.depth[i]);
    if (hit != referenceHit)
    {
      ++coverageDiffers;
    }
    else if (hit)
    {
      depthDiffs.push_back(std::abs(image.depth[i] - reference.depth[i]));
    }
  }
  const double pixels = static_cast<double>(std::max<std::size_t>(image.pixelCount(), 1));
  error.rgbMeanAbsDiff = rgbSum / (3.0 * pixels);
  error.coverageDiffPercent = 100.0 * coverageDiffers / pixels;
  if (!depthDiffs.empty())
  {
    error.depthMaxAbsDiff = *std::max_element(depthDiffs.begin(), depthDiffs.end());
    const std::size_t p99 = static_cast<std::size_t>(0.99 * (depthDiffs.size() - 1));
    std::nth_element(depthDiffs.begin(), depthDiffs.begin() + p99, depthDiffs.end());
    error.depthP99AbsDiff = depthDiffs[p99];
  }
  return error;
}

double hitPercent(const Image& image)
{
  const auto hits = std::count_if(image.depth.begin(), image.depth.end(), isHit);
  return 100.0 * hits / std::max<double>(1.0, image.pixelCount());
}

//------------------------------------------------------------------------------
void writeImagePNGs(
  const Image& image, const std::string& path, const std::string& cropPath, int maxWidth, int zoom)
{
  const Image small = downsample(image, maxWidth);
  writePNG(small.rgb, small.width, small.height, path);

  const int cropWidth = std::max(1, image.width / (2 * zoom));
  const int cropHeight = std::max(1, image.height / (2 * zoom));
  const int x0 = (image.width - cropWidth) / 2;
  const int y0 = (image.height - cropHeight) / 2;
  std::vector<std::uint8_t> crop(
    static_cast<std::size_t>(cropWidth) * zoom * cropHeight * zoom * 3);
  for (int y = 0; y < cropHeight * zoom; ++y)
  {
    for (int x = 0; x < cropWidth * zoom; ++x)
    {
      const std::size_t source =
        static_cast<std::size_t>(y0 + y / zoom) * image.width + (x0 + x / zoom);
      const std::size_t target = static_cast<std::size_t>(y) * cropWidth * zoom + x;
      std::copy(&image.rgb[3 * source], &image.rgb[3 * source] + 3, &crop[3 * target]);
    }
  }
  writePNG(crop, cropWidth * zoom, cropHeight * zoom, cropPath);
}

void writeDifferencePNG(
  const Image& image, const Image& reference, const std::string& path, int gain)
{
  if (image.width != reference.width || image.height != reference.height)
  {
    throw std::runtime_error("cannot compare images of different sizes");
  }
  Image difference;
  difference.width = image.width;
  difference.height = image.height;
  difference.rgb.resize(image.rgb.size());
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
  {
    const int d = std::abs(int(image.rgb[i]) - int(reference.rgb[i])) * gain;
    difference.rgb[i] = static_cast<std::uint8_t>(std::min(d, 255));
  }
  difference = downsample(difference, 1920);
  writePNG(difference.rgb, difference.width, difference.height, path);
}

//------------------------------------------------------------------------------
FrameTiming timeFrames(int runs, const std::function<void()>& frame)
{
  std::vector<double> seconds;
  for (int run = 0; run < runs; ++run)
  {
    seconds.push_back(timeOnce(frame));
  }
  FrameTiming timing;
  timing.runs = runs;
  if (seconds.empty())
  {
    return timing;
  }
  std::sort(seconds.begin(), seconds.end());
  const std::size_t n = seconds.size();
  timing.medianSeconds = n % 2 ? seconds[n / 2] : 0.5 * (seconds[n / 2 - 1] + seconds[n / 2]);
  timing.minSeconds = seconds.front();
  return timing;
}

double timeOnce(const std::function<void()>& work)
{
  const auto start = Clock::now();
  work();
  return std::chrono::duration<double>(Clock::now() - start).count();
}

//------------------------------------------------------------------------------
MachineDescription MachineDescription::probe()
{
  MachineDescription machine;
  machine.cpuModel = firstLineValue("/proc/cpuinfo", "model name");
  if (machine.cpuModel.empty())
  {
    machine.cpuModel = "unknown";
  }
  // Model names of virtual CPUs can be vague ("AMD EPYC"): add the family and model, the
  // widest vector ISA (it decides Embree's and llvmpipe's code paths) and whether it is a VM.
  const std::string flags = " " + firstLineValue("/proc/cpuinfo", "flags") + " ";
  const std::string family = firstLineValue("/proc/cpuinfo", "cpu family");
  const std::string model = firstLineValue("/proc/cpuinfo", "model\t");
  std::string detail;
  if (!family.empty())
  {
    detail += "family " + family + " model " + model;
  }
  for (const char* isa : { "avx512f", "avx2", "sse4_2" })
  {
    if (flags.find(std::string(" ") + isa + " ") != std::string::npos)
    {
      detail += std::string(detail.empty() ? "" : ", ") + isa;
      break;
    }
  }
  if (flags.find(" hypervisor ") != std::string::npos)
  {
    detail += std::string(detail.empty() ? "" : ", ") + "virtual machine";
  }
  if (!detail.empty())
  {
    machine.cpuModel += " (" + detail + ")";
  }
  machine.logicalCores = static_cast<int>(std::thread::hardware_concurrency());
  machine.tbbThreads = tbb::this_task_arena::max_concurrency();
  const std::string memTotal = firstLineValue("/proc/meminfo", "MemTotal"); // "24576000 kB"
  machine.memoryGiB = std::atof(memTotal.c_str()) / (1024.0 * 1024.0);
  std::ifstream("/proc/loadavg") >> machine.loadAverage;
  machine.vtkVersion = vtkVersion::GetVTKVersion();
  machine.embreeVersion = RTC_VERSION_STRING;
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof(date), "%Y-%m-%dT%H:%M:%S", std::localtime(&now));
  machine.date = date;
  return machine;
}

void MachineDescription::describeOpenGL(vtkRenderWindow* window)
{
  if (this->glRenderer != "not used" || !window)
  {
    return;
  }
  const std::string capabilities = window->ReportCapabilities();
  const std::string renderer = lineAfter(capabilities, "OpenGL renderer string:");
  const std::string version = lineAfter(capabilities, "OpenGL version string:");
  this->glRenderer = renderer.empty() ? "unknown" : renderer;
  this->glVersion = version.empty() ? "unknown" : version;
}

//------------------------------------------------------------------------------
bool openGLAvailable()
{
  // Debian's VTK opens X11 windows even for offscreen rendering; without a display the
  // window would abort the process.
  vtkNew<vtkRenderWindow> probe;
  const std::string type = probe->GetClassName();
  if (type == "vtkXOpenGLRenderWindow")
  {
    const char* display = std::getenv("DISPLAY");
    return display && *display;
  }
  return true;
}

vtkSmartPointer<vtkRenderWindow> makeOffscreenWindow(int width, int height)
{
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetMultiSamples(0);
  window->SetOffScreenRendering(1);
  window->SetSize(width, height);
  return window;
}

//------------------------------------------------------------------------------
void logProgress(const std::string& message)
{
  static const auto start = Clock::now();
  const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  std::cerr << "[" << std::fixed << std::setprecision(1) << std::setw(7) << elapsed << " s] "
            << message << std::endl;
}
} // namespace sightline_benchmark
