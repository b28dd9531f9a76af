// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineTubeRepresentation.h"

#include "vtkAppendFilter.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkProperty.h"
#include "vtkSightlineMapper.h"
#include "vtkSightlineTubeMapper.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"

#include <cmath>

vtkStandardNewMacro(vtkSightlineTubeRepresentation);

vtkSightlineTubeRepresentation::vtkSightlineTubeRepresentation()
  : vtkSightlineRepresentation(vtkSmartPointer<vtkSightlineTubeMapper>::New())
{
  this->UpdateVaryRadius();
}

vtkSightlineTubeRepresentation::~vtkSightlineTubeRepresentation() = default;

vtkSightlineTubeMapper* vtkSightlineTubeRepresentation::GetTubeMapper()
{
  return static_cast<vtkSightlineTubeMapper*>(this->Mapper.GetPointer());
}

void vtkSightlineTubeRepresentation::SetRadius(double radius)
{
  this->GetTubeMapper()->SetRadius(radius);
}

void vtkSightlineTubeRepresentation::SetRadiusArray(int, int, int, int, const char* name)
{
  const char* selected = SelectedArrayName(name);
  this->HasRadiusArray = selected != nullptr;
  this->GetTubeMapper()->SetRadiusArrayName(selected);
  this->UpdateVaryRadius();
}

void vtkSightlineTubeRepresentation::SetVaryRadius(int mode)
{
  this->VaryRadius = mode;
  this->UpdateVaryRadius();
}

void vtkSightlineTubeRepresentation::UpdateVaryRadius()
{
  // The mapper varies the radius by the active scalars when no array is named and VaryRadius is
  // not off; in ParaView "no radius array" means a constant radius.
  this->GetTubeMapper()->SetVaryRadius(
    this->HasRadiusArray ? this->VaryRadius : vtkSightlineTubeMapper::VARY_RADIUS_OFF);
  auto* controller = vtkMultiProcessController::GetGlobalController();
  if (this->HasRadiusArray && this->VaryRadius == vtkSightlineTubeMapper::VARY_RADIUS_BY_SCALAR &&
    controller && controller->GetNumberOfProcesses() > 1)
  {
    vtkWarningMacro(<< "Vary Radius 'by scalar' maps each rank's own scalar range to radii, so on "
                    << controller->GetNumberOfProcesses()
                    << " ranks the tubes differ from one process; 'by absolute scalar' does not.");
  }
}

void vtkSightlineTubeRepresentation::SetRadiusScale(double scale)
{
  this->GetTubeMapper()->SetRadiusScale(scale);
}

void vtkSightlineTubeRepresentation::SetRadiusFactor(double factor)
{
  this->GetTubeMapper()->SetRadiusFactor(factor);
}

void vtkSightlineTubeRepresentation::SetPredecessorArray(int, int, int, int, const char* name)
{
  const char* selected = SelectedArrayName(name);
  this->PredecessorArray = selected ? selected : "";
  this->GetTubeMapper()->SetPredecessorArrayName(selected);
}

bool vtkSightlineTubeRepresentation::NeedsOrderedCompositing()
{
  // The translucent union is exact only if the ranks' layers are blended in depth order.
  return this->Property->GetOpacity() < 1.0;
}

vtkSmartPointer<vtkUnstructuredGrid> vtkSightlineTubeRepresentation::RegionCells(vtkDataObject* piece)
{
  vtkNew<vtkAppendFilter> append;
  for (vtkPointSet* leaf : vtkSightlineMapper::PointSets(piece))
  {
    const vtkIdType count = leaf->GetNumberOfPoints();
    if (count == 0)
    {
      continue;
    }
    vtkDataArray* predecessors = this->PredecessorArray.empty()
      ? nullptr
      : leaf->GetPointData()->GetArray(this->PredecessorArray.c_str());
    // Each link becomes a line of its two points, so that a region receives the links that
    // reach into it, not whole streamlines. Predecessor ids name points of this leaf; bad ones
    // are left out here (the mapper's own path reports them).
    const bool usePredecessors = predecessors && predecessors->GetNumberOfComponents() == 1 &&
      predecessors->GetNumberOfTuples() == count;
    auto links = CellsOnPoints(leaf);
    if (usePredecessors)
    {
      links->Allocate(count);
      for (vtkIdType i = 0; i < count; ++i)
      {
        const double value = predecessors->GetComponent(i, 0);
        if (value >= 0.0 && value < static_cast<double>(count) && value == std::floor(value))
        {
          const vtkIdType ends[2] = { static_cast<vtkIdType>(value), i };
          links->InsertNextCell(VTK_LINE, 2, ends);
        }
      }
    }
    else
    {
      // The polylines' consecutive points (poly-line and line cells of any point set).
      vtkNew<vtkIdList> ids;
      for (vtkIdType cell = 0; cell < leaf->GetNumberOfCells(); ++cell)
      {
        const int type = leaf->GetCellType(cell);
        if (type != VTK_LINE && type != VTK_POLY_LINE)
        {
          continue;
        }
        leaf->GetCellPoints(cell, ids);
        for (vtkIdType k = 1; k < ids->GetNumberOfIds(); ++k)
        {
          const vtkIdType ends[2] = { ids->GetId(k - 1), ids->GetId(k) };
          links->InsertNextCell(VTK_LINE, 2, ends);
        }
      }
    }
    append->AddInputData(links);
  }
  return AppendedCells(append);
}

void vtkSightlineTubeRepresentation::DrawingRegionCells(bool on)
{
  // A region's cells are lines: predecessor ids of the piece mean nothing there.
  this->GetTubeMapper()->SetPredecessorArrayName(
    on || this->PredecessorArray.empty() ? nullptr : this->PredecessorArray.c_str());
}

void vtkSightlineTubeRepresentation::SetLinkLayout(int layout)
{
  this->GetTubeMapper()->SetLinkLayout(layout);
}

void vtkSightlineTubeRepresentation::SetChunkLinks(int links)
{
  this->GetTubeMapper()->SetChunkLinks(links);
}

void vtkSightlineTubeRepresentation::SetHiddenLinkCulling(int on)
{
  this->GetTubeMapper()->SetHiddenLinkCulling(on);
}

void vtkSightlineTubeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "VaryRadius: " << this->VaryRadius << "\n";
  os << indent << "HasRadiusArray: " << this->HasRadiusArray << "\n";
  os << indent << "PredecessorArray: " << (this->PredecessorArray.empty() ? "(none)" : this->PredecessorArray) << "\n";
}
