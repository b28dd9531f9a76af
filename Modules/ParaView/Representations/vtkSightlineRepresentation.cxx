// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineRepresentation.h"

#include "vtkActor.h"
#include "vtkAlgorithm.h"
#include "vtkAlgorithmOutput.h"
#include "vtkAppendFilter.h"
#include "vtkBoundingBox.h"
#include "vtkCellType.h"
#include "vtkCommunicator.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataSet.h"
#include "vtkExtractCells.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkProperty.h"
#include "vtkPVRenderView.h"
#include "vtkPVRenderViewDataDeliveryManager.h"
#include "vtkRenderer.h"
#include "vtkScalarsToColors.h"
#include "vtkSightlineMapper.h"
#include "vtkTransform.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <vector>

namespace
{
// Bounds of a data set or of every non-empty leaf of a composite.
void DataObjectBounds(vtkDataObject* data, double bounds[6])
{
  vtkBoundingBox box;
  if (auto* dataSet = vtkDataSet::SafeDownCast(data))
  {
    if (dataSet->GetNumberOfPoints() > 0)
    {
      box.AddBounds(dataSet->GetBounds());
    }
  }
  else if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      auto* leaf = vtkDataSet::SafeDownCast(it->GetCurrentDataObject());
      if (leaf && leaf->GetNumberOfPoints() > 0)
      {
        box.AddBounds(leaf->GetBounds());
      }
    }
  }
  if (box.IsValid())
  {
    box.GetBounds(bounds);
  }
  else
  {
    vtkMath::UninitializeBounds(bounds);
  }
}

// A shallow copy of `data` as a vtkMultiBlockDataSet: a multiblock as it is, a data set as its
// only block, another composite (partitioned collections) as a flat list of its leaves.
vtkSmartPointer<vtkMultiBlockDataSet> AsMultiBlock(vtkDataObject* data)
{
  auto blocks = vtkSmartPointer<vtkMultiBlockDataSet>::New();
  if (auto* multiBlock = vtkMultiBlockDataSet::SafeDownCast(data))
  {
    blocks->ShallowCopy(multiBlock);
  }
  else if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    unsigned int block = 0;
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      vtkSmartPointer<vtkDataObject> leaf;
      leaf.TakeReference(it->GetCurrentDataObject()->NewInstance());
      leaf->ShallowCopy(it->GetCurrentDataObject());
      blocks->SetBlock(block++, leaf);
    }
  }
  else if (data)
  {
    vtkSmartPointer<vtkDataObject> copy;
    copy.TakeReference(data->NewInstance());
    copy->ShallowCopy(data);
    blocks->SetBlock(0, copy);
  }
  return blocks;
}

/// The view's regions as each rank draws them: the cuts end at the load-balancing data's
/// bounds, and what lies beyond (a tube's radius, a glyph) belongs to the region at that face,
/// so faces on the outside of all regions move to infinity. Invalid boxes stay invalid.
std::vector<vtkBoundingBox> OpenRegions(const std::vector<vtkBoundingBox>& cuts)
{
  vtkBoundingBox all;
  for (const vtkBoundingBox& cut : cuts)
  {
    if (cut.IsValid())
    {
      all.AddBox(cut);
    }
  }
  double outer[6];
  all.GetBounds(outer);
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<vtkBoundingBox> regions(cuts.size());
  for (std::size_t r = 0; r < cuts.size(); ++r)
  {
    if (!cuts[r].IsValid())
    {
      continue;
    }
    double bounds[6];
    cuts[r].GetBounds(bounds);
    for (int i = 0; i < 6; ++i)
    {
      if (bounds[i] == outer[i])
      {
        bounds[i] = i % 2 ? inf : -inf;
      }
    }
    regions[r].SetBounds(bounds);
  }
  return regions;
}

