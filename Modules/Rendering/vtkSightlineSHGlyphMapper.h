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
 * @sa vtkSightlineMapper vtkSightlineImageRenderer vtkNIFTIImageReader
 */
#ifndef vtkSightlineSHGlyphMapper_h
#define vtkSightlineSHGlyphMapper_h

#include "SightlineRenderingModule.h" // for export macro
#include "vtkSightlineMapper.h"

#ifndef __VTK_WRAP__
#include <glm/vec3.hpp> // for sightline::vec3
#include <cstdint>      // for std::uint32_t
#include <string>       // for std::string
#include <vector>       // for std::vector
namespace sightline
{
using vec3 = glm::vec3;
struct SHGlyphOptions;
}
#endif

class vtkMatrix4x4;

class SIGHTLINERENDERING_EXPORT vtkSightlineSHGlyphMapper : public vtkSightlineMapper
{
public:
  static vtkSightlineSHGlyphMapper* New();
  vtkTypeMacro(vtkSightlineSHGlyphMapper, vtkSightlineMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Includes the modification times of DataToWorldMatrix and DirectionToWorldMatrix.
   */
  vtkMTimeType GetMTime() override;

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
   * Highest band to draw (even); higher bands of the input are ignored. Negative (default)
   * draws every band the array has.
   */
  vtkSetMacro(MaximumOrder, int);
  vtkGetMacro(MaximumOrder, int);
  ///@}

  enum Normalizations
  {
    NORMALIZE_NONE = 0,          ///< radius = scale * |F|
    NORMALIZE_MAX_AMPLITUDE,     ///< each glyph's longest lobe has radius = scale
    NORMALIZE_COEFFICIENT_NORM,  ///< each glyph divided by its coefficient vector's norm
    NORMALIZE_GLOBAL             ///< all glyphs divided by the largest amplitude of the input
  };

  ///@{
  /**
   * How glyphs are normalised before ScaleFactor. Default NORMALIZE_MAX_AMPLITUDE.
   */
  vtkSetClampMacro(Normalization, int, NORMALIZE_NONE, NORMALIZE_GLOBAL);
  vtkGetMacro(Normalization, int);
  void SetNormalizationToNone() { this->SetNormalization(NORMALIZE_NONE); }
  void SetNormalizationToMaxAmplitude() { this->SetNormalization(NORMALIZE_MAX_AMPLITUDE); }
  void SetNormalizationToCoefficientNorm() { this->SetNormalization(NORMALIZE_COEFFICIENT_NORM); }
  void SetNormalizationToGlobal() { this->SetNormalization(NORMALIZE_GLOBAL); }
  const char* GetNormalizationAsString();
  ///@}

  ///@{
  /**
   * Glyph size (see the class documentation): for images in units of half the smallest voxel
   * spacing, otherwise in world units. Default 1.
   */
  vtkSetMacro(ScaleFactor, double);
  vtkGetMacro(ScaleFactor, double);
  ///@}

  enum SliceOrientations
  {
    SLICE_AXIAL = 0, ///< the voxel axis closest to world z (inferior-superior)
    SLICE_CORONAL,   ///< the voxel axis closest to world y (posterior-anterior)
    SLICE_SAGITTAL,  ///< the voxel axis closest to world x (left-right)
    SLICE_EXTENT     ///< every voxel of DisplayExtent
  };

  ///@{
  /**
   * Which glyphs of an image are drawn: one slice across the voxel axis that DataToWorldMatrix
   * maps closest to the world's z, y or x axis, or an extent. Default SLICE_AXIAL.
   */
  vtkSetClampMacro(SliceOrientation, int, SLICE_AXIAL, SLICE_EXTENT);
  vtkGetMacro(SliceOrientation, int);
  void SetSliceOrientationToAxial() { this->SetSliceOrientation(SLICE_AXIAL); }
  void SetSliceOrientationToCoronal() { this->SetSliceOrientation(SLICE_CORONAL); }
  void SetSliceOrientationToSagittal() { this->SetSliceOrientation(SLICE_SAGITTAL); }
  void SetSliceOrientationToExtent() { this->SetSliceOrientation(SLICE_EXTENT); }
  const char* GetSliceOrientationAsString();
  ///@}

  ///@{
  /**
   * Index of the slice along the slice axis, in the image's structured extent; negative
   * (default) picks the middle slice. Out-of-range numbers are clamped, with a warning.
   */
  vtkSetMacro(SliceNumber, int);
  vtkGetMacro(SliceNumber, int);
  ///@}

  ///@{
  /**
   * Voxel extent drawn with SLICE_EXTENT, clamped to the image (like odf_slicer's
   * display_extent). Default: everything.
   */
  vtkSetVector6Macro(DisplayExtent, int);
  vtkGetVector6Macro(DisplayExtent, int);
  ///@}

  /**
   * The image axis (0, 1 or 2) that the current orientation slices across, for the current
   * input and DataToWorldMatrix; -1 for SLICE_EXTENT or non-image input.
   */
  int GetSliceAxis();

  /**
   * The voxel extent the last build drew (the slice or the clamped display extent).
   */
  vtkGetVector6Macro(DrawnExtent, int);

  ///@{
  /**
   * Matrix from the input's point coordinates to world coordinates, applied to the glyph
   * centres only (see the class documentation). Null (default) is the identity.
   */
  void SetDataToWorldMatrix(vtkMatrix4x4* matrix);
  vtkGetObjectMacro(DataToWorldMatrix, vtkMatrix4x4);
  ///@}

  ///@{
  /**
   * Map from the axes of the SH directions to world axes (only its 3x3 part counts, and only
   * its rotation: scaling and shear are removed). Null (default): directions are in world axes.
   */
  void SetDirectionToWorldMatrix(vtkMatrix4x4* matrix);
  vtkGetObjectMacro(DirectionToWorldMatrix, vtkMatrix4x4);
  ///@}

  ///@{
  /**
   * Point-data array that masks glyphs: a glyph is drawn where its first component is not 0.
   * Null (default): no mask.
   */
  vtkSetStringMacro(MaskArrayName);
  vtkGetStringMacro(MaskArrayName);
  ///@}

  enum Colorings
  {
    COLOR_BY_DIRECTION = 0, ///< |p / |p|| as RGB
    COLOR_BY_SCALARS,       ///< vtkMapper scalar colouring through the lookup table
    COLOR_SOLID,            ///< the actor's vtkProperty colour
    COLOR_BY_RADIUS         ///< the lookup table at |p|, the glyph radius at each surface point
  };

  ///@{
  /**
   * How glyphs are coloured. Default COLOR_BY_DIRECTION.
   */
  vtkSetClampMacro(Coloring, int, COLOR_BY_DIRECTION, COLOR_BY_RADIUS);
  vtkGetMacro(Coloring, int);
  void SetColoringToDirection() { this->SetColoring(COLOR_BY_DIRECTION); }
  void SetColoringToScalars() { this->SetColoring(COLOR_BY_SCALARS); }
  void SetColoringToSolid() { this->SetColoring(COLOR_SOLID); }
  void SetColoringToRadius() { this->SetColoring(COLOR_BY_RADIUS); }
  const char* GetColoringAsString();

  /**
   * COLOR_BY_RADIUS (the tensor-glyph paper's colour coding by scalar value): each surface
   * point gets the lookup table's colour of its glyph radius |F(w)| in input units (e.g. GPa
   * for a stiffness tensor), before normalisation and scaling. The table's colours are spread
   * over RadiusRange; when it is empty (lo >= hi, the default [0, -1]) over [0, largest radius
   * of the drawn glyphs]. Without a lookup table set, black-red-yellow as in the paper.
   */
  vtkSetVector2Macro(RadiusRange, double);
  vtkGetVector2Macro(RadiusRange, double);
  /** The range the last render used for COLOR_BY_RADIUS. */
  vtkGetVector2Macro(LastRadiusRange, double);
  ///@}

  enum NegativeLobeModes
  {
    NEGATIVE_LOBES_SHOW = 0, ///< drawn like positive lobes (|F| is the radius)
    NEGATIVE_LOBES_COLOR,    ///< drawn in NegativeLobeColor
    NEGATIVE_LOBES_HIDE      ///< not drawn
  };

  ///@{
  /**
   * Negative lobes (where F < 0, e.g. from noise in a CSD fit). Default NEGATIVE_LOBES_SHOW.
   */
  vtkSetClampMacro(NegativeLobes, int, NEGATIVE_LOBES_SHOW, NEGATIVE_LOBES_HIDE);
  vtkGetMacro(NegativeLobes, int);
  void SetNegativeLobesToShow() { this->SetNegativeLobes(NEGATIVE_LOBES_SHOW); }
  void SetNegativeLobesToColor() { this->SetNegativeLobes(NEGATIVE_LOBES_COLOR); }
  void SetNegativeLobesToHide() { this->SetNegativeLobes(NEGATIVE_LOBES_HIDE); }
  const char* GetNegativeLobesAsString();
  vtkSetVector3Macro(NegativeLobeColor, double);
  vtkGetVector3Macro(NegativeLobeColor, double);
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
   * Boxes the last build computed (the others came from the per-voxel cache).
   */
  vtkGetMacro(LastComputedBoxes, vtkIdType);

  /**
   * Bytes held by the glyph geometry and the per-voxel caches (not the input).
   */
  virtual vtkIdType GetMemoryBytes();

protected:
  vtkSightlineSHGlyphMapper();
  ~vtkSightlineSHGlyphMapper() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
#ifndef __VTK_WRAP__
  std::shared_ptr<sightline::Geometry> BuildGeometry() override;
  void ConfigureRender(sightline::RenderOptions& options) override;

  /**
   * The point array whose tuples are the glyph functions, its SH order and whether it holds
   * canonical (orthonormal) SH coefficients instead of Basis. Reports the problem and returns
   * null when there is none. Subclasses that convert other inputs (tensors) override it.
   */
  virtual vtkDataArray* SelectCoefficients(
    vtkDataSet* input, int& order, bool& canonical, std::string& label);

  /**
   * Creates the glyph geometry from what BuildGeometry gathered: centres in world
   * coordinates, `values` (shCoefficientCount(order) per glyph in options.convention), scales,
   * colours and cached boxes (see sightline::SHGlyphSet). Subclasses may draw other shapes
   * from the same glyphs.
   */
  virtual std::shared_ptr<sightline::Geometry> CreateGlyphGeometry(
    const std::vector<sightline::vec3>& centers, const std::vector<float>& values, int order,
    sightline::SHGlyphOptions& options, const std::vector<float>& scales,
    const std::vector<std::uint32_t>& colors, const std::vector<sightline::vec3>& halfExtents);
#endif

  char* CoefficientArrayName = nullptr;
  int Basis = DESCOTEAUX07;
  bool LegacyBasis = true;
  int MaximumOrder = -1;
  int Normalization = NORMALIZE_MAX_AMPLITUDE;
  double ScaleFactor = 1.0;
  int SliceOrientation = SLICE_AXIAL;
  int SliceNumber = -1;
  int DisplayExtent[6] = { VTK_INT_MIN, VTK_INT_MAX, VTK_INT_MIN, VTK_INT_MAX, VTK_INT_MIN,
    VTK_INT_MAX };
  int DrawnExtent[6] = { 0, -1, 0, -1, 0, -1 };
  vtkMatrix4x4* DataToWorldMatrix = nullptr;
  vtkMatrix4x4* DirectionToWorldMatrix = nullptr;
  char* MaskArrayName = nullptr;
  int Coloring = COLOR_BY_DIRECTION;
  int NegativeLobes = NEGATIVE_LOBES_SHOW;
  double NegativeLobeColor[3] = { 0.9, 0.1, 0.1 };
  double RadiusRange[2] = { 0.0, -1.0 };
  double LastRadiusRange[2] = { 0.0, -1.0 };
  char* UncertaintyArrayName = nullptr;
  double UncertaintyExtinction = 2.0;
  double UncertaintyColor[3] = { 0.5, 0.5, 0.5 };
  vtkIdType LastComputedBoxes = 0;

private:
  vtkSightlineSHGlyphMapper(const vtkSightlineSHGlyphMapper&) = delete;
  void operator=(const vtkSightlineSHGlyphMapper&) = delete;

  class vtkGlyphInternals;
  std::unique_ptr<vtkGlyphInternals> GlyphInternals;
};

#endif
