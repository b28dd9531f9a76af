// SPDX-License-Identifier: BSD-3-Clause
// vtkSightlineTubeMapper: a neuron read by vtkSightlineSWCReader drawn from its parent indices
// and from its polylines (the same tubes), a straight tube's silhouette against its analytic
// area, translucent tubes composited with OpenGL spheres in front and behind, and bad input.
// Baselines with vtkTesting's metric, threshold 0.5.
#include "SightlineTestUtilities.h"

#include "sightline/core/Framebuffer.h"

#include "vtkAppendFilter.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyDataAlgorithm.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSightlineSWCReader.h"
#include "vtkSightlineTubeMapper.h"
#include "vtkPolyDataMapper.h"
#include "vtkSphereSource.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

using namespace sightline_test;

namespace
{
using Scene = MapperScene<vtkSightlineTubeMapper>;

// asGrid: the reader's polylines as VTK_POLY_LINE cells of a vtkUnstructuredGrid (vtkAppendFilter),
// the form in which ParaView's RedistributeDataSet hands each MPI rank its piece.
vtkSmartPointer<vtkImageData> RenderNeuron(bool fromParents, bool asGrid = false,
  int layout = vtkSightlineTubeMapper::LINKS_AUTOMATIC)
{
  vtkNew<vtkSightlineSWCReader> reader;
  reader->SetFileName((std::string(SIGHTLINE_SOURCE_DIR) + "/Testing/Data/SWC/neuron_three_point_soma.swc").c_str());
  vtkNew<vtkAppendFilter> toGrid;
  toGrid->SetInputConnection(reader->GetOutputPort());
  Scene scene(320, 240);
  scene.mapper->SetInputConnection(asGrid ? toGrid->GetOutputPort() : reader->GetOutputPort());
  scene.mapper->SetRadiusArrayName("Radius");
  scene.mapper->SetLinkLayout(layout);
  scene.mapper->ScalarVisibilityOff();
  if (fromParents)
    scene.mapper->SetPredecessorArrayName("ParentIndex");
  scene.actor->GetProperty()->SetColor(0.9, 0.75, 0.5);
  vtkCamera* camera = scene.renderer->GetActiveCamera();
  camera->SetFocalPoint(-2, 2, 0);
  camera->SetPosition(-2, -20, 45);
  camera->SetViewUp(0, 1, 0);
  camera->SetViewAngle(40);
  scene.renderer->ResetCameraClippingRange();
  scene.window->Render();
  // 12 samples; the 8 polylines (unbranched chains) repeat each chain start: 19 control points.
  EXPECT_EQ(scene.mapper->GetNumberOfLinks(), fromParents ? 12 : 19);
  // Small inputs: the automatic layout is the combined one.
  EXPECT_EQ(scene.mapper->GetBuiltLinkLayout(),
    layout == vtkSightlineTubeMapper::LINKS_AUTOMATIC ? vtkSightlineTubeMapper::LINKS_COMBINED_ON_THE_FLY : layout);
  return CaptureRGB(scene.window);
}

vtkSmartPointer<vtkPolyData> Polyline(const std::vector<std::array<double, 3>>& points)
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> p;
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(static_cast<int>(points.size()));
  for (const auto& q : points)
    lines->InsertCellPoint(p->InsertNextPoint(q.data()));
  poly->SetPoints(p);
  poly->SetLines(lines);
  return poly;
}
} // namespace

namespace
{
// Helical streamlines of varying length, made piece by piece as the readers answer piece
// requests (a run of streamlines per piece, numbered in turn), with a per-point "height" array;
// counts its executions.
class HelixStreamlines : public vtkPolyDataAlgorithm
{
public:
  static HelixStreamlines* New();
  vtkTypeMacro(HelixStreamlines, vtkPolyDataAlgorithm);
  int Streamlines = 40;
  int Executions = 0;

protected:
  HelixStreamlines() { this->SetNumberOfInputPorts(0); }
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    out->GetInformationObject(0)->Set(CAN_HANDLE_PIECE_REQUEST(), 1);
    return 1;
  }
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    ++this->Executions;
    vtkInformation* info = out->GetInformationObject(0);
    const int piece = info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
    const int pieces = info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES());
    const int first = static_cast<int>(static_cast<long long>(this->Streamlines) * piece / pieces);
    const int end = static_cast<int>(static_cast<long long>(this->Streamlines) * (piece + 1) / pieces);
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> lines;
    vtkNew<vtkFloatArray> height;
    height->SetName("height");
    for (int s = first; s < end; ++s)
    {
      const int count = 2 + (s * 7) % 23;
      lines->InsertNextCell(count);
      for (int k = 0; k < count; ++k)
      {
        const double t = 0.3 * k + 0.5 * s;
        const double p[3] = { 100.0 + std::cos(t) * (1 + 0.05 * s), 0.2 * k - 2.0 + 0.02 * s,
          -40.0 + std::sin(t) * (1 + 0.05 * s) };
        lines->InsertCellPoint(points->InsertNextPoint(p));
        height->InsertNextValue(static_cast<float>(p[2]));
      }
    }
    auto* output = vtkPolyData::GetData(info);
    output->SetPoints(points);
    output->SetLines(lines);
    output->GetPointData()->AddArray(height);
    return 1;
  }
};
vtkStandardNewMacro(HelixStreamlines);

