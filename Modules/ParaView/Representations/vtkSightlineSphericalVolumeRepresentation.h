// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineSphericalVolumeRepresentation
 * @brief   ParaView's "Sightline Spherical Volume": exact ray marching through (r, theta, phi) or
 *          (rho, phi, z) cells of a rectilinear grid, with ParaView's transfer functions
 *
 * The colour (LookupTable) and opacity (ScalarOpacityFunction) transfer functions, the scalar
 * opacity unit distance, shading and the actor's transform come from vtkVolumeRepresentation,
 * as for ParaView's own "Volume". The grid's coordinates are read as spherical or cylindrical
 * ones by the vtkSightlineSphericalVolumeMapper this forwards to.
 *
 * On several MPI ranks, rank 0 traces the whole grid and the other ranks ask for nothing:
 * translucent pieces need compositing in visibility order, which IceT's depth compositing is
 * not.
 */
#ifndef vtkSightlineSphericalVolumeRepresentation_h
#define vtkSightlineSphericalVolumeRepresentation_h

#include "SightlineParaViewModule.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeRepresentation.h"

class vtkSightlineSphericalVolumeMapper;

class SIGHTLINEPARAVIEW_EXPORT vtkSightlineSphericalVolumeRepresentation
  : public vtkVolumeRepresentation
{
public:
  static vtkSightlineSphericalVolumeRepresentation* New();
  vtkTypeMacro(vtkSightlineSphericalVolumeRepresentation, vtkVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  int ProcessViewRequest(
    vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo) override;

  /// ParaView's ColorArrayName: the point or cell array to render.
  void SetInputArrayToProcess(
    int idx, int port, int connection, int fieldAssociation, const char* name) override;
  using Superclass::SetInputArrayToProcess;

  void SetShade(bool shade);
  void SetCoordinateSystem(int system);
  void SetAngleUnits(int units);
  void SetPolarAngle(int angle);
  void SetInterpolatePointData(int interpolate);
  void SetSampleDistance(double distance);
  void SetMinimumTransmittance(double transmittance);
  void SetInteractiveSubsampling(int step);

  vtkSightlineSphericalVolumeMapper* GetSphericalVolumeMapper();

protected:
  vtkSightlineSphericalVolumeRepresentation();
  ~vtkSightlineSphericalVolumeRepresentation() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  bool AddToView(vtkView* view) override;
  bool RemoveFromView(vtkView* view) override;

  vtkSmartPointer<vtkSightlineSphericalVolumeMapper> Mapper;
  vtkSmartPointer<vtkDataObject> Cache;

private:
  vtkSightlineSphericalVolumeRepresentation(
    const vtkSightlineSphericalVolumeRepresentation&) = delete;
  void operator=(const vtkSightlineSphericalVolumeRepresentation&) = delete;
};

#endif
