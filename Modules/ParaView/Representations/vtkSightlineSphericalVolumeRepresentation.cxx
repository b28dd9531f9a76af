// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineSphericalVolumeRepresentation.h"

#include "vtkCellData.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPVLODVolume.h"
#include "vtkPointData.h"
#include "vtkPVRenderView.h"
#include "vtkRectilinearGrid.h"
#include "vtkRenderer.h"
#include "vtkSightlineSphericalVolumeMapper.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStructuredData.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

vtkStandardNewMacro(vtkSightlineSphericalVolumeRepresentation);

vtkSightlineSphericalVolumeRepresentation::vtkSightlineSphericalVolumeRepresentation()
  : Mapper(vtkSmartPointer<vtkSightlineSphericalVolumeMapper>::New())
{
  this->Actor->SetMapper(this->Mapper);
  this->Actor->SetProperty(this->Property);
  vtkMath::UninitializeBounds(this->RegionBox);
  this->Mapper->GetRegion(this->Region);
}

vtkSightlineSphericalVolumeRepresentation::~vtkSightlineSphericalVolumeRepresentation() = default;

vtkSightlineSphericalVolumeMapper* vtkSightlineSphericalVolumeRepresentation::GetSphericalVolumeMapper()
{
  return this->Mapper;
}

int vtkSightlineSphericalVolumeRepresentation::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkRectilinearGrid");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkSightlineSphericalVolumeRepresentation::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMath::UninitializeBounds(this->DataBounds);
  this->DataSize = 0;
  this->Cache = nullptr;
  std::fill(this->WholeExtent, this->WholeExtent + 6, 0);
  this->WholeExtent[1] = this->WholeExtent[3] = this->WholeExtent[5] = -1;
  if (inputVector[0]->GetNumberOfInformationObjects() == 1)
  {
    vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
    if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    {
      inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), this->WholeExtent);
    }
    if (vtkDataObject* input = vtkDataObject::GetData(inputVector[0], 0))
    {
      this->Cache.TakeReference(input->NewInstance());
      this->Cache->ShallowCopy(input);
      this->DataSize = this->Cache->GetActualMemorySize();
      vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
      if (!controller || controller->GetNumberOfProcesses() == 1)
      {
        // The mapper knows the world bounds of the grid's (r, theta, phi) cells. (On several
        // ranks the partition gives each rank its box instead.)
        this->Mapper->SetInputDataObject(this->Cache);
        const double* bounds = this->Mapper->GetBounds();
        if (vtkMath::AreBoundsInitialized(bounds))
        {
          std::copy(bounds, bounds + 6, this->DataBounds);
        }
      }
      else
      {
        // The region grid of the last partition is stale until the next one: without this, the
        // view's bounds pass would read it with the new data's scalar selection (a switch from
        // cell to point data reported "no scalars").
        this->Mapper->SetInputDataObject(nullptr);
      }
    }
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

namespace
{
// The grid to draw: the data itself, or a composite's first leaf with points.
vtkRectilinearGrid* FirstGrid(vtkDataObject* data)
{
  if (auto* grid = vtkRectilinearGrid::SafeDownCast(data))
  {
    return grid;
  }
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      auto* grid = vtkRectilinearGrid::SafeDownCast(it->GetCurrentDataObject());
      if (grid && grid->GetNumberOfPoints() > 0)
      {
        return grid;
      }
    }
  }
  return nullptr;
}

bool IsValidExtent(const int extent[6])
{
  return extent[0] <= extent[1] && extent[2] <= extent[3] && extent[4] <= extent[5];
}

// The point extent both hold, when it has at least one cell along every axis (a shared face
// alone brings no cell, and its points come with the cells on either side).
bool CellsInBoth(const int a[6], const int b[6], int both[6])
{
  for (int axis = 0; axis < 3; ++axis)
  {
    both[2 * axis] = std::max(a[2 * axis], b[2 * axis]);
    both[2 * axis + 1] = std::min(a[2 * axis + 1], b[2 * axis + 1]);
    if (both[2 * axis + 1] <= both[2 * axis])
    {
      return false;
    }
  }
  return true;
}

