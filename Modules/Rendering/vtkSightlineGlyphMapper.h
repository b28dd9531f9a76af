// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineGlyphMapper
 * @brief   Abstract superclass of the exact glyph mappers: which points become glyphs, where,
 *          how large and in which colour.
 *
 * Every input point with a glyph function (SH coefficients, a tensor) becomes one ray-traced
 * glyph. This class holds what all glyph kinds share, and the subclasses only say where the
 * functions come from (vtkSightlineSHGlyphMapper: SH coefficients in a basis, plus an
 * uncertainty volume; vtkSightlineTensorGlyphMapper: tensors in a layout, or ellipsoids):
 * - which points: one axial, coronal or sagittal slice or an extent of a vtkImageData
 *   (SliceOrientation), every point of any other vtkDataSet, minus those a mask array zeroes;
 * - where: DataToWorldMatrix places the centres; DirectionToWorldMatrix turns the glyph
 *   functions from their axes into world axes (its closest rotation);
 * - how large: Normalization, then ScaleFactor (for images in units of half the smallest voxel
 *   spacing, otherwise world units); MaximumOrder truncates higher SH bands;
 * - colour: by direction, by point scalars through the lookup table, solid, or by radius;
 *   negative lobes shown, coloured or hidden;
 * - intersection: exact root finding, or the tensor-glyph paper's marching and interval
 *   methods as baselines (orders up to 12).
 *
 * The kernel (sightline::SHGlyphPreparation) converts, turns, normalises and boxes the glyphs;
 * it caches each point's box and largest amplitude while the array stays the same, so changing
 * the slice, the scale or the normalisation only rebuilds the BVH (GetLastComputedBoxes()).
 *
 * Every point array (glyph functions, mask, uncertainty) is checked against the points it
 * describes before it is read: a missing array, a tuple count that differs from the number of
 * points or too few components is an error naming the array; nothing is read past its end.
 *
 * @sa vtkSightlineSHGlyphMapper vtkSightlineTensorGlyphMapper vtkSightlineMapper
 */
#ifndef vtkSightlineGlyphMapper_h
#define vtkSightlineGlyphMapper_h

#include "SightlineRenderingModule.h" // for export macro
#include "vtkSightlineMapper.h"

#ifndef __VTK_WRAP__
#include <cstddef> // for std::size_t
#include <memory>  // for std::unique_ptr
#include <string>  // for std::string
#include <vector>  // for std::vector
namespace sightline
{
class SHGlyphPreparation;
struct GlyphDrops;
struct GlyphSource;
struct GlyphRequest;
struct PreparedEllipsoids;
struct PreparedSHGlyphs;
}
#endif

class vtkDataArray;
class vtkDataSet;
class vtkMatrix4x4;

