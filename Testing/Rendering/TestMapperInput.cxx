// SPDX-License-Identifier: BSD-3-Clause
// What ParaView hands a mapper: scalar colouring with InterpolateScalarsBeforeMapping on,
// empty inputs (before data arrives, empty blocks), bounds before data, and composite
// datasets (vtkMultiBlockDataSet, vtkPartitionedDataSet(Collection)). Every mapper kind, in a
// window and through the GL-free vtkSightlineImageRenderer.
#include "SightlineTestUtilities.h"

#include "vtkActor.h"
#include "vtkAppendPolyData.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkColorTransferFunction.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkLookupTable.h"
#include "vtkMath.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOutputWindow.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRectilinearGrid.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSightlineImageRenderer.h"
#include "vtkSightlineSHGlyphMapper.h"
#include "vtkSightlineSphereMapper.h"
#include "vtkSightlineSphericalFieldSource.h"
#include "vtkSightlineSphericalVolumeMapper.h"
#include "vtkSightlineTensorGlyphMapper.h"
#include "vtkSightlineTubeMapper.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

using namespace sightline_test;

namespace
{
constexpr int Size = 64;

// Every message VTK prints (errors and warnings of objects nobody observes, e.g. a pipeline's
// executive) while it is installed.
class CapturingOutputWindow : public vtkOutputWindow
{
public:
  static CapturingOutputWindow* New();
  vtkTypeMacro(CapturingOutputWindow, vtkOutputWindow);
  void DisplayText(const char* text) override { Messages.emplace_back(text ? text : ""); }
  std::vector<std::string> Messages;
};
vtkStandardNewMacro(CapturingOutputWindow);

struct CaptureOutput
{
  vtkNew<CapturingOutputWindow> window;
  vtkSmartPointer<vtkOutputWindow> previous = vtkOutputWindow::GetInstance();
  CaptureOutput() { vtkOutputWindow::SetInstance(window); }
  ~CaptureOutput() { vtkOutputWindow::SetInstance(previous); }
};

std::string Joined(const std::vector<std::string>& messages)
{
  std::string all;
  for (const std::string& m : messages)
    all += m + "\n";
  return all;
}

vtkSmartPointer<vtkImageData> RenderInWindow(vtkProp* prop, vtkCamera* camera)
{
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(0, 0, 0);
  renderer->AddViewProp(prop);
  renderer->SetActiveCamera(camera);
  vtkNew<vtkRenderWindow> window;
  window->AddRenderer(renderer);
  window->SetSize(Size, Size);
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->Render();
  return CaptureRGB(window);
}

vtkSmartPointer<vtkImageData> RenderWithoutGL(vtkProp* prop, vtkCamera* camera)
{
  vtkNew<vtkSightlineImageRenderer> renderer;
  if (auto* actor = vtkActor::SafeDownCast(prop))
    renderer->AddActor(actor);
  if (auto* volume = vtkVolume::SafeDownCast(prop))
    renderer->AddVolume(volume);
  renderer->SetActiveCamera(camera);
  renderer->SetSize(Size, Size);
  renderer->SetBackground(0, 0, 0);
  renderer->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(renderer->GetOutput());
  return image;
}

// A lookup table from blue (0) to red (1), over [0, 1].
vtkSmartPointer<vtkLookupTable> BlueToRed()
{
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetHueRange(0.667, 0.0);
  lut->SetRange(0, 1);
  lut->Build();
  return lut;
}

void ColorByValue(vtkMapper* mapper)
{
  mapper->SetLookupTable(BlueToRed());
  mapper->SetScalarRange(0, 1);
  mapper->UseLookupTableScalarRangeOff();
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectColorArray("value");
  mapper->ScalarVisibilityOn();
}

// Two spheres: one blue (value 0), one red (value 1).
vtkSmartPointer<vtkPolyData> TwoSpheres(double y = 0.0)
{
  auto spheres = MakeSpheres({ { -0.8, y, 0 }, { 0.8, y, 0 } }, { 0.6, 0.6 });
  vtkDataArray* value = spheres->GetPointData()->GetArray("value");
  value->SetComponent(0, 0, 0.0);
  value->SetComponent(1, 0, 1.0);
  return spheres;
}

// One polyline through points along x at height y, "value" from 0 to 1, "radius" 0.25.
vtkSmartPointer<vtkPolyData> Polyline(double y, bool predecessors = false)
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> value;
  value->SetName("value");
  vtkNew<vtkDoubleArray> parent;
  parent->SetName("parent");
  vtkNew<vtkCellArray> lines;
  const int n = 4;
  lines->InsertNextCell(n);
  for (int i = 0; i < n; ++i)
  {
    points->InsertNextPoint(-1.2 + 0.8 * i, y, 0.0);
    value->InsertNextValue(i / double(n - 1));
    parent->InsertNextValue(i - 1);
    lines->InsertCellPoint(i);
  }
  poly->SetPoints(points);
  poly->GetPointData()->AddArray(value);
  if (predecessors)
    poly->GetPointData()->AddArray(parent);
  else
    poly->SetLines(lines);
  return poly;
}

