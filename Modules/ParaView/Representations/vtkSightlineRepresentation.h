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
class vtkAlgorithmOutput;
class vtkProperty;
class vtkScalarsToColors;
class vtkSightlineMapper;
class vtkUnstructuredGrid;

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
   * Hands the view's piece (from `producer`) to the mapper at REQUEST_RENDER; `inInfo` is the
   * view's request. Subclasses that draw other data on some frames (the tubes' region pieces
   * under ordered compositing) override it.
   */
  virtual void SetMapperInput(vtkInformation* inInfo, vtkAlgorithmOutput* producer);

  /**
   * Whether the view blends the ranks' images in the visibility order of its kd-tree regions
   * (ParaView's ordered compositing, on several ranks), and then this rank's region in `region`
   * (xmin, xmax, ymin, ymax, zmin, zmax) with the faces on the outside of all regions pushed
   * to infinity: the regions then tile all of space. Valid at REQUEST_RENDER. The same on
   * every rank, so a collective step may follow.
   */
  static bool GetOrderedCompositingRegion(vtkInformation* inInfo, double region[6]);

  /**
   * Whether this representation needs the view to blend the ranks' images in visibility order
   * (translucent tubes). Default false. Any representation whose mapper's primitives sit on
   * points (spheres, tubes) is drawn by region whenever the view does so (see the class
   * documentation).
   */
  virtual bool NeedsOrderedCompositing() { return false; }

  /**
   * The cells that carry the piece's primitives to the ranks' regions, as one unstructured
   * grid with the point data: by default a vertex per point of every leaf (spheres).
   */
  virtual vtkSmartPointer<vtkUnstructuredGrid> RegionCells(vtkDataObject* piece);

  /**
   * Called with true before the mapper draws a region's cells, with false before it draws the
   * view's piece again (the tubes then ignore their predecessor array, whose ids are the
   * piece's).
   */
  virtual void DrawingRegionCells(bool vtkNotUsed(on)) {}

  /// An unstructured grid on the points and point data of `leaf`, without cells yet.
  static vtkSmartPointer<vtkUnstructuredGrid> CellsOnPoints(class vtkPointSet* leaf);

  /// The output of `append` (its inputs: the cells of each leaf), or an empty grid for none.
  static vtkSmartPointer<vtkUnstructuredGrid> AppendedCells(class vtkAppendFilter* append);

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
  /// Whether the primitives sit on points, so that they can be sent to regions by their cells.
  bool DrawsByRegion();

  /// Moves every primitive reaching into a rank's region to that rank (the regions padded by
  /// the largest reach, cells assigned to every padded region they meet) and draws them
  /// clipped to the region. Collective over the ranks.
  void DrawRegion(vtkDataObject* piece, const double region[6], vtkInformation* inInfo);

  vtkSmartPointer<vtkDataObject> RegionPiece; ///< this rank's cells under ordered compositing
  vtkMTimeType RegionCutsTime = 0;
  vtkMTimeType RegionPieceTime = 0;
  double RegionReach = -1.0;

  vtkSightlineRepresentation(const vtkSightlineRepresentation&) = delete;
  void operator=(const vtkSightlineRepresentation&) = delete;
};

#endif
