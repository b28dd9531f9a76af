// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineTensorGlyphRepresentation
 * @brief   ParaView's "Sightline Tensor Glyphs": exact glyphs of symmetric tensors of order 2 to 12
 *
 * Settings are forwarded to its vtkSightlineTensorGlyphMapper (see there); the glyph settings
 * shared with the other glyph kind are in vtkSightlineGlyphRepresentation.
 */
#ifndef vtkSightlineTensorGlyphRepresentation_h
#define vtkSightlineTensorGlyphRepresentation_h

#include "SightlineParaViewModule.h"
#include "vtkSightlineGlyphRepresentation.h"

class vtkSightlineTensorGlyphMapper;

class SIGHTLINEPARAVIEW_EXPORT vtkSightlineTensorGlyphRepresentation
  : public vtkSightlineGlyphRepresentation
{
public:
  static vtkSightlineTensorGlyphRepresentation* New();
  vtkTypeMacro(vtkSightlineTensorGlyphRepresentation, vtkSightlineGlyphRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The point array of tensor components (5-element form of ParaView array properties).
  void SetTensorArray(int idx, int port, int connection, int association, const char* name);
  /// vtkSightlineTensorGlyphMapper::TensorLayouts.
  void SetTensorLayout(int layout);
  /// vtkSightlineTensorGlyphMapper::SHAPE_TENSOR_FUNCTION or SHAPE_ELLIPSOID.
  void SetShape(int shape);

protected:
  vtkSightlineTensorGlyphRepresentation();
  ~vtkSightlineTensorGlyphRepresentation() override;
  vtkSightlineTensorGlyphMapper* GetTensorGlyphMapper();

private:
  vtkSightlineTensorGlyphRepresentation(const vtkSightlineTensorGlyphRepresentation&) = delete;
  void operator=(const vtkSightlineTensorGlyphRepresentation&) = delete;
};

#endif