// A single-voxel image with an order-2 SH glyph (a sphere) and "value" 1.
vtkSmartPointer<vtkImageData> SHVoxel(double x = 0.0)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(1, 1, 1);
  image->SetOrigin(x, 0, 0);
  vtkNew<vtkDoubleArray> sh;
  sh->SetName("SH");
  sh->SetNumberOfComponents(6);
  sh->SetNumberOfTuples(1);
  sh->Fill(0.0);
  sh->SetComponent(0, 0, 1.0);
  sh->SetComponent(0, 3, 0.3);
  image->GetPointData()->AddArray(sh);
  vtkNew<vtkDoubleArray> value;
  value->SetName("value");
  value->InsertNextValue(1.0);
  image->GetPointData()->AddArray(value);
  vtkNew<vtkDoubleArray> tensor;
  tensor->SetName("T");
  tensor->SetNumberOfComponents(6); // xx, xy, xz, yy, yz, zz
  tensor->InsertNextTuple6(1.0, 0.0, 0.0, 0.5, 0.0, 0.3);
  image->GetPointData()->AddArray(tensor);
  return image;
}

// The spherical-volume scene of the volume tests, at a radius that fits the test camera.
struct VolumeScene
{
  vtkNew<vtkSightlineSphericalVolumeMapper> mapper;
  vtkNew<vtkColorTransferFunction> color;
  vtkNew<vtkPiecewiseFunction> opacity;
  vtkNew<vtkVolumeProperty> property;
  vtkNew<vtkVolume> volume;

  VolumeScene()
  {
    color->AddRGBPoint(0.0, 0.2, 0.4, 1.0);
    color->AddRGBPoint(2.0, 1.0, 0.6, 0.1);
    opacity->AddPoint(0.0, 0.3);
    opacity->AddPoint(2.0, 0.6);
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    property->SetScalarOpacityUnitDistance(0.5);
    volume->SetMapper(mapper);
    volume->SetProperty(property);
  }
};

vtkSmartPointer<vtkRectilinearGrid> SphericalGrid()
{
  vtkNew<vtkSightlineSphericalFieldSource> source;
  source->SetRadialResolution(6);
  source->SetPolarResolution(6);
  source->SetAzimuthalResolution(12);
  source->Update();
  auto grid = vtkSmartPointer<vtkRectilinearGrid>::New();
  grid->ShallowCopy(source->GetOutput());
  return grid;
}

template <typename Leaf>
vtkSmartPointer<vtkMultiBlockDataSet> MultiBlock(const std::vector<Leaf>& leaves)
{
  auto blocks = vtkSmartPointer<vtkMultiBlockDataSet>::New();
  blocks->SetNumberOfBlocks(static_cast<unsigned int>(leaves.size()));
  for (unsigned int i = 0; i < leaves.size(); ++i)
    blocks->SetBlock(i, leaves[i]);
  return blocks;
}

