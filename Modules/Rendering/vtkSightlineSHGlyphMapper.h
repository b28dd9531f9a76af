// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineSHGlyphMapper
 * @brief   Ray-traces exact spherical-harmonics glyphs (fibre ODFs) from a coefficient array.
 *
 * Each input point with a vector of real SH coefficients becomes a glyph whose radius in
 * direction w is |F(w)|, intersected exactly by polynomial root finding (Peters et al. 2023)
 * instead of a tessellated sphere. The input is
 * - a vtkImageData with one coefficient vector per point as a multi-component point array,
 *   e.g. straight from vtkNIFTIImageReader (TimeAsVector on) reading DIPY's or MRtrix3's SH
 *   images; one axial, coronal or sagittal slice or an extent is shown (see SliceOrientation);
 * - or any other vtkDataSet (e.g. vtkPolyData of glyph centres) with such an array: every
 *   point becomes a glyph.
 *
 * Basis: DIPY's descoteaux07 (legacy by default, as DIPY writes) or MRtrix3's tournier07
 * (LegacyBasis off); SetBasisToDIPY() and SetBasisToMRtrix3() set both at once. The number of
 * components gives the order (1, 6, 15, 28, 45, 66, 91, ... for orders 0, 2, 4, ..., 16);
 * MaximumOrder truncates higher bands, and trailing bands that are zero are dropped per glyph
 * (lower polynomial degree).
 *
 * Orientation: DataToWorldMatrix (e.g. vtkNIFTIImageReader::GetQFormMatrix()) places the glyph
 * centres; give an image slice of the same data the same matrix as its actor's UserMatrix so
 * both line up. The SH directions are taken in world (scanner) axes, as MRtrix3 stores FODs
 * and DIPY's odf_slicer assumes. When they are given in other axes, e.g. a DIPY fit made with
 * FSL-style b-vectors (the file's voxel axes), set DirectionToWorldMatrix to the map from
 * those axes to world axes (for a NIfTI file: its affine; with vtkNIFTIImageReader, the qform
 * matrix with its third column multiplied by GetQFac(), since the reader reverses the slices
 * when qfac is -1): each glyph is then turned by the rotation closest to that matrix. An actor
 * transform moves and turns the glyphs as a whole.
 *
 * Size: a glyph of normalised amplitude 1 has radius ScaleFactor times half the smallest voxel
 * spacing for image input (the default fills the voxel) and ScaleFactor world units otherwise.
 * Normalization divides each glyph by its largest amplitude (default, as odf_slicer's norm),
 * by its coefficient norm, by the largest amplitude of all glyphs of the input (Global), or
 * not at all.
 *
 * Colour: by direction (|p/|p||, the usual colouring of fibre directions; default), by a
 * scalar array through the lookup table (Coloring SCALARS, with vtkMapper's ScalarMode,
 * SelectColorArray and lookup table), or the actor's colour. Negative lobes (F < 0) can be
 * shown, coloured (NegativeLobeColor) or hidden. A mask array hides glyphs where it is 0.
 *
 * Uncertainty: an optional second coefficient array (UncertaintyArrayName) describes a glyph
 * enclosing each mean glyph; it is drawn as a homogeneous grey volume with extinction
 * UncertaintyExtinction (Peters et al. 2023, Sec. 4.3), scaled with the same factors.
 *
 * Caching: each voxel's glyph box (Section 4.2, the costly part) and largest amplitude are
 * computed once and kept while the input, the array and the basis stay the same, so changing
 * the slice, the scale or the normalisation only rebuilds the BVH; GetLastComputedBoxes()
 * tells how many boxes the last build had to compute.
 *
 * Bad input is reported by name and never fatal: a missing coefficient, mask or uncertainty
 * array, a component count that is no SH order, an empty input or slice, NaN/Inf coefficients
 * (those glyphs are skipped with a warning naming the first point; the rest render).
 *
 * Slicing, matrices, mask, normalisation, scale, colouring, intersection and the box cache are
 * vtkSightlineGlyphMapper's, shared with vtkSightlineTensorGlyphMapper.
 *
 * @sa vtkSightlineGlyphMapper vtkSightlineTensorGlyphMapper vtkSightlineImageRenderer
 * vtkNIFTIImageReader
 */
#ifndef vtkSightlineSHGlyphMapper_h
#define vtkSightlineSHGlyphMapper_h

#include "SightlineRenderingModule.h" // for export macro
#include "vtkSightlineGlyphMapper.h"

class SIGHTLINERENDERING_EXPORT vtkSightlineSHGlyphMapper : public vtkSightlineGlyphMapper
{
public:
  static vtkSightlineSHGlyphMapper* New();
  vtkTypeMacro(vtkSightlineSHGlyphMapper, vtkSightlineGlyphMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Point-data array with the SH coefficients (one tuple per point), or null for the active
   * point scalars (what vtkNIFTIImageReader produces). Default null.
   */
  vtkSetStringMacro(CoefficientArrayName);
  vtkGetStringMacro(CoefficientArrayName);
  ///@}

  enum Bases
  {
    DESCOTEAUX07 = 0, ///< DIPY's basis
    TOURNIER07        ///< MRtrix3's basis
  };

  ///@{
  /**
   * SH basis of the coefficients, and whether it is the legacy variant (DIPY's default
   * descoteaux07 is legacy; MRtrix3's tournier07 is not). Default descoteaux07, legacy.
   * SetBasisByName accepts "descoteaux07" and "tournier07" and reports anything else.
   */
  vtkSetClampMacro(Basis, int, DESCOTEAUX07, TOURNIER07);
  vtkGetMacro(Basis, int);
  void SetBasisToDescoteaux07() { this->SetBasis(DESCOTEAUX07); }
  void SetBasisToTournier07() { this->SetBasis(TOURNIER07); }
  bool SetBasisByName(const char* name);
  const char* GetBasisAsString();
  vtkSetMacro(LegacyBasis, bool);
  vtkGetMacro(LegacyBasis, bool);
  vtkBooleanMacro(LegacyBasis, bool);
  /** descoteaux07, legacy: what DIPY writes by default. */
  void SetBasisToDIPY();
  /** tournier07, not legacy: what MRtrix3 writes. */
  void SetBasisToMRtrix3();
  ///@}

  ///@{
  /**
   * Optional point-data array of uncertainty glyphs (SH coefficients in the same basis, any
   * order), drawn as a homogeneous volume. Null (default): none.
   */
  vtkSetStringMacro(UncertaintyArrayName);
  vtkGetStringMacro(UncertaintyArrayName);
  ///@}

  ///@{
  /**
   * Extinction of the uncertainty volume per glyph radius: a ray that travels one normalised
   * glyph radius (the length ScaleFactor stands for) inside it keeps exp(-value) of the colour
   * behind. Default 2.
   */
  vtkSetClampMacro(UncertaintyExtinction, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(UncertaintyExtinction, double);
  ///@}

  ///@{
  /**
   * Emission colour of the uncertainty volume. Default grey (0.5, 0.5, 0.5) as in the paper.
   */
  vtkSetVector3Macro(UncertaintyColor, double);
  vtkGetVector3Macro(UncertaintyColor, double);
  ///@}

  /**
   * The superclass's bytes plus the uncertainty glyphs and their cache.
   */
  vtkIdType GetMemoryBytes() override;

protected:
  vtkSightlineSHGlyphMapper();
  ~vtkSightlineSHGlyphMapper() override;

#ifndef __VTK_WRAP__
  std::shared_ptr<sightline::Geometry> BuildGlyphs(
    vtkDataSet* input, const sightline::GlyphRequest& request) override;
  void ConfigureRender(sightline::RenderOptions& options) override;
#endif

  char* CoefficientArrayName = nullptr;
  int Basis = DESCOTEAUX07;
  bool LegacyBasis = true;
  char* UncertaintyArrayName = nullptr;
  double UncertaintyExtinction = 2.0;
  double UncertaintyColor[3] = { 0.5, 0.5, 0.5 };

private:
  vtkSightlineSHGlyphMapper(const vtkSightlineSHGlyphMapper&) = delete;
  void operator=(const vtkSightlineSHGlyphMapper&) = delete;

  class vtkSHInternals;
  std::unique_ptr<vtkSHInternals> SHInternals;
};

#endif