bool TraceHelices(vtkSightlineTubeMapper* mapper, HelixStreamlines* source, int pieces,
  sightline::Framebuffer& frame)
{
  mapper->SetInputConnection(source->GetOutputPort());
  mapper->SetStreamedPieces(pieces);
  mapper->SetRadius(0.08);
  mapper->SetLinkLayout(vtkSightlineTubeMapper::LINKS_CHUNKED);
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectColorArray("height");
  mapper->SetScalarRange(-41.5, -38.5);
  mapper->ScalarVisibilityOn();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<vtkCamera> camera;
  camera->SetFocalPoint(100, 0, -40);
  camera->SetPosition(100 + 3, -14, -40 + 2);
  camera->SetViewUp(0, 0, 1);
  camera->SetViewAngle(40);
  return mapper->RayTrace(actor, camera, nullptr, 200, 150, frame);
}
} // namespace

// StreamedPieces: the mapper pulls pieces from its input's producer one after the other into
// chunked tubes; the image equals the whole input's (the same tubes up to float rounding of
// positions relative to another origin), each piece is read once, and an unchanged pipeline
// is not read again. Runs under the sanitizers with the rendering label.
TEST(TubeMapper, StreamedPiecesDrawTheWholeInput)
{
  vtkNew<HelixStreamlines> wholeSource;
  vtkNew<vtkSightlineTubeMapper> wholeMapper;
  sightline::Framebuffer whole;
  ASSERT_TRUE(TraceHelices(wholeMapper, wholeSource, 1, whole));
  EXPECT_EQ(wholeSource->Executions, 1);
  for (int pieces : { 2, 5, 41 }) // 41: more pieces than streamlines, one empty
  {
    SCOPED_TRACE(pieces);
    vtkNew<HelixStreamlines> source;
    vtkNew<vtkSightlineTubeMapper> mapper;
    vtkNew<MessageCollector> messages;
    messages->Observe(mapper);
    sightline::Framebuffer streamed;
    ASSERT_TRUE(TraceHelices(mapper, source, pieces, streamed));
    EXPECT_TRUE(messages->Errors.empty());
    EXPECT_TRUE(messages->Warnings.empty());
    EXPECT_EQ(source->Executions, pieces);
    EXPECT_EQ(mapper->GetNumberOfLinks(), wholeMapper->GetNumberOfLinks());
    EXPECT_EQ(mapper->GetBuiltLinkLayout(), vtkSightlineTubeMapper::LINKS_CHUNKED);
    EXPECT_EQ(source->GetOutput()->GetNumberOfPoints(), 0); // the last piece was released
    int covered = 0, differing = 0;
    for (std::size_t i = 0; i < whole.pixelCount(); ++i)
    {
      const bool a = whole.Depth[i] < 1.0f, b = streamed.Depth[i] < 1.0f;
      covered += a;
      differing += a != b;
      if (a && b)
      {
        EXPECT_NEAR(whole.Depth[i], streamed.Depth[i], 1e-5f) << "pixel " << i;
        EXPECT_NEAR(glm::length(sightline::vec3(whole.Color[i]) - sightline::vec3(streamed.Color[i])), 0.0f, 2e-2f)
          << "pixel " << i;
      }
    }
    EXPECT_GT(covered, 2000);
    EXPECT_LE(differing, covered / 500);
    // Another frame of the unchanged pipeline reads nothing; a changed source is read again.
    ASSERT_TRUE(TraceHelices(mapper, source, pieces, streamed));
    EXPECT_EQ(source->Executions, pieces);
    source->Streamlines = 20;
    source->Modified();
    ASSERT_TRUE(TraceHelices(mapper, source, pieces, streamed));
    EXPECT_EQ(source->Executions, 2 * pieces);
    EXPECT_LT(mapper->GetNumberOfLinks(), wholeMapper->GetNumberOfLinks());
  }
}