// One partitioned dataset per leaf, as ParaView builds for composite data.
template <typename Leaf>
vtkSmartPointer<vtkPartitionedDataSetCollection> Collection(const std::vector<Leaf>& leaves)
{
  auto collection = vtkSmartPointer<vtkPartitionedDataSetCollection>::New();
  for (unsigned int i = 0; i < leaves.size(); ++i)
  {
    vtkNew<vtkPartitionedDataSet> partitioned;
    partitioned->SetPartition(0, leaves[i]);
    collection->SetPartitionedDataSet(i, partitioned);
  }
  return collection;
}

// Both paths render `prop` (whose mapper is observed by `messages`).
struct Renders
{
  vtkSmartPointer<vtkImageData> window;
  vtkSmartPointer<vtkImageData> noGL;
};
Renders RenderBoth(vtkProp* prop, vtkCamera* camera)
{
  return { RenderInWindow(prop, camera), RenderWithoutGL(prop, camera) };
}
} // namespace

// ParaView turns InterpolateScalarsBeforeMapping on. vtkMapper then maps scalars to a texture
// and returns no colours; ray-traced primitives have no texture coordinates, so the mappers
// must colour per point as with the flag off (they used to come out in the actor's colour).
TEST(MapperInput, InterpolateScalarsBeforeMappingDoesNotChangeColours)
{
  auto camera = MakeCamera(true, 10.0, 2.0);
  auto check = [&](vtkMapper* mapper, vtkActor* actor, const std::string& what)
  {
    vtkNew<MessageCollector> messages;
    messages->Observe(mapper);
    ColorByValue(mapper);
    mapper->InterpolateScalarsBeforeMappingOff();
    const Renders off = RenderBoth(actor, camera);
    mapper->InterpolateScalarsBeforeMappingOn();
    const Renders on = RenderBoth(actor, camera);
    EXPECT_GT(CoveredPixels(off.window), 50) << what;
    EXPECT_EQ(MaxRGBDifference(off.window, on.window), 0) << what << " in a window";
    EXPECT_EQ(MaxRGBDifference(off.noGL, on.noGL), 0) << what << " without GL";
    EXPECT_TRUE(messages->Errors.empty()) << what << ": " << Joined(messages->Errors);
    EXPECT_TRUE(messages->Warnings.empty()) << what << ": " << Joined(messages->Warnings);
    mapper->RemoveObserver(messages);
    mapper->ScalarVisibilityOff(); // glyphs coloured by scalars warn: not checked

    const Renders plain = RenderBoth(actor, camera);
    EXPECT_GT(MaxRGBDifference(plain.window, on.window), 100)
      << what << ": the scalar colours differ from the actor's colour";
  };

  {
    vtkNew<vtkSightlineSphereMapper> mapper;
    mapper->SetInputDataObject(TwoSpheres());
    mapper->SetRadiusArrayName("radius");
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    check(mapper, actor, "spheres");
  }
  {
    vtkNew<vtkSightlineTubeMapper> mapper;
    mapper->SetInputDataObject(Polyline(0.0));
    mapper->SetRadius(0.25);
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    check(mapper, actor, "tubes");
  }
  {
    vtkNew<vtkSightlineSHGlyphMapper> mapper;
    mapper->SetInputDataObject(SHVoxel());
    mapper->SetCoefficientArrayName("SH");
    mapper->SetScaleFactor(2.5);
    mapper->SetColoringToScalars();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    check(mapper, actor, "SH glyphs");
  }
  {
    vtkNew<vtkSightlineTensorGlyphMapper> mapper;
    mapper->SetInputDataObject(SHVoxel());
    mapper->SetTensorArrayName("T");
    mapper->SetScaleFactor(2.5);
    mapper->SetColoringToScalars();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    check(mapper, actor, "tensor glyphs");
  }
}

