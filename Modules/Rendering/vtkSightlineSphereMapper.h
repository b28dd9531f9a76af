// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineSphereMapper
 * @brief   Ray-traces one exact sphere per input point.
 *
 * Each point of a vtkPointSet (vtkPolyData, vtkUnstructuredGrid, ...) becomes a sphere whose
 * radius is taken from a point-data array (RadiusArrayName, times RadiusScale) or is the
 * constant Radius. Colours follow VTK's scalar colouring (ScalarVisibility, lookup table,
 * colour mode) or the actor's vtkProperty. Intersections are exact (no tessellation), so
 * silhouettes and depth are correct at any zoom.
 *
 * Bad input is reported, never fatal: points with a NaN position or a radius that is not
 * positive and finite are skipped with a warning naming the first offending point; a missing,
 * multi-component or wrongly sized radius array is an error and the constant Radius is used.
 *
 * Selection (vtkHardwareSelector): a sphere is picked as its input point (POINTS) and as the
 * vertex or poly-vertex cell holding that point, if any (CELLS); see vtkSightlineMapper.
 *
 * @sa vtkSightlineMapper vtkSightlineImageRenderer
 */
#ifndef vtkSightlineSphereMapper_h
#define vtkSightlineSphereMapper_h

#include "SightlineRenderingModule.h" // for export macro
#include "vtkSightlineMapper.h"

class SIGHTLINERENDERING_EXPORT vtkSightlineSphereMapper : public vtkSightlineMapper
{
public:
  static vtkSightlineSphereMapper* New();
  vtkTypeMacro(vtkSightlineSphereMapper, vtkSightlineMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Radius of every sphere when no radius array is used. Default 1.
   */
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  ///@}

  ///@{
  /**
   * Name of a one-component point-data array holding each sphere's radius, or null to use
   * Radius for all. Default null.
   */
  vtkSetStringMacro(RadiusArrayName);
  vtkGetStringMacro(RadiusArrayName);
  ///@}

  ///@{
  /**
   * Factor applied to the radii read from RadiusArrayName. Default 1.
   */
  vtkSetMacro(RadiusScale, double);
  vtkGetMacro(RadiusScale, double);
  ///@}

  /**
   * The largest radius these settings give a point of `data` (see vtkSightlineMapper).
   */
  double ComputeReach(vtkDataObject* data) override;

protected:
  vtkSightlineSphereMapper();
  ~vtkSightlineSphereMapper() override;

  const char* GetDrawnInputType() override { return "vtkPointSet"; }
  bool AppendsCompositeLeaves() override { return true; }
#ifndef __VTK_WRAP__
  std::shared_ptr<sightline::Geometry> BuildGeometry() override;
  /**
   * Selection: sphere i is input point i (skipped points have no sphere); its cell is the
   * vertex or poly-vertex cell holding the point (the first one), or none.
   */
  void ComputeSelectionIds(
    std::vector<vtkIdType>& pointIds, std::vector<vtkIdType>& cellIds) override;
#endif

  double Radius = 1.0;
  char* RadiusArrayName = nullptr;
  double RadiusScale = 1.0;

private:
  vtkSightlineSphereMapper(const vtkSightlineSphereMapper&) = delete;
  void operator=(const vtkSightlineSphereMapper&) = delete;
};

#endif
