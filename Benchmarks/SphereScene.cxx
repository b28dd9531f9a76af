// SPDX-License-Identifier: BSD-3-Clause
// The sphere scene: random spheres in a unit cube, rendered
// - exactly by Sightline, GL-free (vtkSightlineImageRenderer) and in a window (vtkSightlineMapper);
// - exactly by Embree's own sphere primitive (the reference image);
// - as vtkSphereSource glyphs rasterised by vtkPolyDataMapper at several resolutions.
#include "SceneRegistry.h"

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataObject.h"
#include "vtkFloatArray.h"
#include "vtkGlyph3D.h"
#include "vtkImageData.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "SightlineKernelConversions.h" // the matrix conversion every Sightline mapper uses
#include "vtkSightlineImageRenderer.h"
#include "vtkSightlineSphereMapper.h"
#include "vtkSphereSource.h"
#include "vtkUnsignedCharArray.h"

#include "sightline/core/Camera.h"
#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Framebuffer.h"
#include "sightline/core/Renderer.h"
#include "sightline/core/Shading.h"
#include "sightline/spheres/SphereSet.h"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

namespace sightline_benchmark
{
namespace
{
const double kBackground[3] = { 0.1, 0.1, 0.12 };
// Mean number of spheres a ray crosses when it passes straight through the cube: about 78%
// of the cube's silhouette is covered, so the image is well covered but not saturated.
constexpr double kOpticalDepth = 3.0;
// ResetCamera fits the cube's bounding sphere; zooming in fills the image with the cube.
constexpr double kZoom = 1.2;
// Radii vary uniformly in [0.5, 1.5] x the base radius.
constexpr double kMinRadiusFactor = 0.5;
constexpr double kMaxRadiusFactor = 1.5;

/// The scene's spheres, both as VTK data (what the VTK methods consume) and as plain arrays
/// (what the Embree reference and the kernel byte count consume).
struct Spheres
{
  vtkSmartPointer<vtkPolyData> polyData; ///< points, "Radius" and active scalars "Colors" (RGB)
  std::vector<sightline::vec3> centers;
  std::vector<float> radii;
  std::vector<std::uint32_t> colors; ///< packed RGBA8
  double baseRadius = 0.0;
};

Spheres makeSpheres(long long count, unsigned seed)
{
  // With uniform factors u in [a, b], E[u^2] = (b^3 - a^3) / (3 (b - a)); choose the base
  // radius so that count * pi * E[r^2] over the unit square equals the optical depth.
  const double a = kMinRadiusFactor, b = kMaxRadiusFactor;
  const double meanSquaredFactor = (b * b * b - a * a * a) / (3.0 * (b - a));
  Spheres spheres;
  spheres.baseRadius = std::sqrt(kOpticalDepth / (M_PI * double(count) * meanSquaredFactor));

  std::mt19937 random(seed);
  std::uniform_real_distribution<float> position(0.0f, 1.0f);
  std::uniform_real_distribution<float> factor{ float(a), float(b) };
  std::uniform_int_distribution<int> channel(60, 255);

  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(count);
  vtkNew<vtkFloatArray> radius;
  radius->SetName("Radius");
  radius->SetNumberOfTuples(count);
  vtkNew<vtkUnsignedCharArray> color;
  color->SetName("Colors");
  color->SetNumberOfComponents(3);
  color->SetNumberOfTuples(count);
  spheres.centers.resize(count);
  spheres.radii.resize(count);
  spheres.colors.resize(count);
  for (long long i = 0; i < count; ++i)
  {
    const sightline::vec3 center(position(random), position(random), position(random));
    const float r = float(spheres.baseRadius) * factor(random);
    const unsigned char rgb[3] = { static_cast<unsigned char>(channel(random)),
      static_cast<unsigned char>(channel(random)), static_cast<unsigned char>(channel(random)) };
    points->SetPoint(i, center.x, center.y, center.z);
    radius->SetValue(i, r);
    color->SetTypedTuple(i, rgb);
    spheres.centers[i] = center;
    spheres.radii[i] = r;
    spheres.colors[i] = sightline::packRGBA8(rgb[0], rgb[1], rgb[2]);
  }
  spheres.polyData = vtkSmartPointer<vtkPolyData>::New();
  spheres.polyData->SetPoints(points);
  spheres.polyData->GetPointData()->AddArray(radius);
  spheres.polyData->GetPointData()->SetScalars(color);
  return spheres;
}

/// The camera every method uses: an oblique view of the cube, framed by ResetCamera. Its
/// clipping range is kept fixed afterwards so that window depths are comparable.
vtkSmartPointer<vtkCamera> makeCamera(vtkActor* sphereActor, int width, int height)
{
  auto camera = vtkSmartPointer<vtkCamera>::New();
  camera->Azimuth(30.0);
  camera->Elevation(25.0);
  camera->OrthogonalizeViewUp();
  vtkNew<vtkSightlineImageRenderer> framer;
  framer->SetSize(width, height);
  framer->AddActor(sphereActor);
  framer->SetActiveCamera(camera);
  framer->ResetCamera();
  camera->Zoom(kZoom); // changes the view angle only: the clipping range stays valid
  return camera;
}

vtkSmartPointer<vtkActor> makeSightlineActor(const Spheres& spheres)
{
  vtkNew<vtkSightlineSphereMapper> mapper;
  mapper->SetInputDataObject(spheres.polyData);
  mapper->SetRadiusArrayName("Radius");
  mapper->SetColorModeToDirectScalars();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

std::string formatSeconds(double seconds)
{
  std::ostringstream s;
  s.precision(3);
  s << seconds << " s";
  return s.str();
}

// Checks that no method moved the clipping planes (window depth depends on them).
void checkClippingRange(vtkCamera* camera, const double expected[2], const std::string& method)
{
  double range[2];
  camera->GetClippingRange(range);
  if (range[0] != expected[0] || range[1] != expected[1])
  {
    throw std::runtime_error(method + " changed the camera's clipping range");
  }
}

//------------------------------------------------------------------------------
// embree-builtin: Embree's RTC_GEOMETRY_TYPE_SPHERE_POINT, traced by a loop of its own with the
// kernel's camera and shading. Independent of Sightline's sphere intersection, user-geometry
// callbacks and pixel loop, so it serves as the reference image.
class EmbreeBuiltinSpheres : public sightline::Geometry
{
public:
  explicit EmbreeBuiltinSpheres(const Spheres& spheres)
    : Colors(spheres.colors)
  {
    // One spare element: Embree may read vertex buffers with 16-byte loads past the end.
    Vertices.resize(spheres.centers.size() + 1);
    for (std::size_t i = 0; i < spheres.centers.size(); ++i)
    {
      Vertices[i] = sightline::vec4(spheres.centers[i], spheres.radii[i]);
    }
  }

  std::size_t size() const override { return Vertices.size() - 1; }
  RTCGeometry createEmbreeGeometry(RTCDevice device) const override
  {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
      Vertices.data(), 0, sizeof(sightline::vec4), this->size());
    rtcCommitGeometry(geometry);
    return geometry;
  }
  bool hasPrimitiveColors() const override { return true; }
  sightline::vec3 primitiveColor(unsigned primitive) const override
  {
    const std::uint32_t c = Colors[primitive];
    return sightline::vec3(c & 0xffu, (c >> 8) & 0xffu, (c >> 16) & 0xffu) / 255.0f;
  }
  std::size_t memoryBytes() const override
  {
    return Vertices.capacity() * sizeof(sightline::vec4) +
      Colors.capacity() * sizeof(std::uint32_t);
  }
  sightline::Box3 bounds() const override
  {
    sightline::Box3 box;
    for (std::size_t i = 0; i < this->size(); ++i)
    {
      box.extend(sightline::vec3(Vertices[i]) - Vertices[i].w);
      box.extend(sightline::vec3(Vertices[i]) + Vertices[i].w);
    }
    return box;
  }

private:
  std::vector<sightline::vec4> Vertices;
  std::vector<std::uint32_t> Colors;
};

void traceReference(const sightline::EmbreeScene& scene, const sightline::Camera& camera,
  const sightline::Lighting& lighting, sightline::Framebuffer& framebuffer)
{
  framebuffer.resize(camera.width(), camera.height());
  const sightline::Geometry& geometry = scene.geometry(0);
  const sightline::Material material; // vtkProperty's defaults, as the VTK methods use
  // Packets of the machine's native size over blocks of each tile, as Sightline traces.
  const int packetSize = scene.device().packetSize();
  const sightline::PacketBlock block = sightline::packetBlock(packetSize);
  tbb::parallel_for(tbb::blocked_range2d<int>(0, camera.height(), 16, 0, camera.width(), 16),
    [&](const tbb::blocked_range2d<int>& tile)
    {
      for (int y0 = tile.rows().begin(); y0 < tile.rows().end(); y0 += block.rows)
      {
        for (int x0 = tile.cols().begin(); x0 < tile.cols().end(); x0 += block.columns)
        {
          sightline::DoubleRay rays[sightline::EmbreeScene::kMaxPacket];
          bool active[sightline::EmbreeScene::kMaxPacket];
          sightline::SceneHit hits[sightline::EmbreeScene::kMaxPacket];
          bool found[sightline::EmbreeScene::kMaxPacket];
          for (int lane = 0; lane < packetSize; ++lane)
          {
            const int x = x0 + lane % block.columns, y = y0 + lane / block.columns;
            active[lane] = x < tile.cols().end() && y < tile.rows().end();
            // Embree traces the float rounding of the ray (its built-in spheres are float).
            rays[lane] = sightline::DoubleRay(camera.primaryRay(x + 0.5, y + 0.5));
          }
          scene.intersectPacket(rays, active, packetSize, hits, found, true);
          for (int lane = 0; lane < packetSize; ++lane)
          {
            if (!found[lane])
            {
              continue;
            }
            const sightline::Ray ray = rays[lane].rounded();
            const sightline::vec3 toViewer = -ray.direction;
            sightline::vec3 normal = glm::normalize(hits[lane].normal);
            if (glm::dot(normal, toViewer) < 0.0f)
            {
              normal = -normal;
            }
            const sightline::vec3 color = geometry.primitiveColor(hits[lane].primID);
            const sightline::vec3 rgb =
              sightline::shade(material, color, color, normal, toViewer, lighting);
            const sightline::dvec3 hitPoint =
              sightline::dvec3(ray.origin) + hits[lane].t * sightline::dvec3(ray.direction);
            const std::size_t i = framebuffer.index(x0 + lane % block.columns, y0 + lane / block.columns);
            framebuffer.Color[i] = sightline::vec4(rgb, 1.0f);
            framebuffer.Depth[i] = float(std::clamp(camera.windowDepth(hitPoint), 0.0, 1.0));
            framebuffer.Distance[i] = float(hits[lane].t);
          }
        }
      }
    });
}

MethodResult runEmbreeBuiltin(
  const Options& options, const Spheres& spheres, vtkCamera* camera, long long count)
{
  MethodResult result;
  result.method = "embree-builtin";
  result.isReference = true;
  // A device of its own, so that its memory monitor sees only this scene.
  auto device = std::make_shared<sightline::EmbreeDevice>();
  std::unique_ptr<sightline::EmbreeScene> scene;
  const int width = options.width, height = options.height;
  const sightline::Camera view(
    SightlineKernelConversions::ToKernelMatrix(camera->GetCompositeProjectionTransformMatrix(double(width) / height, -1, 1)), width,
    height);
  double position[3], focal[3];
  camera->GetPosition(position);
  camera->GetFocalPoint(focal);
  const sightline::Lighting headlight = sightline::Lighting::headlight(
    sightline::vec3(focal[0] - position[0], focal[1] - position[1], focal[2] - position[2]));
  sightline::Framebuffer framebuffer;

  result.firstImageSeconds = timeOnce(
    [&]
    {
      scene = std::make_unique<sightline::EmbreeScene>(device);
      scene->add(std::make_shared<EmbreeBuiltinSpheres>(spheres));
      scene->commit();
      traceReference(*scene, view, headlight, framebuffer);
    });
  result.buildSeconds = scene->buildSeconds();
  result.frame =
    timeFrames(options.runs, [&] { traceReference(*scene, view, headlight, framebuffer); });
  result.bytesPerPrimitive = double(scene->geometryBytes() + scene->bvhBytes()) / count;
  result.image = imageFromFramebuffer(framebuffer, kBackground);
  std::ostringstream notes;
  notes << "reference; RTC_GEOMETRY_TYPE_SPHERE_POINT, build quality high; BVH "
        << scene->bvhBytes() / double(count) << " B/sphere";
  result.notes = notes.str();
  return result;
}

//------------------------------------------------------------------------------
// The bytes Sightline holds per sphere: its kernel SphereSet (an equivalent one is built here,
// as the mapper keeps its own private) plus the BVH measured by Embree's memory monitor.
std::size_t sphereSetBytes(const Spheres& spheres)
{
  return sightline::SphereSet(spheres.centers, spheres.radii, 1.0f, spheres.colors).memoryBytes();
}

MethodResult runSightlineImage(
  const Options& options, const Spheres& spheres, vtkCamera* camera, long long count)
{
  MethodResult result;
  result.method = "sightline";
  vtkSmartPointer<vtkActor> actor = makeSightlineActor(spheres);
  auto* mapper = vtkSightlineMapper::SafeDownCast(actor->GetMapper());
  vtkNew<vtkSightlineImageRenderer> renderer;
  renderer->SetSize(options.width, options.height);
  renderer->SetBackground(kBackground[0], kBackground[1], kBackground[2]);
  renderer->AddActor(actor);
  renderer->SetActiveCamera(camera);

  // The mapper builds its BVH on the process-wide device; holding it keeps the byte counter.
  const std::shared_ptr<sightline::EmbreeDevice> device = sightline::EmbreeDevice::shared();
  const std::int64_t bytesBefore = device->allocatedBytes();
  result.firstImageSeconds = timeOnce([&] { renderer->Update(); });
  const std::int64_t bvhBytes = device->allocatedBytes() - bytesBefore;
  result.buildSeconds = mapper->GetLastBuildSeconds();

  std::vector<double> traceSeconds;
  result.frame = timeFrames(options.runs,
    [&]
    {
      renderer->Modified(); // re-executes the ray tracing; the BVH is kept
      renderer->Update();
      traceSeconds.push_back(mapper->GetLastFrameSeconds());
    });
  result.bytesPerPrimitive = double(sphereSetBytes(spheres) + bvhBytes) / count;
  result.image = imageFromSightlineOutput(renderer->GetOutput());
  std::sort(traceSeconds.begin(), traceSeconds.end());
  std::ostringstream notes;
  notes << "vtkSightlineImageRenderer (no OpenGL); BVH " << double(bvhBytes) / count << " B/sphere";
  if (!traceSeconds.empty())
  {
    notes << "; kernel trace alone " << formatSeconds(traceSeconds[traceSeconds.size() / 2]);
  }
  result.notes = notes.str();
  return result;
}

//------------------------------------------------------------------------------
/// An offscreen window with one renderer showing `actor` through `camera`, already rendered
/// once with the actor hidden so that creating the OpenGL context is not counted as building.
struct WindowScene
{
  vtkSmartPointer<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;