vtkIdType CellCount(const int extent[6])
{
  return vtkIdType(extent[1] - extent[0]) * (extent[3] - extent[2]) * (extent[5] - extent[4]);
}

// Cells a rank places in its region grid: the point extent there, and how many cells past the
// whole extent it lies (a full circle's run across the seam; 0 where the piece is).
struct SeamPart
{
  std::array<int, 6> Extent{};
  int Shift = 0;
};

// Point ids, and cell ids (of the cells starting at ijk), inside an extent.
vtkIdType PointIn(const int extent[6], int i, int j, int k)
{
  return (i - extent[0]) +
    vtkIdType(extent[1] - extent[0] + 1) * ((j - extent[2]) + vtkIdType(extent[3] - extent[2] + 1) * (k - extent[4]));
}
vtkIdType CellIn(const int extent[6], int i, int j, int k)
{
  return (i - extent[0]) +
    vtkIdType(extent[1] - extent[0]) * ((j - extent[2]) + vtkIdType(extent[3] - extent[2]) * (k - extent[4]));
}

// The part of `piece` (whose points span `pieceExtent`) over the point extent `extent`: its
// coordinates, point data and cell data, ids counted from the extent's corner.
vtkSmartPointer<vtkRectilinearGrid> SubGrid(vtkRectilinearGrid* piece, const int pieceExtent[6], const int extent[6])
{
  auto part = vtkSmartPointer<vtkRectilinearGrid>::New();
  part->SetExtent(const_cast<int*>(extent));
  vtkDataArray* coordinates[3] = { piece->GetXCoordinates(), piece->GetYCoordinates(), piece->GetZCoordinates() };
  for (int axis = 0; axis < 3; ++axis)
  {
    vtkSmartPointer<vtkDataArray> slice;
    slice.TakeReference(coordinates[axis]->NewInstance());
    slice->SetNumberOfTuples(extent[2 * axis + 1] - extent[2 * axis] + 1);
    for (int i = extent[2 * axis]; i <= extent[2 * axis + 1]; ++i)
    {
      slice->SetTuple(i - extent[2 * axis], i - pieceExtent[2 * axis], coordinates[axis]);
    }
    axis == 0 ? part->SetXCoordinates(slice) : axis == 1 ? part->SetYCoordinates(slice) : part->SetZCoordinates(slice);
  }
  part->GetPointData()->CopyAllocate(piece->GetPointData(), part->GetNumberOfPoints());
  part->GetCellData()->CopyAllocate(piece->GetCellData(), part->GetNumberOfCells());
  for (int k = extent[4]; k <= extent[5]; ++k)
    for (int j = extent[2]; j <= extent[3]; ++j)
      for (int i = extent[0]; i <= extent[1]; ++i)
      {
        part->GetPointData()->CopyData(piece->GetPointData(), PointIn(pieceExtent, i, j, k), PointIn(extent, i, j, k));
        if (i < extent[1] && j < extent[3] && k < extent[5])
        {
          part->GetCellData()->CopyData(piece->GetCellData(), CellIn(pieceExtent, i, j, k), CellIn(extent, i, j, k));
        }
      }
  return part;
}

// Writes the arrays of `part` (the points of `extent`) into `into` (whose points span
// `intoExtent`), adding the arrays it lacks (NaN until written).
void Place(vtkDataSetAttributes* from, vtkDataSetAttributes* into, vtkIdType size,
  const std::function<void(const std::function<void(vtkIdType, vtkIdType)>&)>& forEach)
{
  for (int a = 0; a < from->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* source = from->GetArray(a);
    if (!source || !source->GetName())
    {
      continue;
    }
    vtkDataArray* target = into->GetArray(source->GetName());
    if (!target || target->GetNumberOfComponents() != source->GetNumberOfComponents())
    {
      vtkSmartPointer<vtkDataArray> added;
      added.TakeReference(source->NewInstance());
      added->SetName(source->GetName());
      added->SetNumberOfComponents(source->GetNumberOfComponents());
      added->SetNumberOfTuples(size);
      added->Fill(added->GetDataType() == VTK_FLOAT || added->GetDataType() == VTK_DOUBLE
          ? std::numeric_limits<double>::quiet_NaN()
          : 0.0);
      into->AddArray(added);
      target = added;
    }
    if (from->GetScalars() == source)
    {
      into->SetActiveScalars(source->GetName());
    }
    forEach([&](vtkIdType fromId, vtkIdType intoId) { target->SetTuple(intoId, fromId, source); });
  }
}