/// Sends every cell to each rank whose region (regions[rank]) its bounds meet, so that a cell
/// near a border goes to every rank it reaches; what this rank receives from all ranks becomes
/// inputs of `received`. Collective. Done by hand rather than by vtkRedistributeDataSetFilter:
/// with overlapping explicit cuts, VTK 9.3's filter (ParaView 5.13) gives a cell to one of the
/// regions that contain it only, whatever the boundary mode, where VTK 9.2's gave it to all.
void SendToRegions(vtkMultiProcessController* controller, vtkUnstructuredGrid* cells,
  const std::vector<vtkBoundingBox>& regions, vtkAppendFilter* received)
{
  std::vector<vtkBoundingBox> cellBoxes(static_cast<std::size_t>(cells->GetNumberOfCells()));
  for (vtkIdType c = 0; c < cells->GetNumberOfCells(); ++c)
  {
    double bounds[6];
    cells->GetCellBounds(c, bounds);
    cellBoxes[static_cast<std::size_t>(c)].SetBounds(bounds);
  }
  const int ranks = controller->GetNumberOfProcesses();
  for (int destination = 0; destination < ranks; ++destination)
  {
    vtkNew<vtkIdList> ids;
    const vtkBoundingBox& region = regions[static_cast<std::size_t>(destination)];
    for (std::size_t c = 0; region.IsValid() && c < cellBoxes.size(); ++c)
    {
      if (region.Intersects(cellBoxes[c]))
      {
        ids->InsertNextId(static_cast<vtkIdType>(c));
      }
    }
    vtkNew<vtkExtractCells> extract;
    extract->SetInputData(cells);
    extract->SetCellList(ids);
    extract->Update();
    std::vector<vtkSmartPointer<vtkDataObject>> parts;
    controller->Gather(extract->GetOutput(), parts, destination);
    for (const auto& part : parts)
    {
      auto* grid = vtkUnstructuredGrid::SafeDownCast(part);
      if (grid && grid->GetNumberOfCells() > 0)
      {
        received->AddInputData(grid);
      }
    }
  }
}
}

vtkSmartPointer<vtkUnstructuredGrid> vtkSightlineRepresentation::CellsOnPoints(vtkPointSet* leaf)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(leaf->GetPoints());
  grid->GetPointData()->ShallowCopy(leaf->GetPointData());
  return grid;
}

vtkSmartPointer<vtkUnstructuredGrid> vtkSightlineRepresentation::AppendedCells(vtkAppendFilter* append)
{
  if (append->GetNumberOfInputConnections(0) == 0)
  {
    return vtkSmartPointer<vtkUnstructuredGrid>::New(); // an empty piece still takes part
  }
  append->Update();
  auto cells = vtkSmartPointer<vtkUnstructuredGrid>::New();
  cells->ShallowCopy(append->GetOutput());
  return cells;
}

vtkSightlineRepresentation::vtkSightlineRepresentation(vtkSightlineMapper* mapper)
  : Mapper(mapper)
  , Actor(vtkSmartPointer<vtkActor>::New())
  , Property(vtkSmartPointer<vtkProperty>::New())
{
  this->Actor->SetMapper(this->Mapper);
  this->Actor->SetProperty(this->Property);
  // Hidden until the view hands the mapper its data: a composite representation adds every
  // sub-representation's prop to the renderer, and the inactive ones never get data.
  this->Actor->SetVisibility(0);
  // No scalar colouring until ParaView selects an array.
  this->Mapper->SetScalarVisibility(0);
  vtkMath::UninitializeBounds(this->DataBounds);
}

vtkSightlineRepresentation::~vtkSightlineRepresentation() = default;

vtkSightlineMapper* vtkSightlineRepresentation::GetSightlineMapper()
{
  return this->Mapper;
}

vtkActor* vtkSightlineRepresentation::GetActor()
{
  return this->Actor;
}