// No input, an empty dataset of every kind, an empty composite: nothing is drawn, nothing is
// said, nothing crashes, and the bounds are uninitialized.
TEST(MapperInput, EmptyInputsRenderNothingQuietly)
{
  auto camera = MakeCamera(true, 10.0, 2.0);
  // Empty inputs, by the mapper kinds that accept them.
  using Make = std::function<vtkSmartPointer<vtkDataObject>()>;
  const Make none = [] { return vtkSmartPointer<vtkDataObject>(); };
  const Make emptyPolyData = [] { return vtkSmartPointer<vtkPolyData>::New(); };
  const Make zeroPoints = []
  {
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> points;
    poly->SetPoints(points);
    return poly;
  };
  const Make emptyGrid = [] { return vtkSmartPointer<vtkUnstructuredGrid>::New(); };
  const Make emptyImage = [] { return vtkSmartPointer<vtkImageData>::New(); };
  const Make emptyRectilinear = [] { return vtkSmartPointer<vtkRectilinearGrid>::New(); };
  const Make emptyMultiBlock = [] { return vtkSmartPointer<vtkMultiBlockDataSet>::New(); };
  const Make emptyCollection = [] { return vtkSmartPointer<vtkPartitionedDataSetCollection>::New(); };
  const Make emptyLeaves = []
  {
    return MultiBlock(std::vector<vtkSmartPointer<vtkDataObject>>{
      vtkSmartPointer<vtkPolyData>::New(), nullptr, vtkSmartPointer<vtkPolyData>::New() });
  };
  const Make emptyImageLeaf = []
  {
    return Collection(std::vector<vtkSmartPointer<vtkDataObject>>{ vtkSmartPointer<vtkImageData>::New() });
  };
  const Make emptyRectilinearLeaf = []
  {
    return MultiBlock(std::vector<vtkSmartPointer<vtkDataObject>>{ vtkSmartPointer<vtkRectilinearGrid>::New() });
  };
  const std::vector<std::pair<std::string, Make>> pointSets = { { "no input", none },
    { "empty vtkPolyData", emptyPolyData }, { "vtkPolyData of 0 points", zeroPoints },
    { "empty vtkUnstructuredGrid", emptyGrid }, { "empty vtkMultiBlockDataSet", emptyMultiBlock },
    { "empty vtkPartitionedDataSetCollection", emptyCollection },
    { "vtkMultiBlockDataSet of empty vtkPolyData", emptyLeaves } };
  const std::vector<std::pair<std::string, Make>> images = { { "no input", none },
    { "empty vtkImageData", emptyImage }, { "empty vtkPolyData", emptyPolyData },
    { "empty vtkMultiBlockDataSet", emptyMultiBlock },
    { "empty vtkPartitionedDataSetCollection", emptyCollection },
    { "collection of an empty vtkImageData", emptyImageLeaf } };
  const std::vector<std::pair<std::string, Make>> grids = { { "no input", none },
    { "empty vtkRectilinearGrid", emptyRectilinear },
    { "empty vtkMultiBlockDataSet", emptyMultiBlock },
    { "empty vtkPartitionedDataSetCollection", emptyCollection },
    { "vtkMultiBlockDataSet of an empty vtkRectilinearGrid", emptyRectilinearLeaf } };

  auto check = [&](vtkAbstractMapper3D* mapper, vtkProp* prop, const std::string& kind,
                 const std::vector<std::pair<std::string, Make>>& inputs)
  {
    for (const auto& input : inputs)
    {
      const std::string what = kind + ", " + input.first;
      CaptureOutput output;
      vtkNew<MessageCollector> messages;
      messages->Observe(mapper);
      vtkSmartPointer<vtkDataObject> data = input.second();
      if (data)
        mapper->SetInputDataObject(data);
      else
        mapper->RemoveAllInputConnections(0);
      double bounds[6];
      mapper->GetBounds(bounds);
      EXPECT_FALSE(vtkMath::AreBoundsInitialized(bounds)) << what;
      const Renders rendered = RenderBoth(prop, camera);
      EXPECT_EQ(CoveredPixels(rendered.window), 0) << what;
      EXPECT_EQ(CoveredPixels(rendered.noGL), 0) << what;
      EXPECT_TRUE(messages->Errors.empty()) << what << ": " << Joined(messages->Errors);
      EXPECT_TRUE(messages->Warnings.empty()) << what << ": " << Joined(messages->Warnings);
      EXPECT_TRUE(output.window->Messages.empty()) << what << ": " << Joined(output.window->Messages);
      mapper->RemoveObserver(messages);
    }
  };

  {
    vtkNew<vtkSightlineSphereMapper> mapper;
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    check(mapper, actor, "spheres", pointSets);
  }
  {
    vtkNew<vtkSightlineTubeMapper> mapper;
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    check(mapper, actor, "tubes", pointSets);
  }
  {
    vtkNew<vtkSightlineSHGlyphMapper> mapper;
    mapper->SetCoefficientArrayName("SH");
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    check(mapper, actor, "SH glyphs", images);
  }
  {
    vtkNew<vtkSightlineTensorGlyphMapper> mapper;
    mapper->SetTensorArrayName("T");
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    check(mapper, actor, "tensor glyphs", images);
  }
  {
    VolumeScene scene;
    check(scene.mapper, scene.volume, "spherical volume", grids);
  }
}