TEST(TubeMapper, NeuronFromParentsAndFromPolylinesMatchesBaseline)
{
  auto parents = RenderNeuron(true);
  auto polylines = RenderNeuron(false);
  EXPECT_GT(CoveredPixels(parents), 8000);
  EXPECT_LE(MaxRGBDifference(parents, polylines), 1);
  EXPECT_TRUE(MatchesBaseline(parents, "TubeNeuron", 0.5));
}

// Chunks of links (the tractogram layout) draw the same tubes as one primitive per link, with
// bifurcations (predecessors that are not the previous point) and varying radii; the automatic
// layout takes chunks from AutomaticChunkedLinks points on.
TEST(TubeMapper, ChunkedLinksDrawTheSameNeuron)
{
  for (bool fromParents : { true, false })
  {
    auto combined = RenderNeuron(fromParents, false, vtkSightlineTubeMapper::LINKS_COMBINED_ON_THE_FLY);
    auto chunked = RenderNeuron(fromParents, false, vtkSightlineTubeMapper::LINKS_CHUNKED);
    EXPECT_GT(CoveredPixels(chunked), 8000);
    EXPECT_LE(MaxRGBDifference(combined, chunked), 1);
  }

  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < 5000; ++i)
    points.push_back({ 1e-3 * i, std::sin(1e-2 * i), 0.0 });
  Scene scene(64, 64);
  scene.mapper->SetInputDataObject(Polyline(points));
  scene.mapper->SetAutomaticChunkedLinks(5001);
  scene.window->Render();
  EXPECT_EQ(scene.mapper->GetBuiltLinkLayout(), vtkSightlineTubeMapper::LINKS_COMBINED_ON_THE_FLY);
  scene.mapper->SetAutomaticChunkedLinks(5000);
  scene.mapper->SetRadius(0.05);
  scene.renderer->ResetCamera();
  scene.window->Render();
  EXPECT_EQ(scene.mapper->GetBuiltLinkLayout(), vtkSightlineTubeMapper::LINKS_CHUNKED);
  EXPECT_EQ(scene.mapper->GetBuiltChunkLinks(), 8);
  const auto eight = CaptureRGB(scene.window);
  EXPECT_GT(CoveredPixels(eight), 100);
  EXPECT_STREQ(scene.mapper->GetLinkLayoutAsString(), "Automatic");
  // Long chunks from AutomaticLongChunkLinks points, or as ChunkLinks says: the same tubes.
  scene.mapper->SetAutomaticLongChunkLinks(5000);
  scene.window->Render();
  EXPECT_EQ(scene.mapper->GetBuiltChunkLinks(), 16);
  EXPECT_LE(MaxRGBDifference(eight, CaptureRGB(scene.window)), 1);
  scene.mapper->SetChunkLinks(3);
  scene.window->Render();
  EXPECT_EQ(scene.mapper->GetBuiltChunkLinks(), 3);
  EXPECT_LE(MaxRGBDifference(eight, CaptureRGB(scene.window)), 1);
}

// Polylines in an unstructured grid (VTK_POLY_LINE cells) are the same tubes as in vtkPolyData:
// before, the mapper read only vtkPolyData lines and refused the grid ("no polylines").
TEST(TubeMapper, UnstructuredGridPolylinesDrawAsPolyDataLines)
{
  auto polylines = RenderNeuron(false);
  auto grid = RenderNeuron(false, true);
  EXPECT_GT(CoveredPixels(grid), 8000);
  EXPECT_LE(MaxRGBDifference(polylines, grid), 1);

  // Other cells of a grid (a vertex, a triangle) are no tubes; a grid with no line cell is an error.
  vtkNew<vtkUnstructuredGrid> input;
  vtkNew<vtkPoints> points;
  for (double x : { 0.0, 1.0, 2.0, 3.0 })
    points->InsertNextPoint(x, 0.0, 0.0);
  input->SetPoints(points);
  input->Allocate(3);
  const vtkIdType vertex[1] = { 3 }, triangle[3] = { 0, 1, 3 }, line[3] = { 0, 1, 2 };
  input->InsertNextCell(VTK_VERTEX, 1, vertex);
  input->InsertNextCell(VTK_TRIANGLE, 3, triangle);
  Scene scene(64, 64);
  vtkNew<MessageCollector> messages;
  messages->Observe(scene.mapper);
  scene.mapper->SetInputDataObject(input);
  scene.mapper->SetRadius(0.2);
  scene.renderer->ResetCamera();
  scene.window->Render();
  EXPECT_TRUE(messages->Contains("no polylines"));
  input->InsertNextCell(VTK_POLY_LINE, 3, line);
  input->Modified();
  scene.window->Render();
  EXPECT_EQ(scene.mapper->GetNumberOfLinks(), 3);
  EXPECT_GT(CoveredPixels(CaptureRGB(scene.window)), 0);
}

