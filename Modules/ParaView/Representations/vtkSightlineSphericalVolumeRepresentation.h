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
 * On several MPI ranks the view blends the ranks' images in visibility order (ParaView's
 * ordered compositing) and each rank draws one box of space:
 * - each rank asks for its piece of the grid as ParaView splits structured data (by extent);
 * - the ranks assemble the whole grid's breakpoints (not its values) and cut the section's
 *   world box into one box per rank (recursive halving along the longest side, the same on
 *   every rank), which they give the view as their ordered-compositing bounds;
 * - every rank receives from the others the cells that may meet its box
 *   (vtkSightlineSphericalVolumeMapper::ComputeCellRangeInBox, a conservative (r, theta, phi)
 *   range, one cell wider when shading reads the gradients) and draws them with every ray
 *   clipped to its box (the outer faces at infinity). A box across a full circle's azimuth
 *   seam gets the run of cells across it, assembled as one grid whose azimuths go on past the
 *   seam by a turn, not every azimuth.
 * A ray's emission and absorption over the boxes it crosses, blended front to back, are those
 * of the whole ray, so the image is the one-process image; no rank holds the whole grid. This
 * is redone only when a piece, the coordinate settings or the actor's matrix change. Pieces
 * that do not cover the grid (or bad coordinates) are reported, and nothing is drawn.
 */
#ifndef vtkSightlineSphericalVolumeRepresentation_h
#define vtkSightlineSphericalVolumeRepresentation_h

#include "SightlineParaViewModule.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeRepresentation.h"

#include <vector> // for std::vector

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
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  bool AddToView(vtkView* view) override;
  bool RemoveFromView(vtkView* view) override;

  vtkSmartPointer<vtkSightlineSphericalVolumeMapper> Mapper;
  vtkSmartPointer<vtkDataObject> Cache;
  int WholeExtent[6] = { 0, -1, 0, -1, 0, -1 }; ///< the pipeline's whole extent of the grid
  double SampleDistance = 0.0;                  ///< as set; 0: the whole grid's automatic one

  /// On several ranks: this rank's box of a partition of the section (all ranks together,
  /// collective) and the cells that may meet it, gathered from the ranks' pieces into
  /// RegionGrid. Returns whether the partition is valid (the same answer on every rank).
  bool Partition();
  vtkSmartPointer<vtkDataObject> RegionGrid;
  double RegionBox[6];      ///< this rank's box, finite
  double Region[6];         ///< the same with the faces on the partition's outside at infinity
  bool Partitioned = false; ///< RegionGrid and the boxes are valid
  std::vector<double> PartitionKey; ///< what the partition was made from, to redo it on change

private:
  vtkSightlineSphericalVolumeRepresentation(
    const vtkSightlineSphericalVolumeRepresentation&) = delete;
  void operator=(const vtkSightlineSphericalVolumeRepresentation&) = delete;
};

#endif