class SIGHTLINERENDERING_EXPORT vtkSightlineGlyphMapper : public vtkSightlineMapper
{
public:
  vtkTypeMacro(vtkSightlineGlyphMapper, vtkSightlineMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Includes the modification times of DataToWorldMatrix and DirectionToWorldMatrix.
   */
  vtkMTimeType GetMTime() override;

  ///@{
  /**
   * Highest SH band to draw (even); higher bands of the input are ignored. Negative (default)
   * draws every band the glyph functions have.
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
   * centres only. Null (default) is the identity.
   */
  void SetDataToWorldMatrix(vtkMatrix4x4* matrix);
  vtkGetObjectMacro(DataToWorldMatrix, vtkMatrix4x4);
  ///@}

  ///@{
  /**
   * Map from the axes of the glyph functions' directions to world axes (only its 3x3 part
   * counts, and only its rotation: scaling and shear are removed). Null (default): directions
   * are in world axes.
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

  enum IntersectionMethods
  {
    INTERSECT_EXACT = 0, ///< polynomial root finding (Peters et al. 2023)
    INTERSECT_MARCHING,  ///< the tensor-glyph paper's fixed-step marching
    INTERSECT_INTERVAL,  ///< rejection and bisection with interval arithmetic
    INTERSECT_AFFINE     ///< the same with reduced affine arithmetic
  };

  ///@{
  /**
   * How rays meet the glyph surface. EXACT (default) or, as options and baselines for orders
   * up to 12, the tensor-glyph paper's own methods: MARCHING (fixed steps of MarchingStepSize
   * bounding radii inside the bounding sphere, sign test, bisection steps, final linear
   * interpolation, a third of the step near the centre), INTERVAL and AFFINE (guaranteed
   * rejection and bisection down to SubdivisionTolerance bounding radii). The baselines trace
   * the ray from outside the bounding sphere only.
   */
  vtkSetClampMacro(IntersectionMethod, int, INTERSECT_EXACT, INTERSECT_AFFINE);
  vtkGetMacro(IntersectionMethod, int);
  void SetIntersectionMethodToExact() { this->SetIntersectionMethod(INTERSECT_EXACT); }
  void SetIntersectionMethodToMarching() { this->SetIntersectionMethod(INTERSECT_MARCHING); }
  void SetIntersectionMethodToInterval() { this->SetIntersectionMethod(INTERSECT_INTERVAL); }
  void SetIntersectionMethodToAffine() { this->SetIntersectionMethod(INTERSECT_AFFINE); }
  const char* GetIntersectionMethodAsString();
  ///@}

  ///@{
  /**
   * MARCHING: step in units of the glyph's bounding radius (default 0.2, the paper's
   * recommendation), bisection steps (default 0), final linear interpolation (default on) and
   * a third of the step within a quarter of the radius from the centre (default on).
   */
  vtkSetClampMacro(MarchingStepSize, double, 1e-4, 2.0);
  vtkGetMacro(MarchingStepSize, double);
  vtkSetClampMacro(MarchingBisectionSteps, int, 0, 60);
  vtkGetMacro(MarchingBisectionSteps, int);
  vtkSetMacro(MarchingLinearInterpolation, bool);
  vtkGetMacro(MarchingLinearInterpolation, bool);
  vtkBooleanMacro(MarchingLinearInterpolation, bool);
  vtkSetMacro(MarchingCentreRefinement, bool);
  vtkGetMacro(MarchingCentreRefinement, bool);
  vtkBooleanMacro(MarchingCentreRefinement, bool);
  ///@}

  ///@{
  /**
   * INTERVAL and AFFINE: length, in bounding radii, below which an unrejected segment is the
   * hit. Default 1e-4.
   */
  vtkSetClampMacro(SubdivisionTolerance, double, 1e-12, 0.5);
  vtkGetMacro(SubdivisionTolerance, double);
  ///@}

  ///@{
  /**
   * Frustum culling (default off): the near-exact box search runs only for the glyphs the
   * camera may show (its frustum widened to half again the view angle and twice the depth
   * range, so that small camera moves stay inside). The others get the loose cube of their
   * coefficient bound, which still encloses them: every glyph is drawn exactly wherever a ray
   * reaches it (shadows, a later view), only slower to trace. When a still frame's view shows
   * a glyph with a loose box, the geometry is rebuilt with the near-exact boxes of what is in
   * view (the per-point cache keeps every box computed); interactive frames (while the user
   * drags) never rebuild. Before the first frame (GetBounds() for ResetCamera()) no view is
   * known, every box is loose and so are the bounds. Pays for close-ups of whole-volume glyph
   * fields; a view of the whole field pays one extra build (Benchmarks/README.md).
   */
  vtkSetMacro(FrustumCulling, bool);
  vtkGetMacro(FrustumCulling, bool);
  vtkBooleanMacro(FrustumCulling, bool);
  ///@}

  /**
   * Boxes the last build computed (the others came from the per-point cache).
   */
  vtkGetMacro(LastComputedBoxes, vtkIdType);

  /**
   * Glyphs of the last build with a loose box (FrustumCulling: outside the view).
   */
  vtkGetMacro(LastLooseBoxes, vtkIdType);

#ifndef __VTK_WRAP__
  /**
   * FrustumCulling: keeps the view's frustum for the next build, and asks for a rebuild when
   * a still frame's view shows a glyph with a loose box.
   */
  void SetView(vtkProp3D* prop, vtkCamera* camera, double aspect, bool interactive) override;
#endif

  /**
   * Bytes held by the glyph geometry and the per-point caches (not the input).
   */
  virtual vtkIdType GetMemoryBytes();

protected:
  vtkSightlineGlyphMapper();
  ~vtkSightlineGlyphMapper() override;


#ifndef __VTK_WRAP__
  /**
   * Picks the points (slice or extent, mask), their world scale and rotation, and lets the
   * subclass build the glyphs of its functions at those points.
   */
  std::shared_ptr<sightline::Geometry> BuildGeometry() final;

  /**
   * Selection: a glyph stands for its point of the input (the voxel, for images); glyphs have
   * no cell id.
   */
  void ComputeSelectionIds(
    std::vector<vtkIdType>& pointIds, std::vector<vtkIdType>& cellIds) final;

  /**
   * The subclass's glyphs for `request` (the chosen points, rotation, normalisation, world
   * scale and progress). Report problems by name and return null when nothing is drawn;
   * kernel exceptions are caught and reported by the caller.
   */
  virtual std::shared_ptr<sightline::Geometry> BuildGlyphs(
    vtkDataSet* input, const sightline::GlyphRequest& request) = 0;

  /**
   * The SH order to draw of functions of order `order`: at most MaximumOrder (warning once
   * per build when it is odd).
   */
  int ApplyMaximumOrder(int order);

  /**
   * Prepares the glyphs of `source` with the shared per-point cache, reports dropped ones as
   * the glyphs of `label`, and counts the computed boxes.
   */
  sightline::PreparedSHGlyphs PrepareSHGlyphs(sightline::SHGlyphPreparation& preparation,
    const sightline::GlyphSource& source, const sightline::GlyphRequest& request,
    const std::string& label);

  /** The shared cache of the glyphs' boxes and amplitudes. */
  sightline::SHGlyphPreparation& GetGlyphPreparation();

  /**
   * Warns about glyphs with non-finite values in `label`, naming the first point.
   */
  void ReportDroppedGlyphs(const sightline::GlyphDrops& drops, const std::string& label);

  /**
   * Prepared SH glyphs as a kernel SHGlyphSet at their points' world centres, coloured and
   * intersected as this mapper is set (`volume`: a plain glyph set for volume rendering).
   * Null, with a warning, when no glyph is left.
   */
  std::shared_ptr<sightline::Geometry> MakeSHGlyphSet(
    vtkDataSet* input, const sightline::PreparedSHGlyphs& glyphs, bool volume = false);

  /**
   * Prepared ellipsoids as a kernel EllipsoidSet, coloured by direction, scalars or solid.
   */
  std::shared_ptr<sightline::Geometry> MakeEllipsoidSet(
    vtkDataSet* input, const sightline::PreparedEllipsoids& ellipsoids);
#endif

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
  int IntersectionMethod = INTERSECT_EXACT;
  double MarchingStepSize = 0.2;
  int MarchingBisectionSteps = 0;
  bool MarchingLinearInterpolation = true;
  bool MarchingCentreRefinement = true;
  double SubdivisionTolerance = 1e-4;
  vtkIdType LastComputedBoxes = 0;
  vtkIdType LastLooseBoxes = 0;
  bool FrustumCulling = false;
  /// World length of a normalised glyph radius of 1 in the last build.
  double WorldScale = 1.0;

private:
  vtkSightlineGlyphMapper(const vtkSightlineGlyphMapper&) = delete;
  void operator=(const vtkSightlineGlyphMapper&) = delete;

#ifndef __VTK_WRAP__
  /// The chosen points of the input, or false (after an error) when there are none.
  bool SelectPoints(vtkDataSet* input, std::vector<std::size_t>& points);
  /// World length of a normalised radius of 1: half the smallest voxel step for images.
  double ComputeWorldScale(vtkDataSet* input);
#endif

  class vtkGlyphInternals;
  std::unique_ptr<vtkGlyphInternals> GlyphInternals;
};

#endif