void PlacePart(vtkRectilinearGrid* part, const int extent[6], vtkRectilinearGrid* into, const int intoExtent[6])
{
  Place(part->GetPointData(), into->GetPointData(), into->GetNumberOfPoints(),
    [&](const std::function<void(vtkIdType, vtkIdType)>& copy)
    {
      for (int k = extent[4]; k <= extent[5]; ++k)
        for (int j = extent[2]; j <= extent[3]; ++j)
          for (int i = extent[0]; i <= extent[1]; ++i)
            copy(PointIn(extent, i, j, k), PointIn(intoExtent, i, j, k));
    });
  Place(part->GetCellData(), into->GetCellData(), into->GetNumberOfCells(),
    [&](const std::function<void(vtkIdType, vtkIdType)>& copy)
    {
      for (int k = extent[4]; k < extent[5]; ++k)
        for (int j = extent[2]; j < extent[3]; ++j)
          for (int i = extent[0]; i < extent[1]; ++i)
            copy(CellIn(extent, i, j, k), CellIn(intoExtent, i, j, k));
    });
}

// Splits `box` into `count` boxes from boxes[first] on: recursive halving along the longest
// side, in proportion to the ranks on each side (a kd-tree, as ParaView's own cuts are).
void SplitBox(const std::array<double, 6>& box, int first, int count, std::vector<std::array<double, 6>>& boxes)
{
  if (count == 1)
  {
    boxes[first] = box;
    return;
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
  {
    if (box[2 * a + 1] - box[2 * a] > box[2 * axis + 1] - box[2 * axis])
    {
      axis = a;
    }
  }
  const int lower = count / 2;
  const double cut = box[2 * axis] + (box[2 * axis + 1] - box[2 * axis]) * lower / count;
  std::array<double, 6> below = box, above = box;
  below[2 * axis + 1] = cut;
  above[2 * axis] = cut;
  SplitBox(below, first, lower, boxes);
  SplitBox(above, first + lower, count - lower, boxes);
}

// The box around `box`'s corners moved by `matrix`.
std::array<double, 6> MovedBox(vtkMatrix4x4* matrix, const std::array<double, 6>& box)
{
  const double inf = std::numeric_limits<double>::infinity();
  std::array<double, 6> moved{ inf, -inf, inf, -inf, inf, -inf };
  for (int corner = 0; corner < 8; ++corner)
  {
    double p[4] = { box[corner & 1 ? 1 : 0], box[corner & 2 ? 3 : 2], box[corner & 4 ? 5 : 4], 1.0 };
    matrix->MultiplyPoint(p, p);
    for (int axis = 0; axis < 3; ++axis)
    {
      moved[2 * axis] = std::min(moved[2 * axis], p[axis] / p[3]);
      moved[2 * axis + 1] = std::max(moved[2 * axis + 1], p[axis] / p[3]);
    }
  }
  return moved;
}
} // namespace

