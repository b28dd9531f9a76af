// SPDX-License-Identifier: BSD-3-Clause
// The generalized-tube scenes (Han et al. 2019), everything ray-traced through the kernel's
// Renderer at the same camera, light and material, one BVH per method, timed round robin:
// - "tubes": neuron assemblies (copies of a synthetic base neuron of ~2,000 links at random
//   positions and rotations, the paper's Section 6 generator), far view; bifurcating data;
// - "tube-chains": smooth non-branching streamlines (tractography-like, radius varying along
//   each line), the data Embree's built-in curves can express.
// Methods:
// - embree-round-curves: Embree's RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE, the same swept-sphere
//   shape, independent of Sightline's intersection code: the reference image. Bifurcations are
//   emulated by duplicating the branch point at the start of each further branch (interior
//   surfaces there do not show in opaque images);
// - sightline:<layout>: the four implementation choices of the paper's Table 1 (combined /
//   separate primitives x on-the-fly / precomputed stumps), opaque first-hit traversal;
// - sightline:chunked-K: runs of up to K consecutive links as one BVH primitive (K = 4, 8, 16,
//   32; the tractogram layout, TubeLayout::Primitives::Chunked), opaque first-hit traversal;
// - sightline-csg: the default layout through the translucent (all-hit CSG union) path at
//   opacity 1, the paper's Section 6.3 measure of the CSG overhead;
// - sightline-translucent-0.4: the same at opacity 0.4, a real transparent frame (its image is
//   not comparable with the opaque reference);
// - vtk-tube-filter-N: vtkTubeFilter with N sides (capped, radius by absolute scalar) over the
//   same unbranched sections, triangulated and ray-traced as Embree triangles with the filter's
//   vertex normals.
#include "GlyphSceneSupport.h"
#include "SceneRegistry.h"

#include "sightline/baselines/TriangleMesh.h"
#include "sightline/baselines/TubeAssembly.h"
#include "sightline/tubes/TubeSet.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTriangleFilter.h"
#include "vtkTubeFilter.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

namespace sightline_benchmark
{
namespace
{
using sightline::TubeLayout;
using sightline::TubeTree;
using sightline::vec3;
using sightline::vec4;

constexpr std::size_t kBaseNeuronLinks = 2000;
/// Cube edge per neuron (um): neighbouring neurons interpenetrate, as in real tissue models.
constexpr float kNeuronSpacing = 120.0f;
constexpr std::size_t kLinksPerStreamline = 100;

/// The unbranched sections of a tree as runs of consecutive vertices: each run starts at a root
/// or at a duplicate of a branch point, so a segment always joins vertices i and i + 1.
struct Sections
{
  std::vector<vec4> vertices;            ///< position and radius
  std::vector<std::uint32_t> colors;     ///< per vertex
  std::vector<std::uint32_t> runStarts;  ///< first vertex of each run
  std::vector<std::uint32_t> runLengths; ///< vertices in each run (>= 1)
};

Sections sectionsOf(const TubeTree& tree)
{
  const std::size_t n = tree.size();
  std::vector<std::int64_t> firstChild(n, -1), nextSibling(n, -1);
  for (std::size_t i = n; i-- > 0;)
    if (tree.predecessors[i] >= 0)
    {
      const std::size_t p = std::size_t(tree.predecessors[i]);
      nextSibling[i] = firstChild[p];
      firstChild[p] = std::int64_t(i);
    }
  Sections s;
  s.vertices.reserve(n + n / 8);
  s.colors.reserve(n + n / 8);
  auto emit = [&](std::size_t i)
  {
    s.vertices.push_back(vec4(tree.points[i], tree.radii[i]));
    s.colors.push_back(tree.colors.empty() ? 0xffffffffu : tree.colors[i]);
  };
  // Runs start at roots and at every child but the first of a point; each run follows first
  // children to a tip.
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i < n; ++i)
    if (tree.predecessors[i] < 0)
      starts.push_back(i);
  for (std::size_t k = 0; k < starts.size(); ++k)
  {
    const std::size_t start = starts[k];
    s.runStarts.push_back(std::uint32_t(s.vertices.size()));
    if (tree.predecessors[start] >= 0)
      emit(std::size_t(tree.predecessors[start])); // the duplicated branch point
    for (std::int64_t i = std::int64_t(start); i >= 0; i = firstChild[std::size_t(i)])
    {
      emit(std::size_t(i));
      for (std::int64_t c = firstChild[std::size_t(i)] >= 0 ? nextSibling[std::size_t(firstChild[std::size_t(i)])] : -1;
           c >= 0; c = nextSibling[std::size_t(c)])
        starts.push_back(std::size_t(c));
    }
    s.runLengths.push_back(std::uint32_t(s.vertices.size()) - s.runStarts.back());
  }
  return s;
}

vec3 unpackColor(std::uint32_t c)
{
  return vec3(float(c & 0xffu), float((c >> 8) & 0xffu), float((c >> 16) & 0xffu)) / 255.0f;
}

/// Embree's built-in round linear curves over the sections (a lone root is a zero-length
/// segment: a sphere).
class EmbreeRoundCurves : public sightline::Geometry
{
public:
  explicit EmbreeRoundCurves(const Sections& sections)
    : Vertices(sections.vertices)
  {
    for (std::size_t r = 0; r < sections.runStarts.size(); ++r)
    {
      const std::uint32_t start = sections.runStarts[r], length = sections.runLengths[r];
      if (length == 1)
      {
        // A lone point: a zero-length segment between two copies of it (a sphere).
        Indices.push_back(std::uint32_t(Vertices.size()));
        Vertices.push_back(Vertices[start]);
        Vertices.push_back(Vertices[start]);
        Colors.push_back(sections.colors[start]);
        continue;
      }
      for (std::uint32_t k = 0; k + 1 < length; ++k)
      {
        Indices.push_back(start + k);
        Colors.push_back(sections.colors[start + k + 1]);
      }
    }
    // One spare element: Embree may read vertex buffers with 16-byte loads past the end.
    Vertices.push_back(vec4(0.0f));
    Vertices.shrink_to_fit();
    Indices.shrink_to_fit();
  }

