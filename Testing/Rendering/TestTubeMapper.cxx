// vtkSightlineTubeMapper: a neuron read by vtkSightlineSWCReader drawn from its parent indices
// and from its polylines (the same tubes), a straight tube's silhouette against its analytic
// area, and bad input. Baseline with vtkTesting's metric, threshold 0.5.
#include "SightlineTestUtilities.h"

#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSightlineSWCReader.h"
#include "vtkSightlineTubeMapper.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace sightline_test;

namespace
{
using Scene = MapperScene<vtkSightlineTubeMapper>;

vtkSmartPointer<vtkImageData> RenderNeuron(bool fromParents)
{
  vtkNew<vtkSightlineSWCReader> reader;
  reader->SetFileName((std::string(SIGHTLINE_SOURCE_DIR) + "/Testing/Data/SWC/neuron_three_point_soma.swc").c_str());
  Scene scene(320, 240);
  scene.mapper->SetInputConnection(reader->GetOutputPort());
  scene.mapper->SetRadiusArrayName("Radius");
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

TEST(TubeMapper, NeuronFromParentsAndFromPolylinesMatchesBaseline)
{
  auto parents = RenderNeuron(true);
  auto polylines = RenderNeuron(false);
  EXPECT_GT(CoveredPixels(parents), 8000);
  EXPECT_LE(MaxRGBDifference(parents, polylines), 1);
  EXPECT_TRUE(MatchesBaseline(parents, "TubeNeuron", 0.5));
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
