// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineTensorGlyphRepresentation.h"

#include "vtkObjectFactory.h"
#include "vtkSightlineTensorGlyphMapper.h"
#include "vtkSmartPointer.h"

vtkStandardNewMacro(vtkSightlineTensorGlyphRepresentation);

vtkSightlineTensorGlyphRepresentation::vtkSightlineTensorGlyphRepresentation()
  : vtkSightlineGlyphRepresentation(vtkSmartPointer<vtkSightlineTensorGlyphMapper>::New())
{
}

vtkSightlineTensorGlyphRepresentation::~vtkSightlineTensorGlyphRepresentation() = default;

vtkSightlineTensorGlyphMapper* vtkSightlineTensorGlyphRepresentation::GetTensorGlyphMapper()
{
  return static_cast<vtkSightlineTensorGlyphMapper*>(this->Mapper.GetPointer());
}

void vtkSightlineTensorGlyphRepresentation::SetTensorArray(int, int, int, int, const char* name)
{
  this->GetTensorGlyphMapper()->SetTensorArrayName(SelectedArrayName(name));
}

void vtkSightlineTensorGlyphRepresentation::SetTensorLayout(int layout)
{
  this->GetTensorGlyphMapper()->SetTensorLayout(layout);
}

void vtkSightlineTensorGlyphRepresentation::SetShape(int shape)
{
  this->GetTensorGlyphMapper()->SetShape(shape);
}

void vtkSightlineTensorGlyphRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