int vtkSightlineRepresentation::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkSightlineRepresentation::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMath::UninitializeBounds(this->DataBounds);
  this->Cache = nullptr;
  if (inputVector[0]->GetNumberOfInformationObjects() == 1)
  {
    if (vtkDataObject* input = vtkDataObject::GetData(inputVector[0], 0))
    {
      // A shallow copy, so that the view delivers this frame's data even if the pipeline
      // re-executes before the next render; always a vtkMultiBlockDataSet (see below).
      this->Cache = AsMultiBlock(input);
      DataObjectBounds(this->Cache, this->DataBounds);
    }
  }
  if (!this->Cache)
  {
    // A pvserver's client has no input. With local rendering the view moves every rank's piece
    // to the client, which must offer a piece of the same type as the servers' (the move's
    // output type is the local piece's): with none it receives nothing while the server sends
    // and aborts on the unexpected message ("Wrong tag"); with another type it gets an empty
    // object. So every process holds a multiblock, the client an empty one, as
    // vtkGeometryRepresentation does.
    this->Cache = vtkSmartPointer<vtkMultiBlockDataSet>::New();
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

int vtkSightlineRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request, inInfo, outInfo))
  {
    return 0;
  }
  if (request == vtkPVView::REQUEST_UPDATE())
  {
    // Ranks without data still take part in every frame: an empty piece, drawn as nothing.
    vtkPVView::SetPiece(inInfo, this, this->Cache);
    vtkPVRenderView::SetGeometryBounds(inInfo, this, this->DataBounds);
    if (this->DrawsByRegion())
    {
      // The view's kd-tree regions are built from the points of these pieces (the data stay
      // where they are: DrawRegion moves them, with the margin the view's move lacks).
      vtkPVRenderView::SetOrderedCompositingConfiguration(
        inInfo, this, vtkPVRenderView::USE_DATA_FOR_LOAD_BALANCING);
    }
    if (this->NeedsOrderedCompositing())
    {
      outInfo->Set(vtkPVRenderView::NEED_ORDERED_COMPOSITING(), 1);
    }
  }
  else if (request == vtkPVView::REQUEST_RENDER())
  {
    // A client of a pvserver that renders remotely gets no data, only a placeholder
    // vtkDataObject: nothing to draw there, and no input for the mapper to refuse.
    vtkAlgorithmOutput* producer = vtkPVRenderView::GetPieceProducer(inInfo, this);
    vtkDataObject* piece = producer && producer->GetProducer()
      ? producer->GetProducer()->GetOutputDataObject(producer->GetIndex())
      : nullptr;
    const bool drawable =
      vtkDataSet::SafeDownCast(piece) || vtkCompositeDataSet::SafeDownCast(piece);
    if (drawable)
    {
      this->SetMapperInput(inInfo, producer);
    }
    this->Actor->SetVisibility(drawable && this->GetVisibility() ? 1 : 0);
  }
  return 1;
}

void vtkSightlineRepresentation::SetMapperInput(vtkInformation* inInfo, vtkAlgorithmOutput* producer)
{
  double region[6];
  // The same decision on every rank: DrawRegion is collective.
  if (this->DrawsByRegion() && GetOrderedCompositingRegion(inInfo, region))
  {
    this->DrawRegion(producer->GetProducer()->GetOutputDataObject(producer->GetIndex()), region, inInfo);
    return;
  }
  this->DrawingRegionCells(false);
  this->Mapper->SetRegionToAllOfSpace();
  this->Mapper->SetInputConnection(producer);
}

bool vtkSightlineRepresentation::DrawsByRegion()
{
  // Mappers of primitives centred on points (spheres, tubes) have a reach; glyph mappers none.
  return this->Mapper->ComputeReach(nullptr) >= 0.0;
}

vtkSmartPointer<vtkUnstructuredGrid> vtkSightlineRepresentation::RegionCells(vtkDataObject* piece)
{
  vtkNew<vtkAppendFilter> append;
  for (vtkPointSet* leaf : vtkSightlineMapper::PointSets(piece))
  {
    const vtkIdType count = leaf->GetNumberOfPoints();
    if (count == 0)
    {
      continue;
    }
    auto vertices = CellsOnPoints(leaf);
    vertices->Allocate(count);
    for (vtkIdType i = 0; i < count; ++i)
    {
      vertices->InsertNextCell(VTK_VERTEX, 1, &i);
    }
    append->AddInputData(vertices);
  }
  return AppendedCells(append);
}