// A straight tube of radius r and length L seen side on (parallel projection) covers the area of
// a rectangle 2r x L plus two half discs: 2 r L + pi r^2.
TEST(TubeMapper, StraightTubeSilhouetteHasTheAnalyticArea)
{
  Scene scene(400, 400);
  scene.mapper->SetInputDataObject(Polyline({ { { -1.5, 0, 0 } }, { { 0, 0.1, 0 } }, { { 1.5, 0, 0 } } }));
  scene.mapper->SetRadius(0.3);
  vtkCamera* camera = scene.renderer->GetActiveCamera();
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(0, 0, 10);
  camera->SetViewUp(0, 1, 0);
  camera->ParallelProjectionOn();
  camera->SetParallelScale(2.0); // 400 pixels span 4 units: 100 pixels per unit
  scene.renderer->ResetCameraClippingRange(-3, 3, -3, 3, -3, 3);
  scene.window->Render();
  // Two links at a slight angle: the union's area, from the two rectangles, the end caps and
  // the wedge at the joint, sampled finely as a reference.
  const double r = 0.3;
  auto inside = [&](double x, double y)
  {
    const double a[3][2] = { { -1.5, 0 }, { 0, 0.1 }, { 1.5, 0 } };
    for (int s = 0; s < 2; ++s)
    {
      const double dx = a[s + 1][0] - a[s][0], dy = a[s + 1][1] - a[s][1];
      double t = ((x - a[s][0]) * dx + (y - a[s][1]) * dy) / (dx * dx + dy * dy);
      t = std::max(0.0, std::min(1.0, t));
      const double ex = x - a[s][0] - t * dx, ey = y - a[s][1] - t * dy;
      if (ex * ex + ey * ey <= r * r)
        return true;
    }
    return false;
  };
  double area = 0.0;
  const int n = 1600;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      area += inside(-2.0 + 4.0 * (i + 0.5) / n, -2.0 + 4.0 * (j + 0.5) / n);
  area *= (4.0 / n) * (4.0 / n);
  const double pixels = area * 100.0 * 100.0;
  const int covered = CoveredPixels(CaptureRGB(scene.window));
  std::cout << "tube silhouette: " << covered << " pixels, reference " << pixels << "\n";
  EXPECT_NEAR(covered, pixels, 0.01 * pixels);
}

namespace
{
/// A Y bifurcation in the plane z = 0 as points with parent indices and radii.
vtkSmartPointer<vtkPolyData> Bifurcation()
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkIdTypeArray> parents;
  parents->SetName("parent");
  vtkNew<vtkDoubleArray> radii;
  radii->SetName("radius");
  const double p[4][3] = { { 0, -1.5, 0 }, { 0, 0.5, 0 }, { -1.3, 1.8, 0 }, { 1.3, 1.8, 0 } };
  const double r[4] = { 0.55, 0.45, 0.25, 0.3 };
  const vtkIdType parent[4] = { -1, 0, 1, 1 };
  for (int i = 0; i < 4; ++i)
  {
    points->InsertNextPoint(p[i]);
    radii->InsertNextValue(r[i]);
    parents->InsertNextValue(parent[i]);
  }
  poly->SetPoints(points);
  poly->GetPointData()->AddArray(parents);
  poly->GetPointData()->AddArray(radii);
  return poly;
}