// A new mapper, before any input: uninitialized bounds, and no message.
TEST(MapperInput, BoundsBeforeInputAreUninitialized)
{
  CaptureOutput output;
  vtkNew<MessageCollector> messages;
  vtkNew<vtkSightlineSphereMapper> spheres;
  vtkNew<vtkSightlineTubeMapper> tubes;
  vtkNew<vtkSightlineSHGlyphMapper> sh;
  vtkNew<vtkSightlineTensorGlyphMapper> tensors;
  vtkNew<vtkSightlineSphericalVolumeMapper> volume;
  for (vtkAbstractMapper3D* mapper :
    std::vector<vtkAbstractMapper3D*>{ spheres, tubes, sh, tensors, volume })
  {
    messages->Observe(mapper);
    const double* bounds = mapper->GetBounds();
    ASSERT_NE(bounds, nullptr);
    EXPECT_FALSE(vtkMath::AreBoundsInitialized(bounds)) << mapper->GetClassName();
  }
  EXPECT_TRUE(messages->Errors.empty()) << Joined(messages->Errors);
  EXPECT_TRUE(messages->Warnings.empty()) << Joined(messages->Warnings);
  EXPECT_TRUE(output.window->Messages.empty()) << Joined(output.window->Messages);
}

// Spheres: a composite of two polydata renders exactly as the two appended, point data
// (the colouring array) included; so does a vtkPartitionedDataSetCollection of them.
TEST(MapperInput, CompositeSpheresRenderAsTheirUnion)
{
  auto camera = MakeCamera(true, 10.0, 2.5);
  const auto a = TwoSpheres(-0.9);
  const auto b = TwoSpheres(0.9);
  vtkNew<vtkAppendPolyData> append;
  append->AddInputData(a);
  append->AddInputData(b);
  append->Update();

  vtkNew<vtkSightlineSphereMapper> mapper;
  mapper->SetRadiusArrayName("radius");
  ColorByValue(mapper);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<MessageCollector> messages;
  messages->Observe(mapper);

  mapper->SetInputDataObject(append->GetOutput());
  const Renders appended = RenderBoth(actor, camera);
  EXPECT_GT(CoveredPixels(appended.window), 400);
  double expected[6];
  mapper->GetBounds(expected);

  using Leaves = std::vector<vtkSmartPointer<vtkDataObject>>;
  for (const auto& composite : std::vector<vtkSmartPointer<vtkDataObject>>{
         MultiBlock(Leaves{ a, nullptr, vtkSmartPointer<vtkPolyData>::New(), b }),
         Collection(Leaves{ a, b }) })
  {
    mapper->SetInputDataObject(composite);
    const Renders images = RenderBoth(actor, camera);
    EXPECT_EQ(MaxRGBDifference(images.window, appended.window), 0) << composite->GetClassName();
    EXPECT_EQ(MaxRGBDifference(images.noGL, appended.noGL), 0) << composite->GetClassName();
    EXPECT_EQ(mapper->GetNumberOfPrimitives(), 4);
    double bounds[6];
    mapper->GetBounds(bounds);
    for (int i = 0; i < 6; ++i)
      EXPECT_DOUBLE_EQ(bounds[i], expected[i]) << i;
  }
  EXPECT_TRUE(messages->Errors.empty()) << Joined(messages->Errors);
  EXPECT_TRUE(messages->Warnings.empty()) << Joined(messages->Warnings);

  // Leaves of different point-set types are appended as an unstructured grid, arrays kept.
  vtkNew<vtkUnstructuredGrid> bGrid;
  bGrid->SetPoints(b->GetPoints());
  bGrid->GetPointData()->ShallowCopy(b->GetPointData());
  mapper->SetInputDataObject(MultiBlock(Leaves{ a, bGrid }));
  const Renders mixedTypes = RenderBoth(actor, camera);
  EXPECT_EQ(MaxRGBDifference(mixedTypes.window, appended.window), 0);
  EXPECT_EQ(MaxRGBDifference(mixedTypes.noGL, appended.noGL), 0);
  EXPECT_TRUE(messages->Errors.empty()) << Joined(messages->Errors);

  // A leaf the mapper cannot draw is named, and the rest is drawn.
  mapper->SetInputDataObject(MultiBlock(Leaves{ a, SHVoxel(), b }));
  const Renders mixed = RenderBoth(actor, camera);
  EXPECT_TRUE(messages->Contains("vtkImageData")) << Joined(messages->Errors);
  EXPECT_EQ(MaxRGBDifference(mixed.window, appended.window), 0);
}

