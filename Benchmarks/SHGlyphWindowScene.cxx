// SPDX-License-Identifier: BSD-3-Clause
// The SH glyph window scene: what a VTK user experiences in a render window with one slice of
// real fibre ODFs (scripts/make_sh_data.py's CSD of DIPY's small_64D, its fullest axial slice
// tiled to side x side voxels; 140 x 140 = 19,600 glyphs by default), at k = 8 and at k = 4:
//
// - "sightline": vtkSightlineSHGlyphMapper on vtkNIFTIImageReader (TimeAsVectorOn) output,
//   SetBasisToDIPY(), default normalisation (each glyph's largest lobe fills half a voxel),
//   k = 4 by SetMaximumOrder(4). Exact glyphs: the reference image of its k.
// - "dipy-<sphere>": what a VTK/DIPY user does today, the way DIPY's odf_slicer does it: one
//   vtkPolyData holding, per glyph, the vertices of a DIPY sphere scaled by |F(v)| / max |F|
//   over those vertices, per-vertex direction colours |v|, area-weighted vertex normals (what
//   FURY's normals_from_v_f computes), drawn by a plain vtkPolyDataMapper. Spheres:
//   repulsion724 and repulsion100 by default (--tessellation picks DIPY sphere vertex counts).
//
// Per method and k, in an offscreen window of --width x --height: time to the first image (from
// creating the mapper, or from building the mesh, to a finished frame and a pixel read), still
// frames (median of --runs re-renders, camera Azimuth(1) before each, DesiredUpdateRate
// 0.0001), interactive frames (the same at DesiredUpdateRate 15: Sightline traces every 2nd
// pixel, VTK renders as usual), memory (Sightline: GetMemoryBytes() + Embree's BVH from the
// device's memory monitor; meshes: vtkPolyData::GetActualMemorySize()) and the process RSS
// increase, the image error of the meshes against Sightline's exact image, and for Sightline the
// cost of a ScaleFactor change (every box cached: the update a slice change also is).
//
// Rows are named "k8:<method>" and "k4:<method>", and none is marked isReference: the harness
// knows one reference per run, so this scene compares each mesh with its own k's Sightline
// image itself (as the sh-glyphs scene does), and writes the difference images.
#include "GlyphSceneSupport.h"
#include "SceneRegistry.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkNIFTIImageReader.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSightlineSHGlyphMapper.h"
#include "vtkUnsignedCharArray.h"

#include "sightline/core/EmbreeScene.h"
#include "sightline/math/Math.h"
#include "sightline/math/SphericalHarmonics.h"

#include <malloc.h> // malloc_trim (glibc)
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#ifndef SIGHTLINE_BENCHMARK_MAKE_SH_DATA
#define SIGHTLINE_BENCHMARK_MAKE_SH_DATA ""
#endif