/// An OpenGL sphere actor (vtkPolyDataMapper), opaque.
vtkSmartPointer<vtkActor> GLSphere(double x, double y, double z, double radius, double r, double g, double b)
{
  vtkNew<vtkSphereSource> source;
  source->SetCenter(x, y, z);
  source->SetRadius(radius);
  source->SetThetaResolution(48);
  source->SetPhiResolution(48);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(r, g, b);
  return actor;
}

struct TranslucentScene : Scene
{
  vtkSmartPointer<vtkActor> front = GLSphere(0.0, -0.5, 1.2, 0.3, 0.2, 0.4, 1.0);
  vtkSmartPointer<vtkActor> behind = GLSphere(0.55, 0.0, -1.2, 0.5, 1.0, 0.3, 0.2);

  TranslucentScene(bool withTubes, bool withSpheres)
    : Scene(320, 240)
  {
    mapper->SetInputDataObject(Bifurcation());
    mapper->SetPredecessorArrayName("parent");
    mapper->SetRadiusArrayName("radius");
    actor->GetProperty()->SetColor(0.3, 0.9, 0.5);
    actor->GetProperty()->SetOpacity(0.45);
    actor->SetVisibility(withTubes);
    if (withSpheres)
    {
      renderer->AddActor(front);
      renderer->AddActor(behind);
    }
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->SetFocalPoint(0, 0.2, 0);
    camera->SetPosition(0, 0.2, 8);
    camera->SetViewUp(0, 1, 0);
    camera->SetViewAngle(35);
    renderer->ResetCameraClippingRange(-3, 3, -3, 3, -3, 3);
  }
};

/// Window pixel of a world point.
std::array<int, 2> PixelOf(vtkRenderer* renderer, double x, double y, double z)
{
  renderer->SetWorldPoint(x, y, z, 1.0);
  renderer->WorldToDisplay();
  double* d = renderer->GetDisplayPoint();
  return { static_cast<int>(d[0]), static_cast<int>(d[1]) };
}
} // namespace

TEST(TubeMapper, TranslucentTubesCompositeWithOpenGLGeometry)
{
  TranslucentScene all(true, true), tubesOnly(true, false), spheresOnly(false, true);
  for (TranslucentScene* scene : { &all, &tubesOnly, &spheresOnly })
    scene->window->Render();
  auto image = CaptureRGB(all.window);
  auto tubes = CaptureRGB(tubesOnly.window);
  auto spheres = CaptureRGB(spheresOnly.window);

  // The sphere in front hides the tube: its centre pixel is the sphere alone.
  const auto front = PixelOf(all.renderer, 0.0, -0.5, 1.2);
  EXPECT_EQ(Pixel(image, front[0], front[1]), Pixel(spheres, front[0], front[1]));
  // The sphere behind shows through the tube: neither the sphere alone nor the tube alone.
  const auto behind = PixelOf(all.renderer, 0.2, 0.0, -1.2); // behind the trunk
  const auto blended = Pixel(image, behind[0], behind[1]);
  const auto sphereAlone = Pixel(spheres, behind[0], behind[1]);
  const auto tubeAlone = Pixel(tubes, behind[0], behind[1]);
  EXPECT_GT(blended[0], tubeAlone[0] + 40) << "the red sphere must show through";
  EXPECT_LT(blended[0], sphereAlone[0] - 40) << "the tube must tint it";
  // Away from the spheres, the tube over black: two layers of opacity 0.45 on the trunk.
  const auto trunk = PixelOf(all.renderer, 0.0, -1.0, 0.0);
  EXPECT_EQ(Pixel(image, trunk[0], trunk[1]), Pixel(tubes, trunk[0], trunk[1]));
  EXPECT_GT(Pixel(tubes, trunk[0], trunk[1])[1], 60);

  // The GL-free path draws the same translucent tubes.
  const double black[3] = { 0, 0, 0 };
  auto withoutGL = RenderWithoutGL({ tubesOnly.actor }, tubesOnly.renderer->GetActiveCamera(), 320, 240, black);
  int differing = 0;
  EXPECT_LE(MaxRGBDifference(tubes, withoutGL, &differing), 2);
  EXPECT_TRUE(MatchesBaseline(image, "TubeTranslucent", 0.5));
}