  std::size_t size() const override { return Indices.size(); }
  RTCGeometry createEmbreeGeometry(RTCDevice device) const override
  {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, Vertices.data(), 0,
      sizeof(vec4), Vertices.size() - 1);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, Indices.data(), 0,
      sizeof(std::uint32_t), Indices.size());
    rtcCommitGeometry(geometry);
    return geometry;
  }
  bool hasPrimitiveColors() const override { return true; }
  vec3 primitiveColor(unsigned primitive) const override { return unpackColor(Colors[primitive]); }
  std::size_t memoryBytes() const override
  {
    // Colours are shading data every method has; count what the shape needs.
    return Vertices.capacity() * sizeof(vec4) + Indices.capacity() * sizeof(std::uint32_t);
  }
  sightline::Box3 bounds() const override
  {
    sightline::Box3 box;
    for (std::size_t i = 0; i + 1 < Vertices.size(); ++i)
    {
      box.extend(vec3(Vertices[i]) - Vertices[i].w);
      box.extend(vec3(Vertices[i]) + Vertices[i].w);
    }
    return box;
  }

private:
  std::vector<vec4> Vertices;
  std::vector<std::uint32_t> Indices;
  std::vector<std::uint32_t> Colors;
};

/// vtkTubeFilter over the sections, triangulated, as a kernel triangle mesh with the filter's
/// normals and the tubes' colours.
std::shared_ptr<sightline::TriangleMesh> tessellate(const Sections& sections, int sides)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(vtkIdType(sections.vertices.size()));
  vtkNew<vtkFloatArray> radius;
  radius->SetName("Radius");
  radius->SetNumberOfValues(vtkIdType(sections.vertices.size()));
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(vtkIdType(sections.vertices.size()));
  for (std::size_t i = 0; i < sections.vertices.size(); ++i)
  {
    const vec4& v = sections.vertices[i];
    points->SetPoint(vtkIdType(i), v.x, v.y, v.z);
    radius->SetValue(vtkIdType(i), v.w);
    const std::uint32_t c = sections.colors[i];
    const unsigned char rgb[3] = { static_cast<unsigned char>(c & 0xffu),
      static_cast<unsigned char>((c >> 8) & 0xffu), static_cast<unsigned char>((c >> 16) & 0xffu) };
    colors->SetTypedTuple(vtkIdType(i), rgb);
  }
  vtkNew<vtkCellArray> lines;
  for (std::size_t r = 0; r < sections.runStarts.size(); ++r)
  {
    if (sections.runLengths[r] < 2)
      continue; // vtkTubeFilter needs a segment
    lines->InsertNextCell(vtkIdType(sections.runLengths[r]));
    for (std::uint32_t k = 0; k < sections.runLengths[r]; ++k)
      lines->InsertCellPoint(vtkIdType(sections.runStarts[r] + k));
  }
  vtkNew<vtkPolyData> input;
  input->SetPoints(points);
  input->SetLines(lines);
  input->GetPointData()->AddArray(radius);
  input->GetPointData()->SetActiveScalars("Radius");
  input->GetPointData()->AddArray(colors);

  vtkNew<vtkTubeFilter> tubes;
  tubes->SetInputData(input);
  tubes->SetNumberOfSides(sides);
  tubes->SetVaryRadiusToVaryRadiusByAbsoluteScalar();
  tubes->CappingOn();
  tubes->SetOutputPointsPrecision(vtkAlgorithm::SINGLE_PRECISION);
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(tubes->GetOutputPort());
  triangles->PassLinesOff();
  triangles->PassVertsOff();
  triangles->Update();
  vtkPolyData* out = triangles->GetOutput();

  std::vector<vec3> vertices(std::size_t(out->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    vertices[std::size_t(i)] = vec3(p[0], p[1], p[2]);
  }
  std::vector<std::uint32_t> indices;
  indices.reserve(std::size_t(3 * out->GetNumberOfPolys()));
  vtkIdType npts = 0;
  const vtkIdType* ids = nullptr;
  vtkCellArray* polys = out->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
    if (npts == 3)
      indices.insert(indices.end(), { std::uint32_t(ids[0]), std::uint32_t(ids[1]), std::uint32_t(ids[2]) });
  auto mesh = std::make_shared<sightline::TriangleMesh>(std::move(vertices), std::move(indices));
  if (vtkDataArray* normals = out->GetPointData()->GetNormals())
  {
    std::vector<vec3> n(std::size_t(normals->GetNumberOfTuples()));
    for (vtkIdType i = 0; i < normals->GetNumberOfTuples(); ++i)
    {
      const double* v = normals->GetTuple3(i);
      n[std::size_t(i)] = vec3(v[0], v[1], v[2]);
    }
    mesh->setVertexNormals(std::move(n));
  }
  if (vtkDataArray* c = out->GetPointData()->GetArray("Colors"))
  {
    std::vector<std::uint32_t> packed(std::size_t(c->GetNumberOfTuples()));
    for (vtkIdType i = 0; i < c->GetNumberOfTuples(); ++i)
      packed[std::size_t(i)] = sightline::packRGBA8(std::uint8_t(c->GetComponent(i, 0)),
        std::uint8_t(c->GetComponent(i, 1)), std::uint8_t(c->GetComponent(i, 2)));
    mesh->setVertexColors(std::move(packed));
  }
  return mesh;
}

