// SPDX-License-Identifier: BSD-3-Clause
// Hardware selection (vtkHardwareSelector) of ray-traced primitives: a one-pixel area at a known
// primitive's projected centre (projected here with the renderer's own world-to-display
// transform) must name the right prop and the right point or cell id, for spheres (some
// dropped, some in vertex cells), SH glyphs (a slice of an image with an empty voxel), tensor
// ellipsoids and a tube tree (opaque and translucent); the background selects nothing and an
// ordinary polygon in front wins. A selection leaves the next normal frame unchanged.
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkHardwareSelector.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPropPicker.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSelection.h"
#include "vtkSelectionNode.h"
#include "vtkSightlineSHGlyphMapper.h"
#include "vtkSightlineSphereMapper.h"
#include "vtkSightlineTensorGlyphMapper.h"
#include "vtkSightlineTubeMapper.h"
#include "vtkSmartPointer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

using namespace sightline_test;

namespace
{
constexpr int kSize = 300;

/// The pixel whose square holds the projection of a world point, by the renderer's own
/// world-to-display transform (display coordinates: pixel i covers [i, i + 1)).
std::array<int, 2> ProjectToPixel(vtkRenderer* renderer, const std::array<double, 3>& world)
{
  renderer->SetWorldPoint(world[0], world[1], world[2], 1.0);
  renderer->WorldToDisplay();
  double display[3];
  renderer->GetDisplayPoint(display);
  return { static_cast<int>(std::floor(display[0])), static_cast<int>(std::floor(display[1])) };
}

/// What a one-pixel hardware selection found: per selected prop, its ids.
struct Picked
{
  struct Node
  {
    vtkProp* prop = nullptr;
    std::vector<vtkIdType> ids;
  };
  std::vector<Node> nodes;

  /// The ids selected on `prop`, or null when it was not selected.
  const std::vector<vtkIdType>* IdsOf(vtkProp* prop) const
  {
    for (const Node& node : nodes)
    {
      if (node.prop == prop)
      {
        return &node.ids;
      }
    }
    return nullptr;
  }
};

Picked SelectPixel(vtkRenderer* renderer, const std::array<int, 2>& pixel, int association)
{
  vtkNew<vtkHardwareSelector> selector;
  selector->SetRenderer(renderer);
  selector->SetArea(pixel[0], pixel[1], pixel[0], pixel[1]);
  selector->SetFieldAssociation(association);
  auto selection = vtkSmartPointer<vtkSelection>::Take(selector->Select());
  Picked picked;
  if (!selection)
  {
    ADD_FAILURE() << "vtkHardwareSelector::Select returned nothing";
    return picked;
  }
  for (unsigned int n = 0; n < selection->GetNumberOfNodes(); ++n)
  {
    vtkSelectionNode* node = selection->GetNode(n);
    Picked::Node entry;
    entry.prop = vtkProp::SafeDownCast(node->GetProperties()->Get(vtkSelectionNode::PROP()));
    if (auto* ids = vtkIdTypeArray::SafeDownCast(node->GetSelectionList()))
    {
      for (vtkIdType i = 0; i < ids->GetNumberOfTuples(); ++i)
      {
        entry.ids.push_back(ids->GetValue(i));
      }
    }
    picked.nodes.push_back(entry);
  }
  return picked;
}

constexpr int kPoints = vtkDataObject::FIELD_ASSOCIATION_POINTS;
constexpr int kCells = vtkDataObject::FIELD_ASSOCIATION_CELLS;

/// Expects exactly `prop` selected with exactly `id`.
void ExpectSelected(const Picked& picked, vtkProp* prop, vtkIdType id, const char* what)
{
  SCOPED_TRACE(what);
  ASSERT_EQ(picked.nodes.size(), 1u);
  const std::vector<vtkIdType>* ids = picked.IdsOf(prop);
  ASSERT_NE(ids, nullptr) << "another prop was selected";
  ASSERT_EQ(ids->size(), 1u);
  EXPECT_EQ((*ids)[0], id);
}

template <class Mapper>
void SetUpView(MapperScene<Mapper>& scene)
{
  scene.renderer->SetActiveCamera(MakeCamera(false, 10.0));
}

/// Six points; point 1 has a negative radius (dropped, so later spheres are not their point's
/// index in the kernel); point 3 is a vertex cell (cell 0), points 4 and 5 a poly-vertex
/// (cell 1); points 0 and 2 are in no cell.
vtkSmartPointer<vtkPolyData> SelectionSpheres()
{
  auto spheres = MakeSpheres({ { -1.5, 1.0, 0 }, { 0, 1.0, 0 }, { 1.5, 1.0, 0.5 },
                               { -1.5, -1.0, 0 }, { 0, -1.0, -0.5 }, { 1.5, -1.0, 0 } },
    { 0.5, -1.0, 0.5, 0.5, 0.6, 0.4 });
  vtkNew<vtkCellArray> verts;
  const vtkIdType vertex[1] = { 3 };
  const vtkIdType polyVertex[2] = { 4, 5 };
  verts->InsertNextCell(1, vertex);
  verts->InsertNextCell(2, polyVertex);
  spheres->SetVerts(verts);
  return spheres;
}
} // namespace