bool vtkSightlineSphericalVolumeRepresentation::Partition()
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int ranks = controller->GetNumberOfProcesses();
  const int rank = controller->GetLocalProcessId();
  vtkRectilinearGrid* piece = FirstGrid(this->Cache);
  if (piece && piece->GetNumberOfPoints() == 0)
  {
    piece = nullptr;
  }

  // Redo the partition when any rank's piece, the coordinate settings or the matrix changed.
  std::vector<double> key{ double(piece ? piece->GetMTime() : 0), double(this->Mapper->GetCoordinateSystem()),
    double(this->Mapper->GetAngleUnits()), double(this->Mapper->GetPolarAngle()), this->SampleDistance,
    double(this->Property->GetShade(0)) };
  vtkMatrix4x4* matrix = this->Actor->GetMatrix();
  key.insert(key.end(), &matrix->GetData()[0], &matrix->GetData()[0] + 16);
  const int localStale = key != this->PartitionKey ? 1 : 0;
  int stale = 0;
  controller->AllReduce(&localStale, &stale, 1, vtkCommunicator::MAX_OP);
  if (!stale)
  {
    return this->Partitioned;
  }
  this->PartitionKey = key;
  this->Partitioned = false;
  this->RegionGrid = nullptr;
  vtkMath::UninitializeBounds(this->RegionBox);

  // Every rank's piece extent, and the whole extent (the same everywhere, but a rank without
  // pipeline information may lack it).
  int local[12] = { 0, -1, 0, -1, 0, -1 };
  if (piece)
  {
    piece->GetExtent(local);
  }
  std::copy(this->WholeExtent, this->WholeExtent + 6, local + 6);
  std::vector<int> all(12 * std::size_t(ranks));
  controller->AllGather(local, all.data(), 12);
  int whole[6] = { 0, -1, 0, -1, 0, -1 };
  for (int r = 0; r < ranks && !IsValidExtent(whole); ++r)
  {
    std::copy(&all[12 * r + 6], &all[12 * r + 12], whole);
  }
  if (!IsValidExtent(whole))
  {
    return false; // no grid anywhere: nothing to draw
  }

  // The whole grid's breakpoints, each from a rank whose piece holds it.
  const int counts[3] = { whole[1] - whole[0] + 1, whole[3] - whole[2] + 1, whole[5] - whole[4] + 1 };
  std::vector<double> mine(std::size_t(counts[0] + counts[1] + counts[2]), -std::numeric_limits<double>::infinity());
  if (piece)
  {
    vtkDataArray* coordinates[3] = { piece->GetXCoordinates(), piece->GetYCoordinates(), piece->GetZCoordinates() };
    for (int axis = 0, offset = 0; axis < 3; offset += counts[axis], ++axis)
    {
      for (int i = std::max(local[2 * axis], whole[2 * axis]); i <= std::min(local[2 * axis + 1], whole[2 * axis + 1]); ++i)
      {
        mine[std::size_t(offset + i - whole[2 * axis])] = coordinates[axis]->GetComponent(i - local[2 * axis], 0);
      }
    }
  }
  std::vector<double> breakpoints(mine.size());
  controller->AllReduce(mine.data(), breakpoints.data(), vtkIdType(mine.size()), vtkCommunicator::MAX_OP);
  for (double b : breakpoints)
  {
    if (!std::isfinite(b))
    {
      if (rank == 0)
      {
        vtkErrorMacro(<< "The ranks' pieces do not give every coordinate of the grid's whole extent ["
                      << whole[0] << ", " << whole[1] << "] x [" << whole[2] << ", " << whole[3] << "] x ["
                      << whole[4] << ", " << whole[5] << "] (or one is NaN): the volume is not drawn.");
      }
      return false;
    }
  }
  vtkNew<vtkRectilinearGrid> wholeGrid;
  wholeGrid->SetExtent(whole);
  for (int axis = 0, offset = 0; axis < 3; offset += counts[axis], ++axis)
  {
    vtkNew<vtkDoubleArray> axisBreakpoints;
    axisBreakpoints->SetNumberOfTuples(counts[axis]);
    std::copy(breakpoints.begin() + offset, breakpoints.begin() + offset + counts[axis], axisBreakpoints->GetPointer(0));
    axis == 0 ? wholeGrid->SetXCoordinates(axisBreakpoints)
              : axis == 1 ? wholeGrid->SetYCoordinates(axisBreakpoints) : wholeGrid->SetZCoordinates(axisBreakpoints);
  }

  // One box per rank, cut from the section's world box the same way on every rank.
  std::array<double, 6> section;
  if (!this->Mapper->ComputeSectionBounds(wholeGrid, section.data()))
  {
    return false; // the mapper said why, on every rank
  }
  const std::array<double, 6> world = MovedBox(matrix, section);
  std::vector<std::array<double, 6>> boxes(static_cast<std::size_t>(ranks));
  SplitBox(world, 0, ranks, boxes);
  vtkNew<vtkMatrix4x4> worldToGrid;
  vtkMatrix4x4::Invert(matrix, worldToGrid);
  // Each rank's cells: those that may meet its box, one wider when shading reads the gradients.
  // A run of azimuth cells across a full circle's seam goes on past the whole extent: index
  // i > whole's last stands for i - n (n cells around), one turn on.
  const int margin = this->Property->GetShade(0) ? 1 : 0;
  std::vector<std::array<int, 6>> needed(static_cast<std::size_t>(ranks));
  int turnAxis = -1; // the axis whose runs cross the seam
  for (int r = 0; r < ranks; ++r)
  {
    int range[6];
    needed[r] = { 0, -1, 0, -1, 0, -1 };
    if (this->Mapper->ComputeCellRangeInBox(wholeGrid, MovedBox(worldToGrid, boxes[r]).data(), range, margin))
    {
      for (int axis = 0; axis < 3; ++axis)
      {
        const bool acrossSeam = range[2 * axis] > range[2 * axis + 1];
        turnAxis = acrossSeam ? axis : turnAxis;
        needed[r][2 * axis] = whole[2 * axis] + range[2 * axis];
        needed[r][2 * axis + 1] = whole[2 * axis] + range[2 * axis + 1] + 1 +
          (acrossSeam ? whole[2 * axis + 1] - whole[2 * axis] : 0);
      }
    }
  }
  const int around = turnAxis < 0 ? 0 : whole[2 * turnAxis + 1] - whole[2 * turnAxis];
  const double turn = this->Mapper->GetAngleUnits() == vtkSightlineSphericalVolumeMapper::DEGREES ? 360.0 : 2.0 * vtkMath::Pi();

  // Rank p sends rank q the cells of p's piece that q needs, as parts: the piece where it is,
  // and once more a turn on for a run across the seam. A rank whose own piece holds all it
  // needs takes nothing from the others.
  const auto partsOf = [&](int p, int q)
  {
    std::vector<SeamPart> parts;
    const int* pieceOfP = &all[12 * p];
    if (!IsValidExtent(needed[q].data()) || !IsValidExtent(pieceOfP))
    {
      return parts;
    }
    for (const int shift : { 0, around })
    {
      SeamPart part;
      part.Shift = shift;
      int moved[6];
      std::copy(pieceOfP, pieceOfP + 6, moved);
      if (shift > 0)
      {
        moved[2 * turnAxis] += shift;
        moved[2 * turnAxis + 1] += shift;
      }
      if (CellsInBoth(moved, needed[q].data(), part.Extent.data()))
      {
        parts.push_back(part);
      }
      if (around == 0)
      {
        break;
      }
    }
    return parts;
  };
  const auto selfSufficient = [&](int q)
  {
    vtkIdType own = 0;
    for (const SeamPart& part : partsOf(q, q))
    {
      own += CellCount(part.Extent.data());
    }
    return own == CellCount(needed[q].data());
  };
  const auto sends = [&](int p, int q)
  {
    return p != q && selfSufficient(q) ? std::vector<SeamPart>() : partsOf(p, q);
  };
  // The part of the piece (whose points span pieceExtent) that goes to `part.Extent`.
  const auto cut = [&](const SeamPart& part)
  {
    std::array<int, 6> inPiece = part.Extent;
    if (part.Shift > 0)
    {
      inPiece[2 * turnAxis] -= part.Shift;
      inPiece[2 * turnAxis + 1] -= part.Shift;
    }
    return SubGrid(piece, local, inPiece.data());
  };
  auto region = vtkSmartPointer<vtkRectilinearGrid>::New();
  const int* mineNeeded = needed[rank].data();
  if (IsValidExtent(mineNeeded))
  {
    region->SetExtent(const_cast<int*>(mineNeeded));
    for (int axis = 0, offset = 0; axis < 3; offset += counts[axis], ++axis)
    {
      vtkNew<vtkDoubleArray> slice;
      slice->SetNumberOfTuples(mineNeeded[2 * axis + 1] - mineNeeded[2 * axis] + 1);
      for (int i = mineNeeded[2 * axis]; i <= mineNeeded[2 * axis + 1]; ++i)
      {
        const bool turned = i > whole[2 * axis + 1];
        slice->SetValue(i - mineNeeded[2 * axis],
          breakpoints[std::size_t(offset + i - (turned ? around : 0) - whole[2 * axis])] + (turned ? turn : 0.0));
      }
      axis == 0 ? region->SetXCoordinates(slice) : axis == 1 ? region->SetYCoordinates(slice) : region->SetZCoordinates(slice);
    }
  }
  if (piece)
  {
    for (const SeamPart& part : sends(rank, rank))
    {
      PlacePart(cut(part), part.Extent.data(), region, mineNeeded);
    }
  }
  // Pairs in one global order, the lower rank sending first: no rank waits on one that waits.
  constexpr int tag = 872301;
  for (int a = 0; a < ranks; ++a)
  {
    for (int b = a + 1; b < ranks; ++b)
    {
      if (rank != a && rank != b)
      {
        continue;
      }
      const int other = rank == a ? b : a;
      for (const bool fromA : { true, false })
      {
        const int from = fromA ? a : b, to = fromA ? b : a;
        for (const SeamPart& part : sends(from, to))
        {
          if (rank == from)
          {
            vtkSmartPointer<vtkRectilinearGrid> sent = cut(part);
            controller->Send(sent, other, tag);
          }
          else
          {
            vtkSmartPointer<vtkDataObject> received;
            received.TakeReference(controller->ReceiveDataObject(other, tag));
            if (auto* grid = vtkRectilinearGrid::SafeDownCast(received))
            {
              PlacePart(grid, part.Extent.data(), region, mineNeeded);
            }
          }
        }
      }
    }
  }

  this->RegionGrid = region;
  std::copy(boxes[rank].begin(), boxes[rank].end(), this->RegionBox);
  for (int i = 0; i < 6; ++i)
  {
    // Faces on the partition's outside reach to infinity: the boxes then tile all of space.
    this->Region[i] = this->RegionBox[i] == world[i]
      ? (i % 2 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity())
      : this->RegionBox[i];
  }
  // Samples of point data as the whole grid's automatic distance puts them on every rank.
  double thinnest = breakpoints[std::size_t(counts[0] - 1)] - breakpoints[0];
  for (int i = 0; i + 1 < counts[0]; ++i)
  {
    thinnest = std::min(thinnest, breakpoints[std::size_t(i) + 1] - breakpoints[std::size_t(i)]);
  }
  this->Mapper->SetSampleDistance(this->SampleDistance > 0.0 ? this->SampleDistance : 0.5 * thinnest);
  this->Partitioned = true;
  return true;
}

int vtkSightlineSphericalVolumeRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request, inInfo, outInfo))
  {
    return 0;
  }
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const bool severalRanks = controller && controller->GetNumberOfProcesses() > 1;
  if (request == vtkPVView::REQUEST_UPDATE())
  {
    vtkPVView::SetPiece(inInfo, this, this->Cache);
    // Every rank updates the view together: the partition's collective steps run here.
    if (severalRanks && this->Partition())
    {
      // The view's ordered-compositing regions are these boxes (ParaView 5.11 reads them from
      // the geometry bounds), blended front to back by IceT.
      std::copy(this->RegionBox, this->RegionBox + 6, this->DataBounds);
      vtkPVRenderView::SetOrderedCompositingConfiguration(
        inInfo, this, vtkPVRenderView::USE_BOUNDS_FOR_REDISTRIBUTION);
      outInfo->Set(vtkPVRenderView::NEED_ORDERED_COMPOSITING(), 1);
    }
    vtkPVRenderView::SetGeometryBounds(inInfo, this, this->DataBounds);
    // Traced where the grid is (see REQUEST_RENDER): a pvserver's client, which has no grid,
    // must not render locally, so the view renders on the server whatever the data size.
    vtkPVRenderView::SetRequiresDistributedRendering(inInfo, this, true);
  }
  else if (request == vtkPVView::REQUEST_RENDER())
  {
    // The grid is traced where it was produced (builtin, pvbatch and pvserver ranks are data
    // and render server at once): ParaView 5.11's delivery turned each coordinate array of a
    // vtkRectilinearGrid into one value per point (36750 radii for a 30 x 25 x 49 grid).
    if (severalRanks)
    {
      this->Mapper->SetInputDataObject(this->Partitioned ? this->RegionGrid : nullptr);
      this->Mapper->SetRegion(this->Region);
    }
    else
    {
      this->Mapper->SetSampleDistance(this->SampleDistance);
      this->Mapper->SetRegionToAllOfSpace();
      this->Mapper->SetInputDataObject(this->Cache);
    }
  }
  return 1;
}