/// Looks at the whole data set from +z (the far view), headlight.
View farView(const TubeTree& tree, int width, int height)
{
  const sightline::Box3 box = tree.bounds();
  const sightline::dvec3 center = 0.5 * sightline::dvec3(box.lower + box.upper);
  const double radius = 0.5 * glm::length(sightline::dvec3(box.upper - box.lower));
  View view;
  view.width = width;
  view.height = height;
  view.parameters.viewAngle = 30.0;
  // Zoomed in 2x on the centre: the axons reach far out, the dendrites fill the middle.
  const double distance = radius / std::sin(glm::radians(0.5 * view.parameters.viewAngle)) * 0.4;
  view.parameters.focalPoint = center;
  view.parameters.position = center + sightline::dvec3(0.25, 0.3, 1.0) / std::sqrt(1.0 + 0.0625 + 0.09) * distance;
  view.parameters.nearClip = std::max(1e-3 * distance, distance - 2.0 * radius);
  view.parameters.farClip = distance + 2.0 * radius;
  view.lighting = sightline::Lighting::headlight(
    vec3(glm::normalize(view.parameters.focalPoint - view.parameters.position)));
  return view;
}

sightline::Material tubeMaterial(float opacity = 1.0f)
{
  sightline::Material m; // vtkProperty's Phong defaults, with some specular
  m.ambient = 0.15f;
  m.diffuse = 0.85f;
  m.specular = 0.3f;
  m.specularPower = 30.0f;
  m.opacity = opacity;
  return m;
}

