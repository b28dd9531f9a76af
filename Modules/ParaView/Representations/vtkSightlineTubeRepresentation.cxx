// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineTubeRepresentation.h"

#include "vtkObjectFactory.h"
#include "vtkSightlineTubeMapper.h"
#include "vtkSmartPointer.h"

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
  this->GetTubeMapper()->SetPredecessorArrayName(SelectedArrayName(name));
}

void vtkSightlineTubeRepresentation::SetLinkLayout(int layout)
{
  this->GetTubeMapper()->SetLinkLayout(layout);
}

void vtkSightlineTubeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "VaryRadius: " << this->VaryRadius << "\n";
  os << indent << "HasRadiusArray: " << this->HasRadiusArray << "\n";
}