TEST(Selection, SpheresSelectTheirPointAndVertexCell)
{
  MapperScene<vtkSightlineSphereMapper> scene(kSize, kSize);
  vtkNew<MessageCollector> messages;
  messages->Observe(scene.mapper);
  auto spheres = SelectionSpheres();
  scene.mapper->SetInputDataObject(spheres);
  scene.mapper->SetRadiusArrayName("radius");
  SetUpView(scene);
  scene.window->Render();
  ASSERT_EQ(scene.mapper->GetNumberOfPrimitives(), 5);
  auto before = CaptureRGB(scene.window);

  struct Expected
  {
    vtkIdType point, cell; // cell -1: the point is in no cell
  };
  const Expected expected[] = { { 0, -1 }, { 2, -1 }, { 3, 0 }, { 4, 1 }, { 5, 1 } };
  for (const Expected& e : expected)
  {
    double x[3];
    spheres->GetPoint(e.point, x);
    const auto pixel = ProjectToPixel(scene.renderer, { x[0], x[1], x[2] });
    SCOPED_TRACE("sphere of point " + std::to_string(e.point));
    ExpectSelected(SelectPixel(scene.renderer, pixel, kPoints), scene.actor, e.point, "points");
    const Picked cells = SelectPixel(scene.renderer, pixel, kCells);
    if (e.cell >= 0)
    {
      ExpectSelected(cells, scene.actor, e.cell, "cells");
    }
    else
    {
      EXPECT_TRUE(cells.nodes.empty()) << "a point in no cell selected a cell";
    }
  }

  // The dropped point's centre shows the background: nothing is selected there, nor in a
  // corner of the window.
  EXPECT_TRUE(SelectPixel(scene.renderer, ProjectToPixel(scene.renderer, { 0, 1.0, 0 }), kPoints)
                .nodes.empty());
  EXPECT_TRUE(SelectPixel(scene.renderer, { 2, 2 }, kPoints).nodes.empty());
  EXPECT_TRUE(SelectPixel(scene.renderer, { 2, 2 }, kCells).nodes.empty());

  // Selection passes leave the normal frame as it was.
  scene.window->Render();
  auto after = CaptureRGB(scene.window);
  EXPECT_EQ(MaxRGBDifference(before, after), 0);
  EXPECT_TRUE(messages->Errors.empty());
  ASSERT_EQ(messages->Warnings.size(), 1u) << "only the dropped sphere is reported";
  EXPECT_TRUE(messages->Contains("first: point 1"));
}