std::vector<MethodResult> runTubes(const Options& options, const std::string& name, const TubeTree& tree)
{
  const long long links = (long long)tree.linkCount();
  const View view = farView(tree, options.width, options.height);
  std::vector<std::unique_ptr<PreparedMethod>> methods;
  std::vector<std::shared_ptr<const BuiltScene>> keep;
  sightline::RenderOptions opaque;
  auto withMaterial = [](auto geometry, float opacity = 1.0f)
  {
    geometry->material = tubeMaterial(opacity);
    return geometry;
  };

  logProgress(name + ": " + std::to_string(links) + " links, unbranched sections");
  const Sections sections = sectionsOf(tree);
  {
    logProgress(name + ": embree-round-curves (reference)");
    std::shared_ptr<BuiltScene> built;
    const double seconds = timeOnce([&]
      { built = std::make_shared<BuiltScene>(withMaterial(std::make_shared<EmbreeRoundCurves>(sections))); });
    methods.push_back(prepareMethod(view, "embree-round-curves", built, nullptr, opaque, seconds, links));
    methods.back()->result.isReference = true;
    std::ostringstream notes;
    notes << "reference; RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE, " << built->scene->geometry(0).size()
          << " segments (branch points duplicated); BVH " << fixed(double(built->scene->bvhBytes()) / links, 1)
          << " B/link";
    methods.back()->result.notes = notes.str();
  }
  // One method per tube layout: its build time (returned), its frame, and its bytes per link.
  auto addLayout = [&](const std::string& method, const TubeLayout& layout)
  {
    std::shared_ptr<BuiltScene> built;
    const double seconds = timeOnce([&]
      {
        built = std::make_shared<BuiltScene>(withMaterial(std::make_shared<sightline::TubeSet>(
          tree.points, tree.radii, tree.predecessors, tree.colors, layout)));
      });
    methods.push_back(prepareMethod(view, method, built, nullptr, opaque, seconds, links));
    std::ostringstream notes;
    notes << built->scene->geometry(0).size() << " primitives; geometry "
          << fixed(double(built->scene->geometryBytes()) / links, 1) << " + BVH "
          << fixed(double(built->scene->bvhBytes()) / links, 1) << " B/link (colours not counted: "
          << "4 B/point)";
    methods.back()->result.notes = notes.str();
    return seconds;
  };
  double defaultBuildSeconds = kNotMeasured;
  const TubeLayout defaultLayout{};
  for (auto primitives : { TubeLayout::Primitives::Combined, TubeLayout::Primitives::Separate })
    for (auto transforms : { TubeLayout::Transforms::OnTheFly, TubeLayout::Transforms::Precomputed })
    {
      const TubeLayout layout{ primitives, transforms };
      const bool isDefault = primitives == defaultLayout.primitives && transforms == defaultLayout.transforms;
      std::string label = layout.name();
      std::replace(label.begin(), label.end(), ' ', '-');
      label.erase(std::remove(label.begin(), label.end(), ','), label.end());
      if (!isDefault && !options.wantsMethod("sightline:" + label))
        continue; // the default layout always runs: the ratios divide by it
      logProgress(name + ": sightline " + layout.name());
      const double seconds = addLayout("sightline:" + label, layout);
      if (isDefault)
        defaultBuildSeconds = seconds;
    }
  // Chunks of K links: the BVH shrinks about K-fold, each hit tests up to K links.
  for (unsigned chunk : { 4u, 8u, 16u, 32u })
  {
    const std::string method = "sightline:chunked-" + std::to_string(chunk);
    if (!options.wantsMethod(method))
      continue;
    logProgress(name + ": sightline " + method);
    TubeLayout layout;
    layout.primitives = TubeLayout::Primitives::Chunked;
    layout.chunkSize = chunk;
    addLayout(method, layout);
  }
  {
    // The CSG union path over the default layout's BVH: an empty opaque scene, the tubes as the
    // translucent scene.
    auto empty = std::make_shared<BuiltScene>(nullptr);
    for (float opacity : { 1.0f, 0.4f })
    {
      const std::string method = opacity == 1.0f ? "sightline-csg" : "sightline-translucent-0.4";
      if (!options.wantsMethod(method))
        continue;
      logProgress(name + ": " + method);
      auto tubes = std::make_shared<BuiltScene>(withMaterial(std::make_shared<sightline::TubeSet>(
        tree.points, tree.radii, tree.predecessors, tree.colors, defaultLayout), opacity));
      keep.push_back(tubes);
      sightline::RenderOptions translucent;
      translucent.translucent.scene = tubes->scene.get();
      methods.push_back(prepareMethod(view, method, empty, nullptr, translucent, 0.0, links));
      methods.back()->result.buildSeconds = defaultBuildSeconds;
      methods.back()->result.bytesPerPrimitive = double(tubes->bytes()) / links;
      methods.back()->result.notes = opacity == 1.0f
        ? "all-hit CSG union traversal at opacity 1 (isolates its cost, as the paper's Section 6.3)"
        : "translucent frame, opacity 0.4 (image not comparable with the opaque reference)";
    }
  }
  for (int sides : { 6, 12, 24 })
  {
    const std::string method = "vtk-tube-filter-" + std::to_string(sides);
    if (!options.wantsMethod(method))
      continue;
    // Triangles: 2 per side per segment plus the caps.
    const long long triangles = 2LL * sides * links;
    if (triangles > options.maxTriangles)
    {
      auto skipped = std::make_unique<PreparedMethod>();
      skipped->result.method = method;
      skipped->result.skipped = true;
      skipped->result.primitives = links;
      skipped->result.triangles = triangles;
      skipped->result.notes = "skipped: about " + std::to_string(triangles) + " triangles exceed --max-triangles";
      methods.push_back(std::move(skipped));
      continue;
    }
    logProgress(name + ": " + method);
    std::shared_ptr<BuiltScene> built;
    std::shared_ptr<sightline::TriangleMesh> mesh;
    const double tessellateSeconds = timeOnce([&] { mesh = tessellate(sections, sides); });
    const double buildSeconds = timeOnce([&] { built = std::make_shared<BuiltScene>(withMaterial(mesh)); });
    methods.push_back(prepareMethod(view, method, built, nullptr, opaque, tessellateSeconds + buildSeconds, links));
    methods.back()->result.triangles = (long long)mesh->size();
    std::ostringstream notes;
    notes << "vtkTubeFilter (" << sides << " sides, capped) + vtkTriangleFilter " << fixed(tessellateSeconds, 2)
          << " s; " << mesh->size() << " triangles; mesh " << fixed(double(built->scene->geometryBytes()) / links, 1)
          << " + BVH " << fixed(double(built->scene->bvhBytes()) / links, 1) << " B/link";
    methods.back()->result.notes = notes.str();
  }

  std::vector<PreparedMethod*> timed;
  for (auto& m : methods)
    if (!m->result.skipped)
      timed.push_back(m.get());
  logProgress(name + ": timing " + std::to_string(options.runs) + " rounds");
  timeRoundRobin(view, options.runs, timed);

  std::vector<MethodResult> results;
  const Image referenceImage = methods.front()->result.image;
  const Image* reference = &referenceImage;
  const double referenceFrame = methods.front()->result.frame.medianSeconds;
  for (auto& m : methods)
  {
    MethodResult r = std::move(m->result);
    r.method = name + ":" + r.method;
    r.primitives = links;
    r.width = options.width;
    r.height = options.height;
    if (!r.skipped)
    {
      std::ostringstream extra;
      extra << "; pixels differing > " << kPixelThreshold << "/255: " << std::setprecision(3)
            << differingPixelPercent(r.image, *reference) << " %; frame x"
            << std::setprecision(3) << r.frame.medianSeconds / referenceFrame << " of the curves";
      r.notes += extra.str();
    }
    results.push_back(std::move(r));
  }
  return results;
}

