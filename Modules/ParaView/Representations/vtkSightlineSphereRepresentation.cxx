// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineSphereRepresentation.h"

#include "vtkObjectFactory.h"
#include "vtkSightlineSphereMapper.h"
#include "vtkSmartPointer.h"

vtkStandardNewMacro(vtkSightlineSphereRepresentation);

vtkSightlineSphereRepresentation::vtkSightlineSphereRepresentation()
  : vtkSightlineRepresentation(vtkSmartPointer<vtkSightlineSphereMapper>::New())
{
}

vtkSightlineSphereRepresentation::~vtkSightlineSphereRepresentation() = default;

vtkSightlineSphereMapper* vtkSightlineSphereRepresentation::GetSphereMapper()
{
  return static_cast<vtkSightlineSphereMapper*>(this->Mapper.GetPointer());
}

void vtkSightlineSphereRepresentation::SetRadius(double radius)
{
  this->GetSphereMapper()->SetRadius(radius);
}

void vtkSightlineSphereRepresentation::SetRadiusArray(
  int, int, int, int, const char* name)
{
  this->GetSphereMapper()->SetRadiusArrayName(SelectedArrayName(name));
}

void vtkSightlineSphereRepresentation::SetRadiusScale(double scale)
{
  this->GetSphereMapper()->SetRadiusScale(scale);
}

void vtkSightlineSphereRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
