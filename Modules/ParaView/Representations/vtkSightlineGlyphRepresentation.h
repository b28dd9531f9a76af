// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineGlyphRepresentation
 * @brief   The glyph settings shared by the Sightline SH Glyphs and Tensor Glyphs representations
 *
 * Forwards to vtkSightlineGlyphMapper: size, normalisation, slice, negative lobes, intersection
 * method, and the glyph colouring used when ParaView's "Coloring" is "Solid Color" (the
 * default: colour by lobe direction). Selecting an array in "Coloring" colours the glyphs by it
 * through ParaView's lookup table.
 */
#ifndef vtkSightlineGlyphRepresentation_h
#define vtkSightlineGlyphRepresentation_h

#include "SightlineParaViewModule.h"
#include "vtkSightlineRepresentation.h"

class vtkSightlineGlyphMapper;

class SIGHTLINEPARAVIEW_EXPORT vtkSightlineGlyphRepresentation : public vtkSightlineRepresentation
{
public:
  vtkTypeMacro(vtkSightlineGlyphRepresentation, vtkSightlineRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetMaximumOrder(int order);
  void SetNormalization(int mode);
  void SetScaleFactor(double factor);
  void SetSliceOrientation(int orientation);
  void SetSliceNumber(int slice);
  /// Colouring without a selected array: vtkSightlineGlyphMapper::COLOR_BY_DIRECTION,
  /// COLOR_SOLID or COLOR_BY_RADIUS.
  void SetGlyphColoring(int coloring);
  void SetNegativeLobes(int mode);
  void SetNegativeLobeColor(double r, double g, double b);
  void SetIntersectionMethod(int method);
  /// vtkSightlineGlyphMapper::SetFrustumCulling: boxes only for the glyphs in view.
  void SetFrustumCulling(bool on);

protected:
  explicit vtkSightlineGlyphRepresentation(vtkSightlineGlyphMapper* mapper);
  ~vtkSightlineGlyphRepresentation() override;
  void SetScalarColoring(bool on) override;
  vtkSightlineGlyphMapper* GetGlyphMapper();

  int GlyphColoring = 0; // vtkSightlineGlyphMapper::COLOR_BY_DIRECTION
  bool ScalarColoring = false;

private:
  vtkSightlineGlyphRepresentation(const vtkSightlineGlyphRepresentation&) = delete;
  void operator=(const vtkSightlineGlyphRepresentation&) = delete;
};

#endif