TEST(Selection, PolygonInFrontWinsOverASphere)
{
  MapperScene<vtkSightlineSphereMapper> scene(kSize, kSize);
  auto spheres = SelectionSpheres();
  scene.mapper->SetInputDataObject(spheres);
  scene.mapper->SetRadiusArrayName("radius");
  SetUpView(scene);

  // A small square in front of the sphere of point 3 (centre (-1.5, -1, 0), radius 0.5), and
  // a larger one behind the sphere of point 0, reaching out beside it.
  // (The camera is at z = 10: the sphere's centre projects through (-1.2, -0.8) at z = 2.)
  vtkNew<vtkPlaneSource> front;
  front->SetOrigin(-1.5, -1.1, 2.0);
  front->SetPoint1(-0.9, -1.1, 2.0);
  front->SetPoint2(-1.5, -0.5, 2.0);
  vtkNew<vtkPolyDataMapper> frontMapper;
  frontMapper->SetInputConnection(front->GetOutputPort());
  vtkNew<vtkActor> frontActor;
  frontActor->SetMapper(frontMapper);
  scene.renderer->AddActor(frontActor);
  vtkNew<vtkPlaneSource> back;
  back->SetOrigin(-2.6, 0.9, -2.0);
  back->SetPoint1(-1.5, 0.9, -2.0);
  back->SetPoint2(-2.6, 2.0, -2.0);
  vtkNew<vtkPolyDataMapper> backMapper;
  backMapper->SetInputConnection(back->GetOutputPort());
  vtkNew<vtkActor> backActor;
  backActor->SetMapper(backMapper);
  scene.renderer->AddActor(backActor);
  scene.window->Render();

  const auto covered = ProjectToPixel(scene.renderer, { -1.5, -1.0, 0.0 });
  ExpectSelected(SelectPixel(scene.renderer, covered, kCells), frontActor, 0, "polygon in front");
  const Picked points = SelectPixel(scene.renderer, covered, kPoints);
  EXPECT_EQ(points.IdsOf(scene.actor), nullptr) << "the hidden sphere was selected";
  const auto visible = ProjectToPixel(scene.renderer, { -1.5, 1.0, 0.0 });
  ExpectSelected(SelectPixel(scene.renderer, visible, kPoints), scene.actor, 0, "sphere in front");
  // Point 0 is in no cell: a cell selection there selects nothing, and the sphere still hides
  // the polygon behind it.
  EXPECT_TRUE(SelectPixel(scene.renderer, visible, kCells).nodes.empty());
  // Beside the sphere the polygon behind is selected.
  ExpectSelected(SelectPixel(scene.renderer, ProjectToPixel(scene.renderer, { -2.5, 1.9, -2.0 }),
                   kCells),
    backActor, 0, "polygon behind, beside the sphere");
}

TEST(Selection, PropPickerPicksSpheresAndThePolygonInFront)
{
  // vtkPropPicker picks through the hardware selector's actor pass: spheres in no cell count.
  MapperScene<vtkSightlineSphereMapper> scene(kSize, kSize);
  scene.mapper->SetInputDataObject(MakeSpheres({ { -1.0, 0, 0 }, { 1.0, 0, 0 } }, { 0.6, 0.6 }));
  scene.mapper->SetRadiusArrayName("radius");
  SetUpView(scene);
  vtkNew<vtkPlaneSource> front;
  front->SetOrigin(0.5, -0.5, 2.0);
  front->SetPoint1(1.3, -0.5, 2.0);
  front->SetPoint2(0.5, 0.3, 2.0);
  vtkNew<vtkPolyDataMapper> frontMapper;
  frontMapper->SetInputConnection(front->GetOutputPort());
  vtkNew<vtkActor> frontActor;
  frontActor->SetMapper(frontMapper);
  scene.renderer->AddActor(frontActor);
  scene.window->Render();

  vtkNew<vtkPropPicker> picker;
  const auto left = ProjectToPixel(scene.renderer, { -1.0, 0, 0 });
  ASSERT_TRUE(picker->Pick(left[0], left[1], 0, scene.renderer));
  EXPECT_EQ(picker->GetViewProp(), scene.actor.Get());
  // The pick position is on the sphere's near surface (z = 0.6 at its centre).
  EXPECT_NEAR(picker->GetPickPosition()[2], 0.6, 0.05);
  const auto right = ProjectToPixel(scene.renderer, { 1.0, 0, 0 });
  ASSERT_TRUE(picker->Pick(right[0], right[1], 0, scene.renderer));
  EXPECT_EQ(picker->GetViewProp(), frontActor.Get());
  EXPECT_FALSE(picker->Pick(2, 2, 0, scene.renderer));
}