void vtkSightlineRepresentation::DrawRegion(
  vtkDataObject* piece, const double region[6], vtkInformation* inInfo)
{
  auto* controller = vtkMultiProcessController::GetGlobalController();
  auto* view = vtkPVRenderView::SafeDownCast(inInfo->Get(vtkPVView::VIEW()));
  auto* delivery = vtkPVRenderViewDataDeliveryManager::SafeDownCast(view->GetDeliveryManager());
  const vtkMTimeType pieceTime = piece ? piece->GetMTime() : 0;
  // Every rank must know the largest reach, and redistribute when any rank's piece changed.
  const double local[2] = { std::max(0.0, this->Mapper->ComputeReach(piece)),
    delivery->GetCutsMTime() != this->RegionCutsTime || pieceTime != this->RegionPieceTime ||
        !this->RegionPiece
      ? 1.0
      : 0.0 };
  double global[2] = { 0.0, 0.0 };
  controller->AllReduce(local, global, 2, vtkCommunicator::MAX_OP);
  if (global[1] > 0.0 || global[0] != this->RegionReach)
  {
    // A primitive reaching into a region has its cell within `reach` of it: pad every region
    // by the largest reach and send each cell to every padded region it meets.
    std::vector<vtkBoundingBox> padded = OpenRegions(delivery->GetCuts());
    for (vtkBoundingBox& box : padded)
    {
      if (box.IsValid())
      {
        box.Inflate(global[0]);
      }
    }
    vtkNew<vtkAppendFilter> received;
    SendToRegions(controller, this->RegionCells(piece), padded, received);
    this->RegionPiece = AppendedCells(received);
    this->RegionCutsTime = delivery->GetCutsMTime();
    this->RegionPieceTime = pieceTime;
    this->RegionReach = global[0];
  }
  this->DrawingRegionCells(true);
  this->Mapper->SetRegion(const_cast<double*>(region));
  this->Mapper->SetInputDataObject(this->RegionPiece);
}

bool vtkSightlineRepresentation::GetOrderedCompositingRegion(vtkInformation* inInfo, double region[6])
{
  auto* view = vtkPVRenderView::SafeDownCast(inInfo->Get(vtkPVView::VIEW()));
  auto* controller = vtkMultiProcessController::GetGlobalController();
  if (!view || !controller || controller->GetNumberOfProcesses() < 2 ||
    !view->GetUseOrderedCompositing())
  {
    return false;
  }
  auto* delivery = vtkPVRenderViewDataDeliveryManager::SafeDownCast(view->GetDeliveryManager());
  if (!delivery)
  {
    return false;
  }
  // One box per rank (ParaView 5.11 and 5.13 merge the kd-tree's leaves down to the rank count).
  const std::vector<vtkBoundingBox>& cuts = delivery->GetCuts();
  const int rank = controller->GetLocalProcessId();
  if (static_cast<int>(cuts.size()) != controller->GetNumberOfProcesses())
  {
    return false;
  }
  const vtkBoundingBox own = OpenRegions(cuts)[rank];
  if (!own.IsValid())
  {
    // No box for this rank (regions from bounds, this rank without data): it is sent nothing,
    // and still takes part in the collective steps, so the decision stays the same everywhere.
    const double inf = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 6; ++i)
    {
      region[i] = i % 2 ? inf : -inf;
    }
    return true;
  }
  own.GetBounds(region);
  return true;
}

bool vtkSightlineRepresentation::AddToView(vtkView* view)
{
  auto* renderView = vtkPVRenderView::SafeDownCast(view);
  if (!renderView)
  {
    return false;
  }
  renderView->GetRenderer()->AddActor(this->Actor);
  renderView->RegisterPropForHardwareSelection(this, this->Actor);
  return this->Superclass::AddToView(view);
}

bool vtkSightlineRepresentation::RemoveFromView(vtkView* view)
{
  auto* renderView = vtkPVRenderView::SafeDownCast(view);
  if (!renderView)
  {
    return false;
  }
  renderView->GetRenderer()->RemoveActor(this->Actor);
  renderView->UnRegisterPropForHardwareSelection(this, this->Actor);
  return this->Superclass::RemoveFromView(view);
}

void vtkSightlineRepresentation::SetVisibility(bool visible)
{
  this->Superclass::SetVisibility(visible);
  if (!visible)
  {
    this->Actor->SetVisibility(0);
  }
}

void vtkSightlineRepresentation::SetInputArrayToProcess(
  int idx, int port, int connection, int fieldAssociation, const char* name)
{
  this->Superclass::SetInputArrayToProcess(idx, port, connection, fieldAssociation, name);
  if (idx != 0)
  {
    return;
  }
  const bool on = name && name[0];
  if (on)
  {
    this->Mapper->SelectColorArray(name);
    this->Mapper->SetScalarMode(fieldAssociation == vtkDataObject::FIELD_ASSOCIATION_CELLS
        ? VTK_SCALAR_MODE_USE_CELL_FIELD_DATA
        : VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);
  }
  this->SetScalarColoring(on);
}