// VTK's default windows are multisampled; the opaque depth the rays stop at must still be read
// (glReadPixels on a multisampled framebuffer returns nothing): the same pixels as without.
TEST(TubeMapper, TranslucentTubesInMultisampledWindows)
{
  TranslucentScene plain(true, true), multisampled(true, true);
  multisampled.window->SetMultiSamples(8);
  plain.window->Render();
  multisampled.window->Render();
  auto a = CaptureRGB(plain.window), b = CaptureRGB(multisampled.window);
  const auto behind = PixelOf(plain.renderer, 0.2, 0.0, -1.2);
  const auto pa = Pixel(a, behind[0], behind[1]), pb = Pixel(b, behind[0], behind[1]);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(pa[c], pb[c], 3) << "the sphere behind the tube, channel " << c;
  int differing = 0;
  MaxRGBDifference(a, b, &differing);
  EXPECT_LT(differing, 320 * 240 / 50) << "only antialiased edges may differ";
}

// Sort-last compositing over MPI ranks: the neuron, translucent, drawn in two half-spaces
// (SetRegion) whose images blended front to back equal the whole image; a bad region is an
// error, not an image.
TEST(TubeMapper, RegionHalvesBlendToTheWholeTranslucentImage)
{
  vtkNew<vtkSightlineSWCReader> reader;
  reader->SetFileName((std::string(SIGHTLINE_SOURCE_DIR) + "/Testing/Data/SWC/neuron_three_point_soma.swc").c_str());
  Scene scene(160, 120);
  scene.mapper->SetInputConnection(reader->GetOutputPort());
  scene.mapper->SetRadiusArrayName("Radius");
  scene.mapper->SetPredecessorArrayName("ParentIndex");
  scene.mapper->ScalarVisibilityOff();
  scene.actor->GetProperty()->SetOpacity(0.4);
  vtkNew<vtkCamera> camera;
  camera->SetFocalPoint(-2, 2, 0);
  camera->SetPosition(-30, -20, 35);
  camera->SetViewUp(0, 1, 0);
  camera->SetViewAngle(40);
  sightline::Framebuffer whole, left, right;
  ASSERT_TRUE(scene.mapper->RayTrace(scene.actor, camera, nullptr, 160, 120, whole));
  const double inf = std::numeric_limits<double>::infinity(), cut = -1.0;
  scene.mapper->SetRegion(-inf, cut, -inf, inf, -inf, inf);
  ASSERT_TRUE(scene.mapper->RayTrace(scene.actor, camera, nullptr, 160, 120, left));
  scene.mapper->SetRegion(cut, inf, -inf, inf, -inf, inf);
  ASSERT_TRUE(scene.mapper->RayTrace(scene.actor, camera, nullptr, 160, 120, right));
  // The camera is at x < cut: every ray crosses the left half first.
  int covered = 0, both = 0;
  ExpectFrontOverBackIsWhole(left, right, whole, 1e-5f, 1e-4f, covered, both);
  EXPECT_GT(covered, 1000);
  EXPECT_GT(both, 50);

  vtkNew<MessageCollector> messages;
  messages->Observe(scene.mapper);
  scene.mapper->SetRegion(0.0, std::nan(""), -inf, inf, -inf, inf);
  EXPECT_FALSE(scene.mapper->RayTrace(scene.actor, camera, nullptr, 160, 120, whole));
  EXPECT_TRUE(messages->Contains("region's x range"));
  scene.mapper->SetRegionToAllOfSpace();
  EXPECT_TRUE(scene.mapper->RayTrace(scene.actor, camera, nullptr, 160, 120, whole));
}

TEST(TubeMapper, BadInputIsReportedByName)
{
  auto render = [](vtkPolyData* input, void (*configure)(vtkSightlineTubeMapper*))
  {
    Scene scene(64, 64);
    vtkNew<MessageCollector> messages;
    messages->Observe(scene.mapper);
    scene.mapper->SetInputDataObject(input);
    configure(scene.mapper);
    scene.renderer->ResetCamera();
    scene.window->Render();
    return std::make_pair(messages->Errors, messages->Warnings);
  };
  auto line = Polyline({ { { 0, 0, 0 } }, { { 1, 0, 0 } }, { { 2, 0, 0 } } });
  vtkNew<vtkIdTypeArray> cyclic;
  cyclic->SetName("parent");
  for (vtkIdType v : { 2, 0, 1 })
    cyclic->InsertNextValue(v);
  line->GetPointData()->AddArray(cyclic);
  vtkNew<vtkDoubleArray> radii;
  radii->SetName("r");
  for (double v : { 0.2, -0.1, 0.2 })
    radii->InsertNextValue(v);
  line->GetPointData()->AddArray(radii);
  auto has = [](const std::vector<std::string>& list, const std::string& text)
  {
    for (const std::string& m : list)
      if (m.find(text) != std::string::npos)
        return true;
    return false;
  };
  auto cycle = render(line, [](vtkSightlineTubeMapper* m) { m->SetPredecessorArrayName("parent"); });
  EXPECT_TRUE(has(cycle.first, "cycle"));
  auto missing = render(line, [](vtkSightlineTubeMapper* m) { m->SetRadiusArrayName("nothing"); });
  EXPECT_TRUE(has(missing.first, "'nothing'"));
  auto negative = render(line, [](vtkSightlineTubeMapper* m) { m->SetRadiusArrayName("r"); });
  EXPECT_TRUE(has(negative.second, "negative")) << "no warning for the negative radius";
  vtkNew<vtkPolyData> points;
  points->SetPoints(line->GetPoints());
  auto noLines = render(points, [](vtkSightlineTubeMapper*) {});
  EXPECT_TRUE(has(noLines.first, "no polylines"));
}