bool vtkSightlineSphericalVolumeRepresentation::AddToView(vtkView* view)
{
  auto* renderView = vtkPVRenderView::SafeDownCast(view);
  if (!renderView)
  {
    return false;
  }
  renderView->GetRenderer()->AddVolume(this->Actor);
  return this->Superclass::AddToView(view);
}

bool vtkSightlineSphericalVolumeRepresentation::RemoveFromView(vtkView* view)
{
  auto* renderView = vtkPVRenderView::SafeDownCast(view);
  if (!renderView)
  {
    return false;
  }
  renderView->GetRenderer()->RemoveVolume(this->Actor);
  return this->Superclass::RemoveFromView(view);
}

void vtkSightlineSphericalVolumeRepresentation::SetInputArrayToProcess(
  int idx, int port, int connection, int fieldAssociation, const char* name)
{
  this->Superclass::SetInputArrayToProcess(idx, port, connection, fieldAssociation, name);
  if (idx != 0)
  {
    return;
  }
  if (name && name[0])
  {
    this->Mapper->SelectScalarArray(name);
    this->Mapper->SetScalarMode(fieldAssociation == vtkDataObject::FIELD_ASSOCIATION_CELLS
        ? VTK_SCALAR_MODE_USE_CELL_FIELD_DATA
        : VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);
  }
  else
  {
    this->Mapper->SetScalarMode(VTK_SCALAR_MODE_DEFAULT);
  }
}