namespace sightline_benchmark
{
namespace
{
namespace fs = std::filesystem;

/// Zoom after framing the slice's bounding sphere, so that the slice fills the image height.
constexpr double kZoom = 1.35;
/// vtkRenderWindowInteractor's rates: still (after interaction) and while the user drags.
constexpr double kStillUpdateRate = 0.0001;
constexpr double kInteractiveUpdateRate = 15.0;
/// ScaleFactor of the update measurement (any change rebuilds the glyphs from cached boxes).
constexpr double kChangedScaleFactor = 0.8;
/// The harness's default --tessellation is vtkSphereSource's; here the values are DIPY sphere
/// vertex counts, and that default means these.
const std::vector<int> kHarnessDefaultTessellations{ 8, 16, 32 };
const std::vector<int> kDefaultSphereVertices{ 724, 100 };

std::string shellQuote(const std::string& text)
{
  std::string quoted = "'";
  for (char c : text)
    quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

//------------------------------------------------------------------------------
// Process memory from /proc/self/status: what the user's machine has to hold, including what
// the structures do not report (Mesa's copies of the vertex buffers, allocator slack).
long long procStatusBytes(const char* key)
{
  std::ifstream status("/proc/self/status");
  std::string line;
  const std::string prefix = std::string(key) + ":";
  while (std::getline(status, line))
  {
    if (line.compare(0, prefix.size(), prefix) == 0)
      return std::atoll(line.c_str() + prefix.size()) * 1024LL; // "VmRSS:  123456 kB"
  }
  return -1;
}

/// Resets VmHWM (the peak RSS) to the current RSS, so that the peak of one method can be read.
void resetPeakRss()
{
  std::ofstream("/proc/self/clear_refs") << "5";
}

//------------------------------------------------------------------------------
fs::path dataDirectory(const Options& options)
{
  return options.dataDirectory.empty()
    ? fs::path(options.outputDirectory) / "sh-glyph-window-data"
    : fs::path(options.dataDirectory);
}

/// The tiled slice, generated by scripts/make_sh_data.py (about 30 s) unless it is there.
fs::path tiledSliceFile(const Options& options, int side)
{
  const fs::path directory = dataDirectory(options);
  const fs::path file = directory / ("small_64D_sh_tiled" + std::to_string(side) + ".nii.gz");
  if (fs::exists(file))
    return file;
  const std::string script = SIGHTLINE_BENCHMARK_MAKE_SH_DATA;
  if (script.empty() || !fs::exists(script))
    throw std::runtime_error("no " + file.string() + " and no scripts/make_sh_data.py to make it; "
      "run make_sh_data.py DIR --tile " + std::to_string(side) + " and pass --data-dir DIR");
  fs::create_directories(directory);
  const std::string command = shellQuote(options.python) + " " + shellQuote(script) + " " +
    shellQuote(directory.string()) + " --tile " + std::to_string(side) + " > " +
    shellQuote((directory / "make_sh_data.log").string()) + " 2>&1";
  logProgress("sh-glyph-window: generating the data: " + command);
  if (std::system(command.c_str()) != 0 || !fs::exists(file))
    throw std::runtime_error("make_sh_data.py failed (needs python3-dipy, python3-nibabel); see " +
      (directory / "make_sh_data.log").string());
  return file;
}

//------------------------------------------------------------------------------
/// A DIPY sphere: unit vertices and triangles, oriented outwards here (a radial deformation
/// by |F| > 0 keeps that orientation, so face normals of the glyph point outwards too).
struct DipySphere
{
  std::string name;
  std::vector<sightline::dvec3> vertices;
  std::vector<std::array<int, 3>> faces;
};

std::string dipySphereName(int vertices)
{
  switch (vertices)
  {
    case 100:
    case 200:
    case 724:
      return "repulsion" + std::to_string(vertices);
    case 362:
    case 642:
      return "symmetric" + std::to_string(vertices);
    default:
      throw std::invalid_argument("sh-glyph-window: --tessellation takes DIPY sphere vertex "
        "counts (100, 200, 724: repulsion; 362, 642: symmetric), got " + std::to_string(vertices));
  }
}

/// DIPY's spheres, read once with DIPY itself into small text files in the data directory.
std::vector<DipySphere> loadDipySpheres(const Options& options, const std::vector<int>& counts)
{
  const fs::path directory = dataDirectory(options) / "dipy-spheres";
  fs::create_directories(directory);
  std::vector<std::string> missing;
  for (int count : counts)
    if (!fs::exists(directory / (dipySphereName(count) + ".txt")))
      missing.push_back(dipySphereName(count));
  if (!missing.empty())
  {
    const fs::path scriptPath = directory / "dump_spheres.py";
    std::ofstream(scriptPath)
      << "import os, sys\n"
         "from dipy.data import get_sphere\n"
         "for name in sys.argv[2:]:\n"
         "    s = get_sphere(name=name)\n"
         "    with open(os.path.join(sys.argv[1], name + '.txt'), 'w') as f:\n"
         "        f.write(f'{len(s.vertices)} {len(s.faces)}\\n')\n"
         "        for v in s.vertices:\n"
         // float(): NumPy 2 (Debian 13) writes a scalar's repr as np.float64(...).
         "            f.write(f'{float(v[0])!r} {float(v[1])!r} {float(v[2])!r}\\n')\n"
         "        for t in s.faces:\n"
         "            f.write(f'{t[0]} {t[1]} {t[2]}\\n')\n";
    std::string command = shellQuote(options.python) + " " + shellQuote(scriptPath.string()) + " " +
      shellQuote(directory.string());
    for (const std::string& name : missing)
      command += " " + name;
    if (std::system(command.c_str()) != 0)
      throw std::runtime_error("could not read DIPY's spheres with " + options.python +
        " (needs python3-dipy)");
  }
  std::vector<DipySphere> spheres;
  for (int count : counts)
  {
    DipySphere sphere;
    sphere.name = dipySphereName(count);
    std::ifstream in(directory / (sphere.name + ".txt"));
    std::size_t nv = 0, nf = 0;
    in >> nv >> nf;
    sphere.vertices.resize(nv);
    for (auto& v : sphere.vertices)
    {
      in >> v.x >> v.y >> v.z;
      v = glm::normalize(v);
    }
    sphere.faces.resize(nf);
    for (auto& f : sphere.faces)
    {
      in >> f[0] >> f[1] >> f[2];
      const sightline::dvec3 &a = sphere.vertices[f[0]], &b = sphere.vertices[f[1]],
                             &c = sphere.vertices[f[2]];
      if (glm::dot(glm::cross(b - a, c - a), a + b + c) < 0.0)
        std::swap(f[1], f[2]);
    }
    if (!in || nv == 0 || nf == 0)
      throw std::runtime_error("could not read " + (directory / (sphere.name + ".txt")).string());
    spheres.push_back(std::move(sphere));
  }
  return spheres;
}

//------------------------------------------------------------------------------
/// The odf_slicer-style mesh of one slice: built in parallel straight into VTK arrays, so the
/// time is a lower bound for what DIPY's (numpy) code takes for the same mesh.
struct GlyphMesh
{
  vtkSmartPointer<vtkPolyData> polyData;
  long long glyphs = 0;
};

GlyphMesh buildGlyphMesh(vtkImageData* image, int order, const DipySphere& sphere, double radius)
{
  vtkDataArray* coefficients = image->GetPointData()->GetScalars();
  const int components = coefficients->GetNumberOfComponents();
  const int stride = sightline::shCoefficientCount(order); // the first bands: truncation to k
  if (components < stride)
    throw std::runtime_error("the coefficient array has fewer than the order's coefficients");
  const sightline::SHConversion conversion = sightline::SHConversion::toCanonical(
    sightline::SHConvention::fromName("descoteaux07", true), order);

  // Basis values at the sphere's vertices, once: F(v) = sum_j B[v][j] c_j (canonical c).
  const std::size_t nv = sphere.vertices.size(), nf = sphere.faces.size();
  std::vector<double> basis(nv * stride);
  for (std::size_t v = 0; v < nv; ++v)
  {
    const sightline::dvec3& d = sphere.vertices[v];
    sightline::evaluateSH<double>(order, d.x, d.y, d.z, basis.data() + v * stride);
  }

  // Pass 1: |F| at every vertex of every glyph of the axial slice (the middle one, as the mapper
  // picks); all-zero glyphs (outside the fit's mask) are dropped, as the mapper drops them.
  int extent[6];
  image->GetExtent(extent);
  const int k = (extent[4] + extent[5]) / 2;
  std::vector<vtkIdType> ids;
  for (int j = extent[2]; j <= extent[3]; ++j)
    for (int i = extent[0]; i <= extent[1]; ++i)
    {
      int ijk[3] = { i, j, k };
      ids.push_back(image->ComputePointId(ijk));
    }
  std::vector<float> radii(ids.size() * nv);
  std::vector<char> drawn(ids.size(), 0);
  tbb::parallel_for(std::size_t(0), ids.size(),
    [&](std::size_t g)
    {
      std::vector<double> tuple(components), canonical(stride);
      coefficients->GetTuple(ids[g], tuple.data());
      conversion.apply(tuple.data(), canonical.data());
      double largest = 0.0;
      float* r = radii.data() + g * nv;
      for (std::size_t v = 0; v < nv; ++v)
      {
        double value = 0.0;
        for (int c = 0; c < stride; ++c)
          value += basis[v * stride + c] * canonical[c];
        r[v] = float(std::abs(value));
        largest = std::max(largest, std::abs(value));
      }
      // odf_slicer's norm=True: divide by the largest sampled amplitude.
      if (largest > 0.0 && std::isfinite(largest))
      {
        drawn[g] = 1;
        const float scale = float(radius / largest);
        for (std::size_t v = 0; v < nv; ++v)
          r[v] *= scale;
      }
    });
  std::vector<std::size_t> glyphs;
  for (std::size_t g = 0; g < ids.size(); ++g)
    if (drawn[g])
      glyphs.push_back(g);

  // Pass 2: points, normals, colours and triangles of every drawn glyph, in place.
  const vtkIdType points = vtkIdType(glyphs.size() * nv), triangles = vtkIdType(glyphs.size() * nf);
  vtkNew<vtkFloatArray> positions;
  positions->SetNumberOfComponents(3);
  positions->SetNumberOfTuples(points);
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(points);
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(points);
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(triangles + 1);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(3 * triangles);
  // Direction colours |v| (FURY's default for odf_slicer), the same for every glyph.
  std::vector<std::array<unsigned char, 3>> vertexColors(nv);
  for (std::size_t v = 0; v < nv; ++v)
    for (int c = 0; c < 3; ++c)
      vertexColors[v][c] = static_cast<unsigned char>(std::lround(255.0 * std::abs(sphere.vertices[v][c])));

  float* P = positions->GetPointer(0);
  float* N = normals->GetPointer(0);
  unsigned char* C = colors->GetPointer(0);
  vtkIdType* O = offsets->GetPointer(0);
  vtkIdType* T = connectivity->GetPointer(0);
  tbb::parallel_for(std::size_t(0), glyphs.size(),
    [&](std::size_t n)
    {
      const std::size_t g = glyphs[n];
      double center[3];
      image->GetPoint(ids[g], center);
      const float* r = radii.data() + g * nv;
      const vtkIdType firstPoint = vtkIdType(n * nv);
      std::vector<sightline::vec3> p(nv), normal(nv, sightline::vec3(0.0f));
      for (std::size_t v = 0; v < nv; ++v)
        p[v] = sightline::vec3(sphere.vertices[v] * double(r[v]));
      for (std::size_t f = 0; f < nf; ++f)
      {
        const auto& t = sphere.faces[f];
        // Unnormalised face normal: the area-weighted average FURY and vtkPolyDataNormals use.
        const sightline::vec3 face = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
        for (int c = 0; c < 3; ++c)
          normal[t[c]] += face;
        const vtkIdType cell = vtkIdType(n * nf + f);
        O[cell] = 3 * cell;
        for (int c = 0; c < 3; ++c)
          T[3 * cell + c] = firstPoint + t[c];
      }
      for (std::size_t v = 0; v < nv; ++v)
      {
        const std::size_t out = 3 * (firstPoint + v);
        const float length = glm::length(normal[v]);
        const sightline::vec3 unit =
          length > 0.0f ? normal[v] / length : sightline::vec3(sphere.vertices[v]);
        for (int c = 0; c < 3; ++c)
        {
          P[out + c] = float(center[c] + p[v][c]);
          N[out + c] = unit[c];
          C[out + c] = vertexColors[v][c];
        }
      }
    });
  O[triangles] = 3 * triangles;

  GlyphMesh mesh;
  mesh.glyphs = static_cast<long long>(glyphs.size());
  mesh.polyData = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> vtkpoints;
  vtkpoints->SetData(positions);
  mesh.polyData->SetPoints(vtkpoints);
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  mesh.polyData->SetPolys(polys);
  mesh.polyData->GetPointData()->SetNormals(normals);
  mesh.polyData->GetPointData()->SetScalars(colors);
  return mesh;
}

//------------------------------------------------------------------------------
/// The view every method uses: the slice seen from above, tilted, framed and zoomed; the
/// clipping range covers the slice's bounding sphere, so the Azimuth steps never clip it and
/// every method's window depth is comparable.
vtkSmartPointer<vtkCamera> makeCamera(const double bounds[6])
{
  const double center[3] = { 0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
    0.5 * (bounds[4] + bounds[5]) };
  const double r = 0.5 *
    std::sqrt(std::pow(bounds[1] - bounds[0], 2) + std::pow(bounds[3] - bounds[2], 2) +
      std::pow(bounds[5] - bounds[4], 2));
  auto camera = vtkSmartPointer<vtkCamera>::New();
  const double tilt = kTiltDegrees * vtkMath::Pi() / 180.0;
  const double distance = r / std::sin(0.5 * camera->GetViewAngle() * vtkMath::Pi() / 180.0);
  camera->SetFocalPoint(center);
  camera->SetPosition(center[0], center[1] - distance * std::sin(tilt),
    center[2] + distance * std::cos(tilt));
  camera->SetViewUp(0.0, std::cos(tilt), std::sin(tilt));
  camera->Zoom(kZoom);
  camera->SetClippingRange(distance - 1.05 * r, distance + 1.05 * r);
  return camera;
}

/// An offscreen window with a renderer, rendered once empty so that creating the OpenGL context
/// is not counted as the method's first image.
struct Window
{
  vtkSmartPointer<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;

  Window(const Options& options, vtkCamera* camera)
    : window(makeOffscreenWindow(options.width, options.height))
  {
    renderer->SetBackground(kGlyphBackground[0], kGlyphBackground[1], kGlyphBackground[2]);
    renderer->SetActiveCamera(camera);
    window->AddRenderer(renderer);
    window->SetDesiredUpdateRate(kStillUpdateRate);
    window->Render();
    window->WaitForCompletion();
  }
  ~Window() { window->Finalize(); }

  /// One frame, finished (glFinish) before returning so its full cost is timed.
  void frame()
  {
    window->Render();
    window->WaitForCompletion();
  }

  /// The first image as a user sees it: the frame, then one pixel read back.
  void firstFrame()
  {
    this->frame();
    vtkNew<vtkUnsignedCharArray> pixel;
    window->GetPixelData(0, 0, 0, 0, 0, pixel);
  }

  /// --runs frames, the camera moved by 1 degree before each, at the given update rate;
  /// `afterFrame` (cheap) is called after each frame.
  FrameTiming movingFrames(
    int runs, double updateRate, const std::function<void()>& afterFrame = [] {})
  {
    window->SetDesiredUpdateRate(updateRate);
    vtkCamera* camera = renderer->GetActiveCamera();
    const FrameTiming timing = timeFrames(runs,
      [&]
      {
        camera->Azimuth(1.0);
        this->frame();
        afterFrame();
      });
    window->SetDesiredUpdateRate(kStillUpdateRate);
    return timing;
  }
};

/// RSS before a method, and its increase and peak since. Freed heap pages are handed back to the
/// system first (malloc_trim), so that what an earlier method freed is not silently reused and
/// hidden from the next one's increase. One-time costs of the process (Embree's device, TBB's
/// threads) still fall on the first method that needs them.
struct Memory
{
  long long rssBefore = 0;
  Memory()
  {
    malloc_trim(0);
    rssBefore = procStatusBytes("VmRSS");
    resetPeakRss();
  }
  long long increase() const { return procStatusBytes("VmRSS") - rssBefore; }
  long long peakIncrease() const { return procStatusBytes("VmHWM") - rssBefore; }
};

std::string megabytes(double bytes)
{
  return fixed(bytes / 1e6, 1) + " MB";
}

//------------------------------------------------------------------------------
MethodResult runSightline(const Options& options, vtkNIFTIImageReader* reader, int order,
  const double bounds[6], MachineDescription& machine, long long& drawnGlyphs)
{
  MethodResult result;
  result.method = "k" + std::to_string(order) + ":sightline";
  vtkSmartPointer<vtkCamera> camera = makeCamera(bounds);
  Window window(options, camera);
  machine.describeOpenGL(window.window);

  const Memory memory;
  const std::shared_ptr<sightline::EmbreeDevice> device = sightline::EmbreeDevice::shared();
  const std::int64_t deviceBytesBefore = device->allocatedBytes();
  vtkSmartPointer<vtkSightlineSHGlyphMapper> mapper;
  vtkNew<vtkActor> actor;
  result.firstImageSeconds = timeOnce(
    [&]
    {
      mapper = vtkSmartPointer<vtkSightlineSHGlyphMapper>::New();
      mapper->SetInputConnection(reader->GetOutputPort());
      mapper->SetBasisToDIPY();
      mapper->SetMaximumOrder(order);
      actor->SetMapper(mapper);
      window.renderer->AddActor(actor);
      window.firstFrame();
    });
  const std::int64_t bvhBytes = device->allocatedBytes() - deviceBytesBefore;
  const long long rssIncrease = memory.increase(), rssPeak = memory.peakIncrease();
  const double geometrySeconds = mapper->GetLastGeometrySeconds();
  const double bvhSeconds = mapper->GetLastBuildSeconds();
  const vtkIdType boxesComputed = mapper->GetLastComputedBoxes();
  const double firstTrace = mapper->GetLastFrameSeconds();
  const vtkIdType glyphs = mapper->GetNumberOfPrimitives();
  if (glyphs <= 0)
    throw std::runtime_error(result.method + ": the mapper drew no glyphs");
  drawnGlyphs = glyphs;
  result.image = captureWindow(window.window);
  result.buildSeconds = geometrySeconds + bvhSeconds;
  result.memoryBytes = double(mapper->GetMemoryBytes() + bvhBytes);
  result.bytesPerPrimitive = result.memoryBytes / double(glyphs);
  result.rssIncreaseBytes = double(rssIncrease);

  // Kernel trace time of each timed frame (the rest is upload and compositing). The camera
  // moves before every frame, so each one is traced again (the frame cache cannot serve it).
  std::vector<double> traces;
  auto recordTrace = [&] { traces.push_back(mapper->GetLastFrameSeconds()); };
  auto medianTrace = [&traces]
  {
    std::sort(traces.begin(), traces.end());
    const double median = traces.empty() ? kNotMeasured : traces[traces.size() / 2];
    traces.clear();
    return median;
  };
  result.frame = window.movingFrames(options.runs, kStillUpdateRate, recordTrace);
  const double stillTrace = medianTrace();
  result.interactiveFrame = window.movingFrames(options.runs, kInteractiveUpdateRate, recordTrace);
  const double interactiveTrace = medianTrace();

  // A ScaleFactor change: the glyphs are rebuilt from the cached boxes, then the BVH and the
  // frame (what changing the slice of a volume costs once its boxes are known).
  mapper->SetScaleFactor(kChangedScaleFactor);
  result.updateSeconds = timeOnce([&] { window.frame(); });
  const vtkIdType boxesOnUpdate = mapper->GetLastComputedBoxes();

  std::ostringstream notes;
  notes << glyphs << " glyphs (all-zero voxels dropped); first image: glyph boxes "
        << fixed(geometrySeconds, 3) << " s (" << boxesComputed << " computed), BVH "
        << fixed(bvhSeconds, 3) << " s, trace " << fixed(firstTrace, 3) << " s; kernel trace of "
        << "still frames " << fixed(stillTrace, 3) << " s, interactive " << fixed(interactiveTrace, 3)
        << " s; memory: mapper " << megabytes(double(mapper->GetMemoryBytes())) << " + BVH "
        << megabytes(double(bvhBytes)) << ", RSS +" << megabytes(double(rssIncrease)) << " (peak +"
        << megabytes(double(rssPeak)) << "); ScaleFactor change: geometry "
        << fixed(mapper->GetLastGeometrySeconds(), 3) << " s, BVH "
        << fixed(mapper->GetLastBuildSeconds(), 3) << " s, boxes computed on update: "
        << boxesOnUpdate << ", with the frame " << fixed(result.updateSeconds, 3) << " s";
  result.notes = notes.str();
  window.renderer->RemoveActor(actor);
  return result;
}

//------------------------------------------------------------------------------
MethodResult runMesh(const Options& options, vtkImageData* image, int order,
  const DipySphere& sphere, long long expectedGlyphs, const double bounds[6],
  MachineDescription& machine)
{
  MethodResult result;
  result.method = "k" + std::to_string(order) + ":dipy-" + sphere.name;
  result.triangles = expectedGlyphs * static_cast<long long>(sphere.faces.size());
  if (result.triangles > options.maxTriangles)
  {
    result.skipped = true;
    result.notes = "skipped: " + std::to_string(result.triangles) +
      " triangles exceed the budget of " + std::to_string(options.maxTriangles) +
      " (--max-triangles)";
    return result;
  }
  vtkSmartPointer<vtkCamera> camera = makeCamera(bounds);
  Window window(options, camera);
  machine.describeOpenGL(window.window);

  // The glyphs are as large as Sightline's: a normalised radius of 1 is half the voxel step
  // (the mapper's default ScaleFactor 1 for image input).
  double spacing[3];
  image->GetSpacing(spacing);
  const double radius = 0.5 * std::min(spacing[0], spacing[1]);

  const Memory memory;
  GlyphMesh mesh;
  vtkNew<vtkActor> actor;
  vtkSmartPointer<vtkPolyDataMapper> mapper;
  double meshSeconds = 0.0;
  result.firstImageSeconds = timeOnce(
    [&]
    {
      meshSeconds = timeOnce([&] { mesh = buildGlyphMesh(image, order, sphere, radius); });
      mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
      mapper->SetInputData(mesh.polyData);
      mapper->ScalarVisibilityOn();
      mapper->SetScalarModeToUsePointData();
      mapper->SetColorModeToDirectScalars();
      actor->SetMapper(mapper);
      window.renderer->AddActor(actor);
      window.firstFrame();
    });
  const long long rssIncrease = memory.increase(), rssPeak = memory.peakIncrease();
  result.triangles = mesh.polyData->GetNumberOfPolys();
  result.image = captureWindow(window.window);
  result.buildSeconds = meshSeconds;
  result.memoryBytes = double(mesh.polyData->GetActualMemorySize()) * 1024.0;
  result.bytesPerPrimitive = result.memoryBytes / double(std::max<long long>(1, mesh.glyphs));
  result.rssIncreaseBytes = double(rssIncrease);
  result.frame = window.movingFrames(options.runs, kStillUpdateRate);
  result.interactiveFrame = window.movingFrames(options.runs, kInteractiveUpdateRate);

  std::ostringstream notes;
  notes << mesh.glyphs << " glyphs x " << sphere.vertices.size() << " vertices / "
        << sphere.faces.size() << " triangles (DIPY " << sphere.name
        << "), odf_slicer-style: |F| normalised by the sampled maximum, direction colours, "
           "area-weighted normals, vtkPolyDataMapper; first image: mesh "
        << fixed(meshSeconds, 3) << " s (TBB, into VTK arrays), upload + first frame "
        << fixed(result.firstImageSeconds - meshSeconds, 3) << " s; memory: vtkPolyData "
        << megabytes(result.memoryBytes) << ", RSS +" << megabytes(double(rssIncrease))
        << " (peak +" << megabytes(double(rssPeak)) << ", includes Mesa's buffer copies)";
  result.notes = notes.str();
  window.renderer->RemoveActor(actor);
  return result;
}

std::vector<int> sphereVertexCounts(const Options& options)
{
  return options.tessellations == kHarnessDefaultTessellations ? kDefaultSphereVertices
                                                               : options.tessellations;
}

void printSummary(const std::vector<MethodResult>& results)
{
  std::cout << "\nSH glyph window: per method and k (errors against the same k's sightline)\n"
            << std::left << std::setw(24) << "method" << std::right << std::setw(11) << "1st img s"
            << std::setw(10) << "still s" << std::setw(10) << "inter. s" << std::setw(10)
            << "update s" << std::setw(12) << "memory MB" << std::setw(10) << "RSS+ MB"
            << std::setw(10) << "RGB err" << std::setw(10) << "cover %" << std::setw(12)
            << "triangles" << "\n";
  for (const MethodResult& r : results)
  {
    std::cout << std::left << std::setw(24) << r.method << std::right;
    if (r.skipped)
    {
      std::cout << " " << r.notes << "\n";
      continue;
    }
    std::cout << std::setw(11) << fixed(r.firstImageSeconds, 3) << std::setw(10)
              << fixed(r.frame.medianSeconds, 3) << std::setw(10)
              << fixed(r.interactiveFrame.medianSeconds, 3) << std::setw(10)
              << fixed(r.updateSeconds, 3) << std::setw(12) << fixed(r.memoryBytes / 1e6, 1)
              << std::setw(10) << fixed(r.rssIncreaseBytes / 1e6, 1) << std::setw(10)
              << fixed(r.error.rgbMeanAbsDiff, 3) << std::setw(10)
              << fixed(r.error.coverageDiffPercent, 3) << std::setw(12) << r.triangles << "\n";
  }
}

//------------------------------------------------------------------------------
std::vector<MethodResult> runSHGlyphWindowScene(
  const Options& options, long long count, MachineDescription& machine)
{
  // The count is the slice's voxels: a side x side tiling.
  const int side = int(std::llround(std::sqrt(double(count))));
  if (side < 1 || (long long)side * side != count)
    throw std::invalid_argument("sh-glyph-window: --count must be a square (side x side voxels)");
  const std::vector<int> sphereCounts = sphereVertexCounts(options);
  const int orders[] = { 8, 4 };

  std::vector<MethodResult> results;
  auto add = [&](MethodResult result)
  {
    result.primitives = count;
    result.width = options.width;
    result.height = options.height;
    results.push_back(std::move(result));
  };
  if (!openGLAvailable())
  {
    logProgress("sh-glyph-window: no display; every method needs OpenGL (run under xvfb-run)");
    for (int order : orders)
    {
      std::vector<std::string> names{ "sightline" };
      for (int vertices : sphereCounts)
        names.push_back("dipy-" + dipySphereName(vertices));
      for (const std::string& name : names)
      {
        MethodResult skipped;
        skipped.method = "k" + std::to_string(order) + ":" + name;
        skipped.skipped = true;
        skipped.notes = "skipped: no display for OpenGL (run under xvfb-run)";
        add(std::move(skipped));
      }
    }
    return results;
  }

  const fs::path file = tiledSliceFile(options, side);
  const std::vector<DipySphere> spheres = loadDipySpheres(options, sphereCounts);
  // Read once for every method (reading is the same for all of them, and not what is compared).
  logProgress("sh-glyph-window: reading " + file.string());
  vtkNew<vtkNIFTIImageReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->TimeAsVectorOn();
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  if (!image->GetPointData()->GetScalars() ||
    image->GetPointData()->GetScalars()->GetNumberOfComponents() !=
      sightline::shCoefficientCount(8))
    throw std::runtime_error(file.string() + " does not hold 45 SH coefficients per voxel");
  // Glyph bounds: the slice plus one glyph radius (half the voxel step) all round.
  double bounds[6], spacing[3];
  image->GetBounds(bounds);
  image->GetSpacing(spacing);
  const double glyphRadius = 0.5 * std::min(spacing[0], spacing[1]);
  for (int axis = 0; axis < 3; ++axis)
  {
    bounds[2 * axis] -= glyphRadius;
    bounds[2 * axis + 1] += glyphRadius;
  }

  const fs::path images = fs::path(options.outputDirectory) / "images";
  fs::create_directories(images);
  for (int order : orders)
  {
    const std::string prefix = "k" + std::to_string(order) + ":";
    logProgress("sh-glyph-window: " + prefix + "sightline");
    const std::size_t first = results.size();
    long long glyphs = 0;
    add(runSightline(options, reader, order, bounds, machine, glyphs));
    for (const DipySphere& sphere : spheres)
    {
      logProgress("sh-glyph-window: " + prefix + "dipy-" + sphere.name);
      add(runMesh(options, image, order, sphere, glyphs, bounds, machine));
    }

    // Errors against this k's exact image (computed here: the harness knows one reference).
    const MethodResult& reference = results[first];
    for (std::size_t i = first; i < results.size(); ++i)
    {
      MethodResult& result = results[i];
      if (result.skipped)
        continue;
      result.error = compareImages(result.image, reference.image);
      if (i == first)
      {
        result.notes = "reference image of " + prefix.substr(0, prefix.size() - 1) + "; " +
          result.notes;
        continue;
      }
      std::ostringstream extra;
      // Glyphs cover a few percent of the image: relative to the exact glyphs' pixels, the
      // coverage error says how much of the glyphs themselves is drawn wrongly.
      const double referenceHit = hitPercent(reference.image);
      extra << "; coverage differs on " << std::setprecision(3)
            << 100.0 * result.error.coverageDiffPercent / std::max(referenceHit, 1e-9)
            << " % of the exact glyphs' " << referenceHit << " % of the pixels; pixels differing > " << kPixelThreshold << "/255: " << std::setprecision(3)
            << differingPixelPercent(result.image, reference.image) << " %; still frame x"
            << std::setprecision(3) << result.frame.medianSeconds / reference.frame.medianSeconds
            << ", first image x" << result.firstImageSeconds / reference.firstImageSeconds
            << " of " << reference.method;
      result.notes += extra.str();
      writeDifferencePNG(result.image, reference.image,
        (images / ("sh-glyph-window-" + std::to_string(count) + "-" + result.method + "-diff.png"))
          .string());
    }
  }
  printSummary(results);
  return results;
}

const SceneRegistration registration{ "sh-glyph-window",
  "a 140x140 slice of real SH glyphs (make_sh_data.py's tiled CSD of DIPY's small_64D) in a "
  "render window at k = 8 and 4: vtkSightlineSHGlyphMapper against odf_slicer-style meshes on "
  "DIPY's spheres; time to first image, still and interactive frames, memory, a ScaleFactor "
  "update, image error; --tessellation gives DIPY sphere vertex counts (724,100 by default); "
  "--count side*side voxels; --data-dir for the data",
  { 19600 }, &runSHGlyphWindowScene };
} // namespace
} // namespace sightline_benchmark
