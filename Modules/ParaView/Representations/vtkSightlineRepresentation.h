// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineRepresentation
 * @brief   ParaView representation that draws its input with one of Sightline's ray-traced mappers
 *
 * The shared part of the Sightline Spheres, Tubes, SH Glyphs and Tensor Glyphs representations:
 * it keeps a shallow copy of the input (a data set or a composite; the mappers accept both),
 * hands it to the render view for delivery, and gives the delivered piece to the mapper when
 * the view renders. Colouring (ParaView's "Coloring" array, lookup table and MapScalars),
 * opacity, lighting and the actor's transform are forwarded to the mapper, its vtkProperty
 * and its vtkActor, so ParaView's colour maps, scalar bars and LUT editor work as for
 * "Surface". Subclasses only create their mapper and forward their own settings.
 *
 * The mapper writes colour and depth into ParaView's frame, so the ray-traced primitives
 * composite with ParaView's own outline, axes and surfaces.
 */
#ifndef vtkSightlineRepresentation_h
#define vtkSightlineRepresentation_h

#include "SightlineParaViewModule.h"
#include "vtkPVDataRepresentation.h"
#include "vtkSmartPointer.h"

class vtkActor;
class vtkProperty;
class vtkScalarsToColors;
class vtkSightlineMapper;

class SIGHTLINEPARAVIEW_EXPORT vtkSightlineRepresentation : public vtkPVDataRepresentation
{
public:
  vtkTypeMacro(vtkSightlineRepresentation, vtkPVDataRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  int ProcessViewRequest(
    vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo) override;
  void SetVisibility(bool visible) override;

  /**
   * ParaView's ColorArrayName: index 0 selects the array coloured through the lookup table; an
   * empty name turns scalar colouring off (the primitive's own colouring applies).
   */
  void SetInputArrayToProcess(
    int idx, int port, int connection, int fieldAssociation, const char* name) override;
  using Superclass::SetInputArrayToProcess;
  void SetLookupTable(vtkScalarsToColors* table);
  void SetMapScalars(int mapScalars);
  void SetInterpolateScalarsBeforeMapping(int interpolate);

  ///@{
  /// Forwarded to the vtkProperty.
  void SetOpacity(double opacity);
  void SetColor(double r, double g, double b);
  void SetDiffuseColor(double r, double g, double b);
  void SetAmbientColor(double r, double g, double b);
  void SetSpecularColor(double r, double g, double b);
  void SetAmbient(double value);
  void SetDiffuse(double value);
  void SetSpecular(double value);
  void SetSpecularPower(double value);
  void SetInterpolation(int interpolation);
  void SetRoughness(double value);
  ///@}

  ///@{
  /// Forwarded to the actor.
  void SetPosition(double x, double y, double z);
  void SetScale(double x, double y, double z);
  void SetOrientation(double x, double y, double z);
  void SetOrigin(double x, double y, double z);
  void SetUserTransform(const double matrix[16]);
  void SetPickable(int pickable);
  ///@}

  ///@{
  /// Forwarded to the mapper (vtkSightlineMapper): shadows and the interactive frame rate.
  void SetShadowMode(int mode);
  void SetShadowSamples(int samples);
  void SetLightAngularRadius(double degrees);
  void SetInteractiveSubsampling(int step);
  ///@}

  vtkSightlineMapper* GetSightlineMapper();
  vtkActor* GetActor();

protected:
  explicit vtkSightlineRepresentation(vtkSightlineMapper* mapper);
  ~vtkSightlineRepresentation() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  bool AddToView(vtkView* view) override;
  bool RemoveFromView(vtkView* view) override;

  /**
   * Called when scalar colouring is turned on (an array is selected) or off. The point and
   * tube mappers colour by scalars through vtkMapper::ScalarVisibility; the glyph mappers
   * have their own colouring modes and override this.
   */
  virtual void SetScalarColoring(bool on);

  /**
   * The array name a ParaView array property selected, or null for none: an empty name or
   * the "None" entry of an optional array's list.
   */
  static const char* SelectedArrayName(const char* name);

  vtkSmartPointer<vtkSightlineMapper> Mapper;
  vtkSmartPointer<vtkActor> Actor;
  vtkSmartPointer<vtkProperty> Property;
  vtkSmartPointer<vtkDataObject> Cache;
  double DataBounds[6];

private:
  vtkSightlineRepresentation(const vtkSightlineRepresentation&) = delete;
  void operator=(const vtkSightlineRepresentation&) = delete;
};

#endif