void vtkSightlineSphericalVolumeRepresentation::SetShade(bool shade)
{
  this->Property->SetShade(shade);
  this->MarkModified(); // on several ranks shading needs each cell's neighbours
}

void vtkSightlineSphericalVolumeRepresentation::SetCoordinateSystem(int system)
{
  this->Mapper->SetCoordinateSystem(system);
  this->MarkModified(); // on several ranks the partition reads the coordinates anew
}

void vtkSightlineSphericalVolumeRepresentation::SetAngleUnits(int units)
{
  this->Mapper->SetAngleUnits(units);
  this->MarkModified(); // on several ranks the partition reads the coordinates anew
}

void vtkSightlineSphericalVolumeRepresentation::SetPolarAngle(int angle)
{
  this->Mapper->SetPolarAngle(angle);
  this->MarkModified(); // on several ranks the partition reads the coordinates anew
}

void vtkSightlineSphericalVolumeRepresentation::SetInterpolatePointData(int interpolate)
{
  this->Mapper->SetInterpolatePointData(interpolate);
}

void vtkSightlineSphericalVolumeRepresentation::SetSampleDistance(double distance)
{
  // On several ranks 0 means the whole grid's automatic distance (see Partition).
  this->SampleDistance = distance;
  this->Mapper->SetSampleDistance(distance);
  this->MarkModified();
}

void vtkSightlineSphericalVolumeRepresentation::SetMinimumTransmittance(double transmittance)
{
  this->Mapper->SetMinimumTransmittance(transmittance);
}

void vtkSightlineSphericalVolumeRepresentation::SetInteractiveSubsampling(int step)
{
  this->Mapper->SetInteractiveSubsampling(step);
}

void vtkSightlineSphericalVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Cache: " << (this->Cache ? this->Cache->GetClassName() : "(none)") << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "Partitioned: " << this->Partitioned << "\n";
  if (this->Partitioned)
  {
    os << indent << "RegionBox: " << this->RegionBox[0] << " " << this->RegionBox[1] << " "
       << this->RegionBox[2] << " " << this->RegionBox[3] << " " << this->RegionBox[4] << " "
       << this->RegionBox[5] << "\n";
    os << indent << "RegionGrid cells: "
       << (this->RegionGrid ? vtkDataSet::SafeDownCast(this->RegionGrid)->GetNumberOfCells() : 0) << "\n";
  }
}