// Polylines naming points the input does not have (found by fuzzing the mapper: 100000 in a
// 6-point data set was a SIGSEGV, 99 and -7 drew links from stray memory without a word) are
// left out with a warning naming one; the valid polyline still renders.
TEST(TubeMapper, PolylinesWithPointIdsOutOfRangeAreLeftOutByName)
{
  auto input = Polyline({ { { 0, 0, 0 } }, { { 1, 0, 0 } }, { { 2, 0, 0 } }, { { 0, 1, 0 } },
    { { 1, 1, 0 } }, { { 2, 1, 0 } } });
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell({ 0, 1, 2 });
  lines->InsertNextCell({ 3, 100000 });
  lines->InsertNextCell({ 4, 99 });
  lines->InsertNextCell({ 5, -7 });
  input->SetLines(lines);
  Scene scene(64, 64);
  vtkNew<MessageCollector> messages;
  messages->Observe(scene.mapper);
  scene.mapper->SetInputDataObject(input);
  scene.mapper->SetRadius(0.2);
  scene.renderer->ResetCamera();
  scene.window->Render();
  EXPECT_TRUE(messages->Contains("Polyline 1 names point 100000 but the input has 6 points"));
  EXPECT_TRUE(messages->Contains("3 polylines name points the input does not have"));
  EXPECT_EQ(scene.mapper->GetNumberOfLinks(), 3) << "only the valid polyline is drawn";
  EXPECT_GT(CoveredPixels(CaptureRGB(scene.window)), 0);

  vtkNew<vtkCellArray> onlyBad;
  onlyBad->InsertNextCell({ 0, 6 });
  input->SetLines(onlyBad);
  vtkNew<MessageCollector> errors;
  errors->Observe(scene.mapper);
  scene.window->Render();
  EXPECT_TRUE(errors->Contains("No polyline names only points of the input"));
}

// Predecessor values that are no point index are named as they are: NaN used to be reported as
// "predecessor 6" (the point count), 1e300 as -9223372036854775808, and 1.5 became 1 silently.
TEST(TubeMapper, PredecessorValuesThatAreNoIndexAreNamed)
{
  for (const auto& [value, text] : std::vector<std::pair<double, std::string>>{
         { std::numeric_limits<double>::quiet_NaN(), "the predecessor nan" },
         { 1e300, "the predecessor 1e+300" },
         { -1e300, "the predecessor -1e+300" },
         { 1.5, "the predecessor 1.5" },
         { 3.0, "the predecessor 3" } })
  {
    auto line = Polyline({ { { 0, 0, 0 } }, { { 1, 0, 0 } }, { { 2, 0, 0 } } });
    vtkNew<vtkDoubleArray> parent;
    parent->SetName("parent");
    for (double v : { -1.0, 0.0, value })
      parent->InsertNextValue(v);
    line->GetPointData()->AddArray(parent);
    Scene scene(32, 32);
    vtkNew<MessageCollector> messages;
    messages->Observe(scene.mapper);
    scene.mapper->SetInputDataObject(line);
    scene.mapper->SetPredecessorArrayName("parent");
    scene.renderer->ResetCamera();
    scene.window->Render();
    EXPECT_TRUE(messages->Contains("gives point 2 " + text + ", which is not -1 (none) or a point index in [0, 2]"))
      << "value " << value;
  }
}