const char* vtkSightlineRepresentation::SelectedArrayName(const char* name)
{
  return name && name[0] && std::strcmp(name, "None") != 0 ? name : nullptr;
}

void vtkSightlineRepresentation::SetScalarColoring(bool on)
{
  this->Mapper->SetScalarVisibility(on ? 1 : 0);
}

void vtkSightlineRepresentation::SetLookupTable(vtkScalarsToColors* table)
{
  this->Mapper->SetLookupTable(table);
}

void vtkSightlineRepresentation::SetMapScalars(int mapScalars)
{
  this->Mapper->SetColorMode(mapScalars ? VTK_COLOR_MODE_MAP_SCALARS : VTK_COLOR_MODE_DIRECT_SCALARS);
}

void vtkSightlineRepresentation::SetInterpolateScalarsBeforeMapping(int interpolate)
{
  this->Mapper->SetInterpolateScalarsBeforeMapping(interpolate);
}

void vtkSightlineRepresentation::SetOpacity(double opacity)
{
  this->Property->SetOpacity(opacity);
}

void vtkSightlineRepresentation::SetColor(double r, double g, double b)
{
  this->Property->SetColor(r, g, b);
}

void vtkSightlineRepresentation::SetDiffuseColor(double r, double g, double b)
{
  this->Property->SetDiffuseColor(r, g, b);
}

void vtkSightlineRepresentation::SetAmbientColor(double r, double g, double b)
{
  this->Property->SetAmbientColor(r, g, b);
}

void vtkSightlineRepresentation::SetSpecularColor(double r, double g, double b)
{
  this->Property->SetSpecularColor(r, g, b);
}

void vtkSightlineRepresentation::SetAmbient(double value)
{
  this->Property->SetAmbient(value);
}

void vtkSightlineRepresentation::SetDiffuse(double value)
{
  this->Property->SetDiffuse(value);
}

void vtkSightlineRepresentation::SetSpecular(double value)
{
  this->Property->SetSpecular(value);
}

void vtkSightlineRepresentation::SetSpecularPower(double value)
{
  this->Property->SetSpecularPower(value);
}

void vtkSightlineRepresentation::SetInterpolation(int interpolation)
{
  this->Property->SetInterpolation(interpolation);
}

void vtkSightlineRepresentation::SetRoughness(double value)
{
  this->Property->SetRoughness(value);
}

void vtkSightlineRepresentation::SetPosition(double x, double y, double z)
{
  this->Actor->SetPosition(x, y, z);
}

void vtkSightlineRepresentation::SetScale(double x, double y, double z)
{
  this->Actor->SetScale(x, y, z);
}

void vtkSightlineRepresentation::SetOrientation(double x, double y, double z)
{
  this->Actor->SetOrientation(x, y, z);
}

void vtkSightlineRepresentation::SetOrigin(double x, double y, double z)
{
  this->Actor->SetOrigin(x, y, z);
}

void vtkSightlineRepresentation::SetUserTransform(const double matrix[16])
{
  vtkNew<vtkTransform> transform;
  transform->SetMatrix(matrix);
  this->Actor->SetUserTransform(transform);
}

void vtkSightlineRepresentation::SetPickable(int pickable)
{
  this->Actor->SetPickable(pickable);
}

void vtkSightlineRepresentation::SetShadowMode(int mode)
{
  this->Mapper->SetShadowMode(mode);
}

void vtkSightlineRepresentation::SetShadowSamples(int samples)
{
  this->Mapper->SetShadowSamples(samples);
}

void vtkSightlineRepresentation::SetLightAngularRadius(double degrees)
{
  this->Mapper->SetLightAngularRadius(degrees);
}

void vtkSightlineRepresentation::SetInteractiveSubsampling(int step)
{
  this->Mapper->SetInteractiveSubsampling(step);
}

void vtkSightlineRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mapper: " << this->Mapper->GetClassName() << "\n";
  os << indent << "Cache: " << (this->Cache ? this->Cache->GetClassName() : "(none)") << "\n";
  os << indent << "DataBounds: " << this->DataBounds[0] << " " << this->DataBounds[1] << " "
     << this->DataBounds[2] << " " << this->DataBounds[3] << " " << this->DataBounds[4] << " "
     << this->DataBounds[5] << "\n";
}
