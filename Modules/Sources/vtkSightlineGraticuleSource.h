// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineGraticuleSource
 * @brief   Parallels and meridians on a sphere, as polylines: the graticule over a globe.
 *
 * The output is vtkPolyData polylines on the sphere of Radius (km for Earth models) centred at
 * the origin, in the frame of vtkSightlineNetCDFSphericalReader's grids: +z the north pole,
 * +x longitude 0 on the equator, +y 90 E. Parallels every Step degrees of latitude and
 * meridians every Step degrees of longitude, at multiples of Step, inside LatitudeRange and
 * LongitudeRange (degrees east; a range may pass 180 or 360, e.g. 150 to 210 for a regional
 * model across the antimeridian). The poles are points and get no parallel; a whole turn of
 * longitude gets each meridian once. Lines are sampled every 1/SamplesPerDegree degree.
 *
 * Draw it with vtkSightlineTubeMapper (exact tubes: in a window and in GL-free images alike,
 * the "Sightline Tubes" representation in ParaView) or as ordinary lines. With a non-zero
 * FacingDirection only the points on the hemisphere that direction points to are kept (the
 * side a camera there sees), each visible run of a line a polyline of its own, so that lines
 * on the far side do not show through a translucent volume.
 *
 * A point array "Latitude" and "Longitude" (degrees) is added for colouring.
 *
 * @sa vtkSightlineNetCDFSphericalReader vtkSightlineSphericalVolumeMapper
 */
#ifndef vtkSightlineGraticuleSource_h
#define vtkSightlineGraticuleSource_h

#include "SightlineSourcesModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class SIGHTLINESOURCES_EXPORT vtkSightlineGraticuleSource : public vtkPolyDataAlgorithm
{
public:
  static vtkSightlineGraticuleSource* New();
  vtkTypeMacro(vtkSightlineGraticuleSource, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The sphere's radius. Default 6371 (the Earth in km). */
  vtkSetClampMacro(Radius, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Radius, double);
  ///@}

  ///@{
  /** Degrees between lines. Default 30. */
  vtkSetClampMacro(Step, double, 0.1, 180.0);
  vtkGetMacro(Step, double);
  ///@}

  ///@{
  /** Latitudes covered, in degrees (clamped to [-90, 90]). Default -90 to 90. */
  vtkSetVector2Macro(LatitudeRange, double);
  vtkGetVector2Macro(LatitudeRange, double);
  ///@}

  ///@{
  /** Longitudes covered, in degrees east, at most one turn. Default 0 to 360. */
  vtkSetVector2Macro(LongitudeRange, double);
  vtkGetVector2Macro(LongitudeRange, double);
  ///@}

  ///@{
  /** Points per degree along each line. Default 2. */
  vtkSetClampMacro(SamplesPerDegree, double, 0.01, 100.0);
  vtkGetMacro(SamplesPerDegree, double);
  ///@}

  ///@{
  /** Keep only the hemisphere this direction points to; (0, 0, 0) (default) keeps all. */
  vtkSetVector3Macro(FacingDirection, double);
  vtkGetVector3Macro(FacingDirection, double);
  ///@}

protected:
  vtkSightlineGraticuleSource();
  ~vtkSightlineGraticuleSource() override = default;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

private:
  vtkSightlineGraticuleSource(const vtkSightlineGraticuleSource&) = delete;
  void operator=(const vtkSightlineGraticuleSource&) = delete;

  double Radius = 6371.0;
  double Step = 30.0;
  double LatitudeRange[2] = { -90.0, 90.0 };
  double LongitudeRange[2] = { 0.0, 360.0 };
  double SamplesPerDegree = 2.0;
  double FacingDirection[3] = { 0.0, 0.0, 0.0 };
};

#endif
