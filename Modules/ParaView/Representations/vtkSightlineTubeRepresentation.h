// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineTubeRepresentation
 * @brief   ParaView's "Sightline Tubes": exact generalized tubes along polylines or a predecessor array
 *
 * Settings are forwarded to its vtkSightlineTubeMapper (see there); everything shared by the Sightline
 * representations (colouring, opacity, transform, shadows) is in vtkSightlineRepresentation.
 *
 * Translucent tubes on several MPI ranks ask the view for ordered compositing: each rank then
 * draws the union's surfaces inside its kd-tree region only, from every link reaching into the
 * region, and IceT blends the ranks front to back (vtkSightlineRepresentation::DrawRegion).
 * There a predecessor array's links are sent to the regions as two-point lines.
 */
#ifndef vtkSightlineTubeRepresentation_h
#define vtkSightlineTubeRepresentation_h

#include "SightlineParaViewModule.h"
#include "vtkSightlineRepresentation.h"

#include <string> // for std::string

class vtkSightlineTubeMapper;

class SIGHTLINEPARAVIEW_EXPORT vtkSightlineTubeRepresentation : public vtkSightlineRepresentation
{
public:
  static vtkSightlineTubeRepresentation* New();
  vtkTypeMacro(vtkSightlineTubeRepresentation, vtkSightlineRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetRadius(double radius);
  /// The point array of radii; empty: a constant radius.
  void SetRadiusArray(int idx, int port, int connection, int association, const char* name);
  /// How a selected radius array sets the radius (vtkSightlineTubeMapper::VaryRadiusModes).
  void SetVaryRadius(int mode);
  void SetRadiusScale(double scale);
  void SetRadiusFactor(double factor);
  /// The point array of predecessor ids (SWC-style trees); empty: the polylines.
  void SetPredecessorArray(int idx, int port, int connection, int association, const char* name);
  void SetLinkLayout(int layout);
  /// vtkSightlineTubeMapper::ChunkLinks and HiddenLinkCulling.
  void SetChunkLinks(int links);
  void SetHiddenLinkCulling(int on);

protected:
  vtkSightlineTubeRepresentation();
  ~vtkSightlineTubeRepresentation() override;
  bool NeedsOrderedCompositing() override;
  vtkSmartPointer<vtkUnstructuredGrid> RegionCells(vtkDataObject* piece) override;
  void DrawingRegionCells(bool on) override;
  vtkSightlineTubeMapper* GetTubeMapper();
  void UpdateVaryRadius();
  int VaryRadius = 2; // vtkSightlineTubeMapper::VARY_RADIUS_BY_ABSOLUTE_SCALAR
  bool HasRadiusArray = false;
  std::string PredecessorArray;

private:
  vtkSightlineTubeRepresentation(const vtkSightlineTubeRepresentation&) = delete;
  void operator=(const vtkSightlineTubeRepresentation&) = delete;
};

#endif