TEST(Selection, SHGlyphsSelectTheirVoxel)
{
  // A 4 x 3 x 2 image of order-2 SH functions, all the round Y00 except the zero voxel 13;
  // the axial slice k = 1 (points 12 to 23) is drawn.
  vtkNew<vtkImageData> image;
  image->SetDimensions(4, 3, 2);
  image->SetOrigin(-1.5, -1.0, -0.5);
  image->SetSpacing(1.0, 1.0, 1.0);
  vtkNew<vtkDoubleArray> sh;
  sh->SetName("SH");
  sh->SetNumberOfComponents(6);
  sh->SetNumberOfTuples(image->GetNumberOfPoints());
  for (vtkIdType p = 0; p < image->GetNumberOfPoints(); ++p)
  {
    const double c[6] = { p == 13 ? 0.0 : 1.0, 0, 0, 0, 0, 0 };
    sh->SetTuple(p, c);
  }
  image->GetPointData()->AddArray(sh);

  MapperScene<vtkSightlineSHGlyphMapper> scene(kSize, kSize);
  scene.mapper->SetInputDataObject(image);
  scene.mapper->SetCoefficientArrayName("SH");
  scene.mapper->SetSliceOrientationToAxial();
  scene.mapper->SetSliceNumber(1);
  scene.mapper->SetScaleFactor(0.8);
  SetUpView(scene);
  scene.window->Render();
  ASSERT_EQ(scene.mapper->GetNumberOfPrimitives(), 11);

  for (vtkIdType voxel : { 12, 14, 18, 23 })
  {
    double x[3];
    image->GetPoint(voxel, x);
    SCOPED_TRACE("voxel " + std::to_string(voxel));
    ExpectSelected(SelectPixel(scene.renderer, ProjectToPixel(scene.renderer, { x[0], x[1], x[2] }),
                     kPoints),
      scene.actor, voxel, "points");
  }
  double empty[3];
  image->GetPoint(13, empty);
  EXPECT_TRUE(
    SelectPixel(scene.renderer, ProjectToPixel(scene.renderer, { empty[0], empty[1], empty[2] }),
      kPoints)
      .nodes.empty())
    << "the zero voxel has no glyph";
}

TEST(Selection, TensorEllipsoidsSelectTheirPoint)
{
  // Three diffusion tensors on points; the middle one is NaN (dropped).
  vtkNew<vtkPolyData> input;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(-1.5, 0, 0);
  points->InsertNextPoint(0, 0, 0);
  points->InsertNextPoint(1.5, 0, 0);
  input->SetPoints(points);
  vtkNew<vtkDoubleArray> tensors;
  tensors->SetName("tensors");
  tensors->SetNumberOfComponents(9);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double d[9] = { 0.5, 0, 0, 0, 0.3, 0, 0, 0, 0.3 };
  const double bad[9] = { nan, 0, 0, 0, nan, 0, 0, 0, nan };
  tensors->InsertNextTuple(d);
  tensors->InsertNextTuple(bad);
  tensors->InsertNextTuple(d);
  input->GetPointData()->SetTensors(tensors);

  MapperScene<vtkSightlineTensorGlyphMapper> scene(kSize, kSize);
  vtkNew<MessageCollector> messages; // the NaN tensor is reported
  messages->Observe(scene.mapper);
  scene.mapper->SetInputDataObject(input);
  scene.mapper->SetTensorArrayName("tensors");
  scene.mapper->SetShapeToEllipsoid();
  scene.mapper->SetScaleFactor(0.6);
  SetUpView(scene);
  scene.window->Render();
  ASSERT_EQ(scene.mapper->GetNumberOfPrimitives(), 2);
  ExpectSelected(SelectPixel(scene.renderer, ProjectToPixel(scene.renderer, { 1.5, 0, 0 }), kPoints),
    scene.actor, 2, "the ellipsoid after the dropped one");
  ExpectSelected(SelectPixel(scene.renderer, ProjectToPixel(scene.renderer, { -1.5, 0, 0 }), kPoints),
    scene.actor, 0, "the first ellipsoid");
}

