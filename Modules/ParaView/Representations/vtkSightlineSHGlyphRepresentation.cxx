// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineSHGlyphRepresentation.h"

#include "vtkObjectFactory.h"
#include "vtkSightlineSHGlyphMapper.h"
#include "vtkSmartPointer.h"

vtkStandardNewMacro(vtkSightlineSHGlyphRepresentation);

vtkSightlineSHGlyphRepresentation::vtkSightlineSHGlyphRepresentation()
  : vtkSightlineGlyphRepresentation(vtkSmartPointer<vtkSightlineSHGlyphMapper>::New())
{
}

vtkSightlineSHGlyphRepresentation::~vtkSightlineSHGlyphRepresentation() = default;

vtkSightlineSHGlyphMapper* vtkSightlineSHGlyphRepresentation::GetSHGlyphMapper()
{
  return static_cast<vtkSightlineSHGlyphMapper*>(this->Mapper.GetPointer());
}

void vtkSightlineSHGlyphRepresentation::SetCoefficientArray(int, int, int, int, const char* name)
{
  this->GetSHGlyphMapper()->SetCoefficientArrayName(SelectedArrayName(name));
}

void vtkSightlineSHGlyphRepresentation::SetBasis(int basis)
{
  this->GetSHGlyphMapper()->SetBasis(basis);
}

void vtkSightlineSHGlyphRepresentation::SetLegacyBasis(int legacy)
{
  this->GetSHGlyphMapper()->SetLegacyBasis(legacy != 0);
}

void vtkSightlineSHGlyphRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
