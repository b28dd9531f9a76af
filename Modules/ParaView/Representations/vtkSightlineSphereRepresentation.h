// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineSphereRepresentation
 * @brief   ParaView's "Sightline Spheres": one exact sphere per input point
 *
 * Settings are forwarded to its vtkSightlineSphereMapper (see there); everything shared by the Sightline
 * representations (colouring, opacity, transform, shadows) is in vtkSightlineRepresentation.
 */
#ifndef vtkSightlineSphereRepresentation_h
#define vtkSightlineSphereRepresentation_h

#include "SightlineParaViewModule.h"
#include "vtkSightlineRepresentation.h"

class vtkSightlineSphereMapper;

class SIGHTLINEPARAVIEW_EXPORT vtkSightlineSphereRepresentation : public vtkSightlineRepresentation
{
public:
  static vtkSightlineSphereRepresentation* New();
  vtkTypeMacro(vtkSightlineSphereRepresentation, vtkSightlineRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Radius of every sphere when no radius array is selected.
  void SetRadius(double radius);
  /// The point array of radii (5-element form of ParaView array properties); empty: constant.
  void SetRadiusArray(int idx, int port, int connection, int association, const char* name);
  void SetRadiusScale(double scale);

protected:
  vtkSightlineSphereRepresentation();
  ~vtkSightlineSphereRepresentation() override;
  vtkSightlineSphereMapper* GetSphereMapper();

private:
  vtkSightlineSphereRepresentation(const vtkSightlineSphereRepresentation&) = delete;
  void operator=(const vtkSightlineSphereRepresentation&) = delete;
};

#endif
