// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineSphericalFieldSource
 * @brief   Samples an analytic field or a layered Earth on a spherical grid.
 *
 * The output is a vtkRectilinearGrid in vtkSightlineSphericalVolumeMapper's default convention:
 * x = radius r, y = colatitude theta (radians, 0 on +z), z = azimuth phi (radians), with the
 * field as cell data named after it ("chi", "r2" or "density"), each cell sampled at its
 * coordinate midpoint (or as point data at the grid's points, OutputCellData off).
 *
 * Fields, defined on the ball of radius RadiusRange[1] = R:
 * - STEP: the radial step function of "Ray casting in spherical coordinates" (Chapter 6),
 *   chi_0.5 = 2 for r <= R/2, 1 for R/2 < r <= R;
 * - RADIUS_SQUARED: (r / R)^2, whose ray integrals are known in closed form;
 * - PREM_DENSITY: the Preliminary Reference Earth Model density in g/cm^3 (Dziewonski and
 *   Anderson 1981), r scaled so that R is the Earth's 6371 km, times 1 + PerturbationAmplitude
 *   sin^2(theta) cos(2 phi) in the mantle (between the core-mantle boundary and the Moho): a
 *   degree-2 lateral perturbation like those seismic tomography images.
 *
 * Radial breakpoints are uniform, unless AlignWithDiscontinuities is on (default): then every
 * radius where the field jumps (R/2 for STEP, PREM's layer boundaries) is a breakpoint and the
 * RadialResolution cells are shared among the layers by thickness (at least one each), so a
 * cell never straddles a jump. Off reproduces the thesis' benchmark grids, where the step falls
 * inside a cell.
 *
 * Pieces (pvbatch/pvserver ranks): the source can produce any sub-extent
 * (CAN_PRODUCE_SUB_EXTENT), so the pipeline turns a piece request into an UPDATE_EXTENT with
 * its extent translator; only that part of the grid is made (its coordinates and values). The
 * whole grid's breakpoints are computed first and then cut, so the alignment with the
 * discontinuities, and every value, is the whole grid's whatever the split. As for any
 * structured data set, neighbouring pieces share the points on their common face and split
 * the cells.
 *
 * @sa vtkSightlineSphericalVolumeMapper
 */
#ifndef vtkSightlineSphericalFieldSource_h
#define vtkSightlineSphericalFieldSource_h

#include "SightlineSourcesModule.h" // for export macro
#include "vtkRectilinearGridAlgorithm.h"

class SIGHTLINESOURCES_EXPORT vtkSightlineSphericalFieldSource : public vtkRectilinearGridAlgorithm
{
public:
  static vtkSightlineSphericalFieldSource* New();
  vtkTypeMacro(vtkSightlineSphericalFieldSource, vtkRectilinearGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum FieldKind
  {
    STEP = 0,
    RADIUS_SQUARED,
    PREM_DENSITY
  };

  ///@{
  /**
   * The field to sample. Default STEP.
   */
  vtkSetClampMacro(Field, int, STEP, PREM_DENSITY);
  vtkGetMacro(Field, int);
  void SetFieldToStep() { this->SetField(STEP); }
  void SetFieldToRadiusSquared() { this->SetField(RADIUS_SQUARED); }
  void SetFieldToPREMDensity() { this->SetField(PREM_DENSITY); }
  const char* GetFieldAsString();
  ///@}

  ///@{
  /**
   * Cells along r, theta and phi. Defaults 16, 16, 32.
   */
  vtkSetClampMacro(RadialResolution, int, 1, VTK_INT_MAX);
  vtkGetMacro(RadialResolution, int);
  vtkSetClampMacro(PolarResolution, int, 1, VTK_INT_MAX);
  vtkGetMacro(PolarResolution, int);
  vtkSetClampMacro(AzimuthalResolution, int, 1, VTK_INT_MAX);
  vtkGetMacro(AzimuthalResolution, int);
  ///@}

  ///@{
  /**
   * Ranges of r (default 0 to 1), theta (radians, default 0 to pi) and phi (radians, default
   * 0 to 2 pi). A smaller range gives a section: a shell, a cap or band, a wedge.
   */
  vtkSetVector2Macro(RadiusRange, double);
  vtkGetVector2Macro(RadiusRange, double);
  vtkSetVector2Macro(PolarRange, double);
  vtkGetVector2Macro(PolarRange, double);
  vtkSetVector2Macro(AzimuthRange, double);
  vtkGetVector2Macro(AzimuthRange, double);
  ///@}

  ///@{
  /**
   * Put a breakpoint at every radius where the field jumps. Default on.
   */
  vtkSetMacro(AlignWithDiscontinuities, vtkTypeBool);
  vtkGetMacro(AlignWithDiscontinuities, vtkTypeBool);
  vtkBooleanMacro(AlignWithDiscontinuities, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Relative amplitude of PREM_DENSITY's lateral perturbation in the mantle. Default 0.05.
   */
  vtkSetClampMacro(PerturbationAmplitude, double, -1.0, 1.0);
  vtkGetMacro(PerturbationAmplitude, double);
  ///@}

  ///@{
  /**
   * Write cell data (default) or point data.
   */
  vtkSetMacro(OutputCellData, vtkTypeBool);
  vtkGetMacro(OutputCellData, vtkTypeBool);
  vtkBooleanMacro(OutputCellData, vtkTypeBool);
  ///@}

protected:
  vtkSightlineSphericalFieldSource();
  ~vtkSightlineSphericalFieldSource() override = default;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Field = STEP;
  int RadialResolution = 16;
  int PolarResolution = 16;
  int AzimuthalResolution = 32;
  double RadiusRange[2] = { 0.0, 1.0 };
  double PolarRange[2];
  double AzimuthRange[2];
  vtkTypeBool AlignWithDiscontinuities = 1;
  double PerturbationAmplitude = 0.05;
  vtkTypeBool OutputCellData = 1;

private:
  vtkSightlineSphericalFieldSource(const vtkSightlineSphericalFieldSource&) = delete;
  void operator=(const vtkSightlineSphericalFieldSource&) = delete;
};

#endif
