// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineSphereMapper.h"

#include "SightlineMapperInput.h"

#include "SightlineKernelConversions.h"

#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"

#include "sightline/spheres/SphereSet.h"

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkSightlineSphereMapper);

//------------------------------------------------------------------------------
vtkSightlineSphereMapper::vtkSightlineSphereMapper() = default;

//------------------------------------------------------------------------------
vtkSightlineSphereMapper::~vtkSightlineSphereMapper()
{
  this->SetRadiusArrayName(nullptr);
}

//------------------------------------------------------------------------------
std::shared_ptr<sightline::Geometry> vtkSightlineSphereMapper::BuildGeometry()
{
  // Called only with points to draw (an empty input draws nothing, quietly).
  vtkPointSet* input = vtkPointSet::SafeDownCast(this->GetDrawnInput());
  const vtkIdType count = input && input->GetPoints() ? input->GetNumberOfPoints() : 0;
  if (count == 0)
  {
    return nullptr;
  }

  std::vector<sightline::dvec3> world(count);
  vtkPoints* points = input->GetPoints();
  for (vtkIdType i = 0; i < count; ++i)
  {
    points->GetPoint(i, &world[i].x);
  }
  std::vector<sightline::vec3> centers;
  const sightline::dvec3 origin = SightlineKernelConversions::ToLocalFrame(world, centers);

  std::vector<float> radii;
  if (this->RadiusArrayName && *this->RadiusArrayName)
  {
    vtkDataArray* array = input->GetPointData()->GetArray(this->RadiusArrayName);
    if (!array)
    {
      vtkErrorMacro(<< "The radius array '" << this->RadiusArrayName
                    << "' is not in the input's point data; using the constant radius "
                    << this->Radius << ".");
    }
    else if (array->GetNumberOfComponents() != 1)
    {
      vtkErrorMacro(<< "The radius array '" << this->RadiusArrayName << "' has "
                    << array->GetNumberOfComponents()
                    << " components; one radius per point is needed. Using the constant radius "
                    << this->Radius << ".");
    }
    else if (array->GetNumberOfTuples() != count)
    {
      vtkErrorMacro(<< "The radius array '" << this->RadiusArrayName << "' has "
                    << array->GetNumberOfTuples() << " values for " << count
                    << " points. Using the constant radius " << this->Radius << ".");
    }
    else
    {
      radii.resize(count);
      for (vtkIdType i = 0; i < count; ++i)
      {
        radii[i] = static_cast<float>(array->GetComponent(i, 0) * this->RadiusScale);
      }
    }
  }
  if (radii.empty() && !(std::isfinite(this->Radius) && this->Radius > 0.0))
  {
    vtkErrorMacro(<< "Radius must be positive and finite, got " << this->Radius
                  << "; no spheres rendered.");
    return nullptr;
  }

  bool cellScalars = false;
  const std::vector<std::uint32_t> colors =
    SightlineKernelConversions::PointColors(this, input, &cellScalars);
  if (cellScalars)
  {
    vtkWarningMacro(<< "Cell scalars cannot colour spheres (one per point); using the "
                       "actor's colour.");
  }

  auto spheres = std::make_shared<sightline::SphereSet>(
    origin, centers, radii, static_cast<float>(this->Radius), colors);
  SightlineKernelConversions::WarnAboutReport(this, spheres->report());
  return spheres;
}

//------------------------------------------------------------------------------
void vtkSightlineSphereMapper::ComputeSelectionIds(
  std::vector<vtkIdType>& pointIds, std::vector<vtkIdType>& cellIds)
{
  auto* spheres = dynamic_cast<sightline::SphereSet*>(this->GetGeometry());
  vtkPointSet* input = vtkPointSet::SafeDownCast(this->GetDrawnInput());
  if (!spheres || !input)
  {
    return;
  }
  const std::vector<std::uint32_t>& source = spheres->sourceIndex();
  for (std::size_t i = 0; i < pointIds.size() && i < source.size(); ++i)
  {
    pointIds[i] = static_cast<vtkIdType>(source[i]);
  }

  // The first vertex cell holding each point. vtkPolyData numbers its vertex cells first, so
  // its verts array is enough; other point sets are scanned cell by cell.
  const vtkIdType count = input->GetNumberOfPoints();
  std::vector<vtkIdType> vertexCell(static_cast<std::size_t>(count), -1);
  bool any = false;
  auto mark = [&](vtkIdType cell, vtkIdType n, const vtkIdType* ids)
  {
    for (vtkIdType k = 0; k < n; ++k)
    {
      if (ids[k] >= 0 && ids[k] < count && vertexCell[ids[k]] < 0)
      {
        vertexCell[ids[k]] = cell;
        any = true;
      }
    }
  };
  if (auto* poly = vtkPolyData::SafeDownCast(input))
  {
    vtkCellArray* verts = poly->GetVerts();
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; verts && c < verts->GetNumberOfCells(); ++c)
    {
      verts->GetCellAtId(c, ids);
      mark(c, ids->GetNumberOfIds(), ids->GetPointer(0));
    }
  }
  else
  {
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
    {
      const int type = input->GetCellType(c);
      if (type == VTK_VERTEX || type == VTK_POLY_VERTEX)
      {
        input->GetCellPoints(c, ids);
        mark(c, ids->GetNumberOfIds(), ids->GetPointer(0));
      }
    }
  }
  if (!any)
  {
    return;
  }
  for (std::size_t i = 0; i < cellIds.size(); ++i)
  {
    if (pointIds[i] >= 0 && pointIds[i] < count)
    {
      cellIds[i] = vertexCell[pointIds[i]];
    }
  }
}

//------------------------------------------------------------------------------
double vtkSightlineSphereMapper::ComputeReach(vtkDataObject* data)
{
  double reach = 0.0;
  for (vtkPointSet* points : SightlineMapperInput::PointSets(data))
  {
    if (points->GetNumberOfPoints() > 0)
    {
      vtkDataArray* array = this->RadiusArrayName && *this->RadiusArrayName
        ? points->GetPointData()->GetArray(this->RadiusArrayName)
        : nullptr;
      reach = std::max(reach, SightlineMapperInput::LargestRadius(array, this->Radius, this->RadiusScale));
    }
  }
  return reach;
}

//------------------------------------------------------------------------------
void vtkSightlineSphereMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "RadiusArrayName: " << (this->RadiusArrayName ? this->RadiusArrayName : "(none)")
     << "\n";
  os << indent << "RadiusScale: " << this->RadiusScale << "\n";
}