  WindowScene(const Options& options, vtkActor* actor, vtkCamera* camera)
    : window(makeOffscreenWindow(options.width, options.height))
  {
    renderer->SetBackground(kBackground[0], kBackground[1], kBackground[2]);
    renderer->SetActiveCamera(camera);
    renderer->AddActor(actor);
    window->AddRenderer(renderer);
    actor->VisibilityOff();
    window->Render();
    actor->VisibilityOn();
  }
  ~WindowScene() { window->Finalize(); }

  /// One frame, finished (glFinish) before returning so its full cost is timed.
  void renderFrame()
  {
    window->Render();
    window->WaitForCompletion();
  }
};

MethodResult runSightlineWindow(const Options& options, const Spheres& spheres, vtkCamera* camera,
  long long count, MachineDescription& machine)
{
  MethodResult result;
  result.method = "sightline-window";
  // A mapper of its own (same input and settings), so its BVH build and first frame are timed
  // as a window application would see them.
  vtkSmartPointer<vtkActor> actor = makeSightlineActor(spheres);
  auto* mapper = vtkSightlineMapper::SafeDownCast(actor->GetMapper());
  WindowScene scene(options, actor, camera);
  machine.describeOpenGL(scene.window);

  // The mapper reports progress only while it traces: counting the events proves that each
  // timed frame was traced again rather than served from its frame cache.
  int progressEvents = 0;
  vtkNew<vtkCallbackCommand> countProgress;
  countProgress->SetClientData(&progressEvents);
  countProgress->SetCallback(
    [](vtkObject*, unsigned long, void* counter, void*) { ++*static_cast<int*>(counter); });
  mapper->AddObserver(vtkCommand::ProgressEvent, countProgress);

  const std::shared_ptr<sightline::EmbreeDevice> device = sightline::EmbreeDevice::shared();
  const std::int64_t bytesBefore = device->allocatedBytes();
  result.firstImageSeconds = timeOnce([&] { scene.renderFrame(); });
  const std::int64_t bvhBytes = device->allocatedBytes() - bytesBefore;
  result.buildSeconds = mapper->GetLastBuildSeconds();

  result.frame = timeFrames(options.runs,
    [&]
    {
      const int before = progressEvents;
      actor->GetProperty()->Modified(); // part of the mapper's frame key: forces a re-trace
      scene.renderFrame();
      if (progressEvents == before)
      {
        throw std::runtime_error("sightline-window: a timed frame was not ray-traced again");
      }
    });
  result.bytesPerPrimitive = double(sphereSetBytes(spheres) + bvhBytes) / count;
  result.image = captureWindow(scene.window);
  result.notes = "vtkSightlineMapper in an offscreen vtkRenderWindow; frame = trace + upload "
                 "+ composite";
  return result;
}

//------------------------------------------------------------------------------
long long sphereSourceTriangles(int resolution)
{
  // vtkSphereSource with theta = phi = R: two caps of R triangles and R (R - 3) quads split in two.
  return 2LL * resolution * (resolution - 2);
}

std::size_t arrayBytes(vtkDataArray* array)
{
  return array ? static_cast<std::size_t>(array->GetNumberOfValues()) * array->GetDataTypeSize()
               : 0;
}

MethodResult runTessellated(const Options& options, const Spheres& spheres, vtkCamera* camera,
  long long count, int resolution, MachineDescription& machine)
{
  MethodResult result;
  result.method = "vtk-tessellated-" + std::to_string(resolution);
  result.triangles = count * sphereSourceTriangles(resolution);
  if (result.triangles > options.maxTriangles)
  {
    result.skipped = true;
    std::ostringstream notes;
    notes << "skipped: " << result.triangles << " triangles exceed the budget of "
          << options.maxTriangles << " (--max-triangles)";
    result.notes = notes.str();
    return result;
  }

  auto tessellated = vtkSmartPointer<vtkPolyData>::New();
  const double glyphSeconds = timeOnce(
    [&]
    {
      vtkNew<vtkSphereSource> sphere;
      sphere->SetThetaResolution(resolution);
      sphere->SetPhiResolution(resolution);
      sphere->SetRadius(1.0); // scaled by each sphere's radius
      vtkNew<vtkGlyph3D> glyph;
      glyph->SetSourceConnection(sphere->GetOutputPort());
      glyph->SetInputData(spheres.polyData);
      glyph->OrientOff();
      glyph->SetScaleModeToScaleByScalar();
      glyph->SetScaleFactor(1.0);
      glyph->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "Radius");
      glyph->SetColorModeToColorByScalar();
      glyph->SetInputArrayToProcess(3, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "Colors");
      glyph->SetOutputPointsPrecision(vtkAlgorithm::SINGLE_PRECISION);
      glyph->Update();
      // Keep what rendering needs (points, triangles, normals, colours) and drop the copied
      // radius array, so memory holds only what is counted.
      vtkPolyData* output = glyph->GetOutput();
      tessellated->SetPoints(output->GetPoints());
      tessellated->SetPolys(output->GetPolys());
      tessellated->GetPointData()->SetNormals(output->GetPointData()->GetNormals());
      tessellated->GetPointData()->SetScalars(output->GetPointData()->GetArray("Colors"));
    });
  if (tessellated->GetNumberOfPolys() != result.triangles ||
    !tessellated->GetPointData()->GetScalars() || !tessellated->GetPointData()->GetNormals())
  {
    throw std::runtime_error(result.method + ": vtkGlyph3D did not produce the expected " +
      std::to_string(result.triangles) + " triangles with normals and colours");
  }

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(tessellated);
  mapper->ScalarVisibilityOn();
  mapper->SetScalarModeToUsePointData();
  mapper->SetColorModeToDirectScalars();
  mapper->StaticOn();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  WindowScene scene(options, actor, camera);
  machine.describeOpenGL(scene.window);

