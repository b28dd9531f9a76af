// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineTensorGlyphMapper
 * @brief   Ray-traces exact higher-order tensor glyphs (orders 0 to 12) from a tensor array.
 *
 * Each point with a symmetric Cartesian tensor T of even order n becomes the glyph whose
 * radius in direction w is |T(w)| = |T_{i1..in} w_i1 ... w_in| (Hlawitschka et al., "higher-order
 * tensor glyphs"; for n = 2 the Reynolds glyph x^T D x, for a stiffness tensor the
 * longitudinal modulus). Even-order tensors and even SH bands up to n span the same functions,
 * so each tensor is converted by an exact linear map to canonical SH coefficients and drawn by
 * the same glyph machinery as vtkSightlineSHGlyphMapper, its sibling: root-finding
 * intersection, boxes, shading, shadows, and vtkSightlineGlyphMapper's slicing,
 * normalisation, colouring and caching. There is no basis and no uncertainty volume.
 *
 * Tensor layouts (TensorLayout; AUTOMATIC picks by the number of components):
 * - SYMMETRIC_UNIQUE: the (n+1)(n+2)/2 unique components, one per monomial x^a y^b z^c,
 *   ordered by a descending, then b descending (n = 2: xx, xy, xz, yy, yz, zz, which is FSL's
 *   order; n = 4: xxxx, xxxy, xxxz, xxyy, xxyz, xxzz, xyyy, ...); each stands for the
 *   n!/(a! b! c!) equal entries of the full tensor. AUTOMATIC for 1, 15, 28, 45, 66, 91.
 * - FULL: all 3^n entries (index i1 + 3 i2 + 9 i3 + ...), e.g. a 3x3x3x3 stiffness tensor or
 *   VTK's 9-component tensors. A tensor that is not totally symmetric (a stiffness tensor has
 *   only minor and major symmetry) is drawn as its totally symmetric part, which has the same
 *   T(w). AUTOMATIC for 9, 81, 729.
 * - VTK_SYMMETRIC: VTK's 6-component symmetric tensors XX, YY, ZZ, XY, YZ, XZ (as
 *   vtkTensorGlyph reads them). AUTOMATIC for 6: note that this differs from
 *   SYMMETRIC_UNIQUE's order 2, so set the layout for FSL-style files.
 * - VOIGT: a 6x6 Voigt stiffness matrix (36 components, row-major, pairs 11, 22, 33, 23, 13,
 *   12), the way elastic constants are published. AUTOMATIC for 36.
 *
 * Second-order tensors can also be drawn as vtkTensorGlyph's ellipsoids (Shape ELLIPSOID): the
 * unit sphere mapped by the eigenvectors scaled by |eigenvalues| (at least 1/1000 of the
 * largest), intersected exactly; normalisation makes the longest semi-axis ScaleFactor. They
 * are built from the eigen-decomposition directly, without SH coefficients or SH boxes.
 *
 * Intersection (IntersectionMethod, see vtkSightlineGlyphMapper): EXACT (default) or the
 * tensor-glyph paper's own methods as baselines; ellipsoids are always intersected exactly.
 *
 * @sa vtkSightlineGlyphMapper vtkSightlineSHGlyphMapper vtkTensorGlyph
 */
#ifndef vtkSightlineTensorGlyphMapper_h
#define vtkSightlineTensorGlyphMapper_h

#include "SightlineRenderingModule.h" // for export macro
#include "vtkSightlineGlyphMapper.h"

class SIGHTLINERENDERING_EXPORT vtkSightlineTensorGlyphMapper : public vtkSightlineGlyphMapper
{
public:
  static vtkSightlineTensorGlyphMapper* New();
  vtkTypeMacro(vtkSightlineTensorGlyphMapper, vtkSightlineGlyphMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Point-data array of tensors, or null (default) for the active point tensors, or, when
   * there are none, the active point scalars (what vtkNIFTIImageReader produces).
   */
  vtkSetStringMacro(TensorArrayName);
  vtkGetStringMacro(TensorArrayName);
  ///@}

  enum TensorLayouts
  {
    LAYOUT_AUTOMATIC = 0,
    LAYOUT_SYMMETRIC_UNIQUE,
    LAYOUT_FULL,
    LAYOUT_VTK_SYMMETRIC,
    LAYOUT_VOIGT
  };

  ///@{
  /**
   * How the tensor array's components are laid out (see the class documentation). Default
   * LAYOUT_AUTOMATIC.
   */
  vtkSetClampMacro(TensorLayout, int, LAYOUT_AUTOMATIC, LAYOUT_VOIGT);
  vtkGetMacro(TensorLayout, int);
  void SetTensorLayoutToAutomatic() { this->SetTensorLayout(LAYOUT_AUTOMATIC); }
  void SetTensorLayoutToSymmetricUnique() { this->SetTensorLayout(LAYOUT_SYMMETRIC_UNIQUE); }
  void SetTensorLayoutToFull() { this->SetTensorLayout(LAYOUT_FULL); }
  void SetTensorLayoutToVTKSymmetric() { this->SetTensorLayout(LAYOUT_VTK_SYMMETRIC); }
  void SetTensorLayoutToVoigt() { this->SetTensorLayout(LAYOUT_VOIGT); }
  const char* GetTensorLayoutAsString();
  ///@}

  /**
   * The order the last build read (-1 before the first).
   */
  vtkGetMacro(TensorOrder, int);

  enum Shapes
  {
    SHAPE_TENSOR_FUNCTION = 0, ///< radius |T(w)|, every order
    SHAPE_ELLIPSOID            ///< vtkTensorGlyph's ellipsoid, order 2 only
  };

  ///@{
  /**
   * Glyph shape. Default SHAPE_TENSOR_FUNCTION.
   */
  vtkSetClampMacro(Shape, int, SHAPE_TENSOR_FUNCTION, SHAPE_ELLIPSOID);
  vtkGetMacro(Shape, int);
  void SetShapeToTensorFunction() { this->SetShape(SHAPE_TENSOR_FUNCTION); }
  void SetShapeToEllipsoid() { this->SetShape(SHAPE_ELLIPSOID); }
  const char* GetShapeAsString();
  ///@}

protected:
  vtkSightlineTensorGlyphMapper();
  ~vtkSightlineTensorGlyphMapper() override;

#ifndef __VTK_WRAP__
  std::shared_ptr<sightline::Geometry> BuildGlyphs(
    vtkDataSet* input, const sightline::GlyphRequest& request) override;
#endif

  char* TensorArrayName = nullptr;
  int TensorLayout = LAYOUT_AUTOMATIC;
  int TensorOrder = -1;
  int Shape = SHAPE_TENSOR_FUNCTION;

private:
  vtkSightlineTensorGlyphMapper(const vtkSightlineTensorGlyphMapper&) = delete;
  void operator=(const vtkSightlineTensorGlyphMapper&) = delete;
};

#endif