// Tubes: each leaf's polylines stay separate, and a predecessor array, which holds point ids of
// its own leaf, is offset into the union.
TEST(MapperInput, CompositeTubesRenderAsTheirUnion)
{
  auto camera = MakeCamera(true, 10.0, 2.5);
  vtkNew<vtkSightlineTubeMapper> mapper;
  mapper->SetRadius(0.3);
  ColorByValue(mapper);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<MessageCollector> messages;
  messages->Observe(mapper);
  using Leaves = std::vector<vtkSmartPointer<vtkDataObject>>;

  for (const bool predecessors : { false, true })
  {
    const std::string what = predecessors ? "predecessor arrays" : "polylines";
    mapper->SetPredecessorArrayName(predecessors ? "parent" : nullptr);
    const auto a = Polyline(-0.8, predecessors);
    const auto b = Polyline(0.8, predecessors);
    // The reference: one polydata with the second line's ids offset by hand.
    auto both = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> points;
    vtkNew<vtkDoubleArray> value;
    value->SetName("value");
    vtkNew<vtkDoubleArray> parent;
    parent->SetName("parent");
    vtkNew<vtkCellArray> lines;
    for (vtkPolyData* line : { a.Get(), b.Get() })
    {
      const vtkIdType first = points->GetNumberOfPoints();
      lines->InsertNextCell(line->GetNumberOfPoints());
      for (vtkIdType i = 0; i < line->GetNumberOfPoints(); ++i)
      {
        points->InsertNextPoint(line->GetPoint(i));
        value->InsertNextValue(line->GetPointData()->GetArray("value")->GetComponent(i, 0));
        parent->InsertNextValue(i == 0 ? -1 : first + i - 1);
        lines->InsertCellPoint(first + i);
      }
    }
    both->SetPoints(points);
    both->GetPointData()->AddArray(value);
    if (predecessors)
      both->GetPointData()->AddArray(parent);
    else
      both->SetLines(lines);
    mapper->SetInputDataObject(both);
    const Renders expected = RenderBoth(actor, camera);
    EXPECT_GT(CoveredPixels(expected.window), 400) << what;
    const vtkIdType links = mapper->GetNumberOfLinks();

    for (const auto& composite :
      std::vector<vtkSmartPointer<vtkDataObject>>{ MultiBlock(Leaves{ a, b }), Collection(Leaves{ a, b }) })
    {
      mapper->SetInputDataObject(composite);
      const Renders images = RenderBoth(actor, camera);
      EXPECT_EQ(MaxRGBDifference(images.window, expected.window), 0) << what;
      EXPECT_EQ(MaxRGBDifference(images.noGL, expected.noGL), 0) << what;
      EXPECT_EQ(mapper->GetNumberOfLinks(), links) << what;
    }
  }
  EXPECT_TRUE(messages->Errors.empty()) << Joined(messages->Errors);
  EXPECT_TRUE(messages->Warnings.empty()) << Joined(messages->Warnings);
}

