// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineSHGlyphRepresentation
 * @brief   ParaView's "Sightline SH Glyphs": exact spherical-harmonics glyphs of an image's coefficient array
 *
 * Settings are forwarded to its vtkSightlineSHGlyphMapper (see there); the glyph settings
 * shared with the other glyph kind are in vtkSightlineGlyphRepresentation.
 */
#ifndef vtkSightlineSHGlyphRepresentation_h
#define vtkSightlineSHGlyphRepresentation_h

#include "SightlineParaViewModule.h"
#include "vtkSightlineGlyphRepresentation.h"

class vtkSightlineSHGlyphMapper;

class SIGHTLINEPARAVIEW_EXPORT vtkSightlineSHGlyphRepresentation
  : public vtkSightlineGlyphRepresentation
{
public:
  static vtkSightlineSHGlyphRepresentation* New();
  vtkTypeMacro(vtkSightlineSHGlyphRepresentation, vtkSightlineGlyphRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The point array of SH coefficients (5-element form of ParaView array properties).
  void SetCoefficientArray(int idx, int port, int connection, int association, const char* name);
  /// vtkSightlineSHGlyphMapper::DESCOTEAUX07 (DIPY) or TOURNIER07 (MRtrix3).
  void SetBasis(int basis);
  void SetLegacyBasis(int legacy);

protected:
  vtkSightlineSHGlyphRepresentation();
  ~vtkSightlineSHGlyphRepresentation() override;
  vtkSightlineSHGlyphMapper* GetSHGlyphMapper();

private:
  vtkSightlineSHGlyphRepresentation(const vtkSightlineSHGlyphRepresentation&) = delete;
  void operator=(const vtkSightlineSHGlyphRepresentation&) = delete;
};

#endif