  const double uploadSeconds = timeOnce([&] { scene.renderFrame(); });
  result.buildSeconds = glyphSeconds + uploadSeconds;
  result.firstImageSeconds = result.buildSeconds;
  // VTK redraws every Render(); Mesa rasterises all triangles again each time.
  result.frame = timeFrames(options.runs, [&] { scene.renderFrame(); });

  vtkCellArray* polys = tessellated->GetPolys();
  const std::size_t bytes = arrayBytes(tessellated->GetPoints()->GetData()) +
    arrayBytes(tessellated->GetPointData()->GetNormals()) +
    arrayBytes(tessellated->GetPointData()->GetScalars()) + arrayBytes(polys->GetOffsetsArray()) +
    arrayBytes(polys->GetConnectivityArray());
  result.bytesPerPrimitive = double(bytes) / count;
  result.image = captureWindow(scene.window);
  std::ostringstream notes;
  notes << "vtkSphereSource(" << resolution << "x" << resolution << ") glyphs, "
        << sphereSourceTriangles(resolution) << " triangles/sphere; glyphing "
        << formatSeconds(glyphSeconds) << ", upload + first frame " << formatSeconds(uploadSeconds)
        << "; bytes = vtkPolyData points+normals+colours+cells (GPU copy not counted)";
  result.notes = notes.str();
  return result;
}

//------------------------------------------------------------------------------
std::vector<MethodResult> runSphereScene(
  const Options& options, long long count, MachineDescription& machine)
{
  logProgress("spheres: generating " + std::to_string(count) + " spheres");
  const Spheres spheres = makeSpheres(count, options.seed);
  vtkSmartPointer<vtkCamera> camera =
    makeCamera(makeSightlineActor(spheres), options.width, options.height);
  double clippingRange[2];
  camera->GetClippingRange(clippingRange);

  std::vector<MethodResult> results;
  auto add = [&](MethodResult result)
  {
    checkClippingRange(camera, clippingRange, result.method);
    result.primitives = count;
    result.width = options.width;
    result.height = options.height;
    results.push_back(std::move(result));
  };

  logProgress("spheres: embree-builtin (reference)");
  add(runEmbreeBuiltin(options, spheres, camera, count));
  logProgress("spheres: sightline");
  add(runSightlineImage(options, spheres, camera, count));

  std::vector<std::string> openGLMethods{ "sightline-window" };
  for (int resolution : options.tessellations)
  {
    openGLMethods.push_back("vtk-tessellated-" + std::to_string(resolution));
  }
  if (!openGLAvailable())
  {
    logProgress("spheres: no display; the OpenGL methods are skipped (run under xvfb-run)");
    for (const std::string& method : openGLMethods)
    {
      MethodResult skipped;
      skipped.method = method;
      skipped.skipped = true;
      skipped.notes = "skipped: no display for OpenGL (run under xvfb-run)";
      add(std::move(skipped));
    }
    return results;
  }

  logProgress("spheres: sightline-window");
  add(runSightlineWindow(options, spheres, camera, count, machine));
  for (int resolution : options.tessellations)
  {
    logProgress("spheres: vtk-tessellated-" + std::to_string(resolution));
    add(runTessellated(options, spheres, camera, count, resolution, machine));
  }
  return results;
}

const SceneRegistration registration{ "spheres",
  "random spheres (radius 0.5-1.5x) in a cube: Sightline vs Embree's built-in spheres vs "
  "vtkSphereSource glyphs in vtkPolyDataMapper",
  { 100000, 1000000 }, &runSphereScene };
} // namespace
} // namespace sightline_benchmark