// Glyphs: a composite with one image (and empty leaves beside it, as ParaView gives a rank)
// renders as the image; with several images the first is drawn, with a warning naming the
// count.
TEST(MapperInput, CompositeWithOneImageRendersAsTheImage)
{
  auto camera = MakeCamera(true, 10.0, 2.0);
  vtkNew<vtkSightlineSHGlyphMapper> mapper;
  mapper->SetCoefficientArrayName("SH");
  mapper->SetScaleFactor(2.5);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<MessageCollector> messages;
  messages->Observe(mapper);

  const auto image = SHVoxel();
  mapper->SetInputDataObject(image);
  const Renders expected = RenderBoth(actor, camera);
  EXPECT_GT(CoveredPixels(expected.window), 50);

  using Leaves = std::vector<vtkSmartPointer<vtkDataObject>>;
  for (const auto& composite : std::vector<vtkSmartPointer<vtkDataObject>>{
         MultiBlock(Leaves{ image }),
         MultiBlock(Leaves{ vtkSmartPointer<vtkImageData>::New(), nullptr, image }),
         Collection(Leaves{ image }) })
  {
    mapper->SetInputDataObject(composite);
    const Renders images = RenderBoth(actor, camera);
    EXPECT_EQ(MaxRGBDifference(images.window, expected.window), 0) << composite->GetClassName();
    EXPECT_EQ(MaxRGBDifference(images.noGL, expected.noGL), 0) << composite->GetClassName();
  }
  EXPECT_TRUE(messages->Errors.empty()) << Joined(messages->Errors);
  EXPECT_TRUE(messages->Warnings.empty()) << Joined(messages->Warnings);

  mapper->SetInputDataObject(MultiBlock(Leaves{ image, SHVoxel(5.0) }));
  const Renders first = RenderBoth(actor, camera);
  EXPECT_EQ(MaxRGBDifference(first.window, expected.window), 0);
  EXPECT_EQ(messages->Warnings.size(), 1u) << Joined(messages->Warnings);
  EXPECT_TRUE(messages->Contains("has 2 non-empty vtkDataSet leaves"));
}

// The spherical volume: a multiblock holding the grid renders as the grid.
TEST(MapperInput, CompositeWithOneGridRendersAsTheGrid)
{
  auto camera = MakeCamera(true, 10.0, 1.2);
  VolumeScene scene;
  vtkNew<MessageCollector> messages;
  messages->Observe(scene.mapper);
  const auto grid = SphericalGrid();
  scene.mapper->SetInputDataObject(grid);
  const Renders expected = RenderBoth(scene.volume, camera);
  EXPECT_GT(CoveredPixels(expected.noGL), 100);
  using Leaves = std::vector<vtkSmartPointer<vtkDataObject>>;
  for (const auto& composite : std::vector<vtkSmartPointer<vtkDataObject>>{
         MultiBlock(Leaves{ nullptr, grid }), Collection(Leaves{ grid }) })
  {
    scene.mapper->SetInputDataObject(composite);
    const Renders images = RenderBoth(scene.volume, camera);
    EXPECT_EQ(MaxRGBDifference(images.window, expected.window), 0) << composite->GetClassName();
    EXPECT_EQ(MaxRGBDifference(images.noGL, expected.noGL), 0) << composite->GetClassName();
  }
  EXPECT_TRUE(messages->Errors.empty()) << Joined(messages->Errors);
  EXPECT_TRUE(messages->Warnings.empty()) << Joined(messages->Warnings);

  scene.mapper->SetInputDataObject(MultiBlock(Leaves{ grid, TwoSpheres() }));
  RenderWithoutGL(scene.volume, camera);
  EXPECT_TRUE(messages->Contains("(the first is a vtkPolyData)")) << Joined(messages->Errors);
}