namespace
{
/// A tube tree: vertex cell 0 (point 0), polyline cell 1 through points 0, 1, 2 along y = 1,
/// polyline cell 2 from point 1 down through 3 to 4 at z = 0.5, crossing in front of polyline
/// cell 3 (points 5, 6 along y = -0.5 at z = -0.5).
vtkSmartPointer<vtkPolyData> TubeTree()
{
  auto tree = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(-2.0, 1.0, 0.0);  // 0
  points->InsertNextPoint(0.0, 1.0, 0.5);   // 1
  points->InsertNextPoint(2.0, 1.0, 0.0);   // 2
  points->InsertNextPoint(0.0, 0.5, 0.5);   // 3
  points->InsertNextPoint(0.0, -1.5, 0.5);  // 4
  points->InsertNextPoint(-2.0, -0.5, -0.5); // 5
  points->InsertNextPoint(2.0, -0.5, -0.5); // 6
  tree->SetPoints(points);
  vtkNew<vtkCellArray> verts;
  const vtkIdType vertex[1] = { 0 };
  verts->InsertNextCell(1, vertex);
  tree->SetVerts(verts);
  vtkNew<vtkCellArray> lines;
  const vtkIdType top[3] = { 0, 1, 2 };
  const vtkIdType down[3] = { 1, 3, 4 };
  const vtkIdType across[2] = { 5, 6 };
  lines->InsertNextCell(3, top);
  lines->InsertNextCell(3, down);
  lines->InsertNextCell(2, across);
  tree->SetLines(lines);
  return tree;
}

/// Opacity and link layout: chunks (several links per kernel primitive) must still name the
/// link a pixel shows.
class TubeSelection : public ::testing::TestWithParam<std::tuple<double, int>>
{
};
} // namespace

TEST_P(TubeSelection, LinksSelectTheirPolylineAndStartPoint)
{
  const double opacity = std::get<0>(GetParam());
  MapperScene<vtkSightlineTubeMapper> scene(kSize, kSize);
  vtkNew<MessageCollector> messages;
  messages->Observe(scene.mapper);
  auto tree = TubeTree();
  scene.mapper->SetLinkLayout(std::get<1>(GetParam()));
  scene.mapper->SetInputDataObject(tree);
  scene.mapper->SetRadius(0.15);
  scene.actor->GetProperty()->SetOpacity(opacity);
  SetUpView(scene);
  scene.window->Render();

  struct Expected
  {
    std::array<double, 3> where;
    vtkIdType cell, point;
    const char* what;
  };
  const Expected expected[] = {
    { { -1.0, 1.0, 0.25 }, 1, 0, "link 0-1 of the first polyline" },
    { { 1.0, 1.0, 0.25 }, 1, 1, "link 1-2 of the first polyline" },
    { { 0.0, -0.5, 0.5 }, 2, 3, "link 3-4, nearest where it crosses the third polyline" },
    { { -1.2, -0.5, -0.5 }, 3, 5, "the third polyline away from the crossing" },
  };
  for (const Expected& e : expected)
  {
    SCOPED_TRACE(e.what);
    const auto pixel = ProjectToPixel(scene.renderer, e.where);
    ExpectSelected(SelectPixel(scene.renderer, pixel, kCells), scene.actor, e.cell, "cells");
    ExpectSelected(SelectPixel(scene.renderer, pixel, kPoints), scene.actor, e.point, "points");
  }
  EXPECT_TRUE(SelectPixel(scene.renderer, { 2, 2 }, kCells).nodes.empty());
  EXPECT_TRUE(messages->Errors.empty() && messages->Warnings.empty());
}

INSTANTIATE_TEST_SUITE_P(OpacityAndLayout, TubeSelection,
  ::testing::Combine(::testing::Values(1.0, 0.4),
    ::testing::Values(vtkSightlineTubeMapper::LINKS_COMBINED_ON_THE_FLY, vtkSightlineTubeMapper::LINKS_CHUNKED)),
  [](const ::testing::TestParamInfo<std::tuple<double, int>>& info)
  {
    return std::string(std::get<0>(info.param) < 1.0 ? "Translucent" : "Opaque") +
      (std::get<1>(info.param) == vtkSightlineTubeMapper::LINKS_CHUNKED ? "Chunked" : "Combined");
  });
