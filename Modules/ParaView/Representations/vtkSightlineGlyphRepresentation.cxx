// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineGlyphRepresentation.h"

#include "vtkSightlineGlyphMapper.h"

vtkSightlineGlyphRepresentation::vtkSightlineGlyphRepresentation(vtkSightlineGlyphMapper* mapper)
  : vtkSightlineRepresentation(mapper)
{
  this->GlyphColoring = mapper->GetColoring();
}

vtkSightlineGlyphRepresentation::~vtkSightlineGlyphRepresentation() = default;

vtkSightlineGlyphMapper* vtkSightlineGlyphRepresentation::GetGlyphMapper()
{
  return static_cast<vtkSightlineGlyphMapper*>(this->Mapper.GetPointer());
}

void vtkSightlineGlyphRepresentation::SetScalarColoring(bool on)
{
  this->ScalarColoring = on;
  this->Superclass::SetScalarColoring(on);
  this->GetGlyphMapper()->SetColoring(
    on ? vtkSightlineGlyphMapper::COLOR_BY_SCALARS : this->GlyphColoring);
}

void vtkSightlineGlyphRepresentation::SetGlyphColoring(int coloring)
{
  this->GlyphColoring = coloring;
  if (!this->ScalarColoring)
  {
    this->GetGlyphMapper()->SetColoring(coloring);
  }
}

void vtkSightlineGlyphRepresentation::SetMaximumOrder(int order)
{
  this->GetGlyphMapper()->SetMaximumOrder(order);
}

void vtkSightlineGlyphRepresentation::SetNormalization(int mode)
{
  this->GetGlyphMapper()->SetNormalization(mode);
}

void vtkSightlineGlyphRepresentation::SetScaleFactor(double factor)
{
  this->GetGlyphMapper()->SetScaleFactor(factor);
}

void vtkSightlineGlyphRepresentation::SetFrustumCulling(bool on)
{
  this->GetGlyphMapper()->SetFrustumCulling(on);
}

void vtkSightlineGlyphRepresentation::SetSliceOrientation(int orientation)
{
  this->GetGlyphMapper()->SetSliceOrientation(orientation);
}

void vtkSightlineGlyphRepresentation::SetSliceNumber(int slice)
{
  this->GetGlyphMapper()->SetSliceNumber(slice);
}

void vtkSightlineGlyphRepresentation::SetNegativeLobes(int mode)
{
  this->GetGlyphMapper()->SetNegativeLobes(mode);
}

void vtkSightlineGlyphRepresentation::SetNegativeLobeColor(double r, double g, double b)
{
  this->GetGlyphMapper()->SetNegativeLobeColor(r, g, b);
}

void vtkSightlineGlyphRepresentation::SetIntersectionMethod(int method)
{
  this->GetGlyphMapper()->SetIntersectionMethod(method);
}

void vtkSightlineGlyphRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "GlyphColoring: " << this->GlyphColoring << "\n";
  os << indent << "ScalarColoring: " << this->ScalarColoring << "\n";
}