std::vector<MethodResult> runNeuronScene(const Options& options, long long count, MachineDescription&)
{
  const TubeTree base = sightline::syntheticNeuron(kBaseNeuronLinks, options.seed);
  const std::size_t copies = std::max<std::size_t>(1, std::size_t(count) / base.linkCount());
  logProgress("tubes: " + std::to_string(copies) + " neurons of " + std::to_string(base.linkCount()) + " links");
  const TubeTree assembly = sightline::neuronAssembly(base, copies, kNeuronSpacing, options.seed + 1);
  return runTubes(options, "neurons", assembly);
}

std::vector<MethodResult> runChainScene(const Options& options, long long count, MachineDescription&)
{
  const std::size_t lines = std::max<std::size_t>(1, std::size_t(count) / kLinksPerStreamline);
  // Density of the DTI data set: a cube that grows with the line count, radius 0.25 steps.
  const float edge = 4.0f * std::cbrt(float(lines * kLinksPerStreamline));
  const TubeTree streamlines =
    sightline::syntheticStreamlines(lines, kLinksPerStreamline, edge, 0.25f, options.seed);
  return runTubes(options, "streamlines", streamlines);
}

const SceneRegistration neurons{ "tubes",
  "generalized tubes (Han et al. 2019) on neuron assemblies: the four layouts of the paper's "
  "Table 1, the CSG union path, Embree's round linear curves (reference) and vtkTubeFilter "
  "tessellations ray-traced as triangles",
  { 100000, 1000000, 10000000 }, &runNeuronScene };

const SceneRegistration chains{ "tube-chains",
  "generalized tubes on non-branching streamlines with varying radius: Sightline's layouts "
  "(chunked ones included) vs "
  "Embree's round linear curves vs vtkTubeFilter tessellations",
  { 100000, 1000000 }, &runChainScene };
} // namespace
} // namespace sightline_benchmark
