// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineMapper
 * @brief   Abstract mapper that ray-traces exact primitives into a VTK render window.
 *
 * vtkSightlineMapper is the pattern every Sightline primitive follows. A subclass only turns
 * its input into a kernel geometry (BuildGeometry()); this class owns everything else:
 *
 * - an Embree BVH over the geometry, rebuilt only when the input, the mapper or its lookup
 *   table change;
 * - ray tracing with the renderer's active camera at the viewport's size, through the same
 *   world-to-clip matrix VTK's OpenGL rendering uses (actor transforms, parallel projection,
 *   window centre and view shear included), with the renderer's lights and the actor's
 *   vtkProperty;
 * - writing colour and depth into the OpenGL frame with a full-viewport quad, so the
 *   ray-traced primitives are depth-composited with ordinary VTK actors in either order;
 * - the GL-free path (RayTrace()), used by vtkSightlineImageRenderer, which produces the same
 *   pixels without a window.
 *
 * Frames are cached: redrawing an unchanged view re-uses the last image. While the window
 * asks for an interactive frame rate (vtkRenderWindow::GetDesiredUpdateRate() above
 * InteractiveUpdateRate) the mapper traces every InteractiveSubsampling-th pixel in each
 * direction and upsamples, then traces the full image once interaction stops.
 *
 * Progress: ProgressEvent is invoked (on the calling thread) while a frame is traced.
 *
 * Shading follows the actor's vtkProperty: Phong with its ambient/diffuse/specular terms, or,
 * with SetInterpolationToPBR(), a glTF dielectric BRDF with the property's roughness. Shadows
 * (ShadowMode) are off by default: then no shadow ray is traced at all; hard shadows trace one
 * ray per light, soft shadows ShadowSamples rays into a spherical light of
 * LightAngularRadius degrees.
 *
 * Opacity: mappers whose primitives are solids (SupportsTranslucency(), e.g. the tube mapper)
 * honour vtkProperty opacity below 1 by drawing only the outer surfaces of the union of their
 * solids, front to back (no interior surfaces where they overlap). In a window they are drawn
 * in VTK's translucent pass: rays stop at the depth of the opaque geometry already drawn, and
 * the image is alpha-blended over the frame without writing depth. The mapper sorts its own
 * surfaces exactly; other translucent actors (order-independent transparency or depth
 * peeling) are blended over it regardless of depth. Other mappers render opaque with a
 * warning.
 *
 * Input: a dataset of the type the subclass draws, or a composite dataset
 * (vtkMultiBlockDataSet, vtkPartitionedDataSet, vtkPartitionedDataSetCollection) of them, as
 * ParaView passes. Point-set mappers (spheres, tubes) draw the union of the non-empty leaves;
 * image mappers (glyphs) draw one leaf, the first with a warning when there are several.
 * Leaves of another type are left out with an error naming their type. An input without
 * points (or no input at all) draws nothing, quietly, and GetBounds() is then uninitialized
 * (vtkMath::AreBoundsInitialized() is false).
 *
 * Scalar colouring gives every primitive the colour of its point (or cell), mapped through
 * the lookup table; InterpolateScalarsBeforeMapping has no meaning for ray-traced primitives
 * (they have no texture coordinates) and is ignored, so colours are the same with it on, as
 * ParaView sets it.
 *
 * Selection: the mapper takes part in VTK's hardware selection (vtkHardwareSelector,
 * vtkRenderedAreaPicker-style area selection, ParaView's selection, vtkPropPicker's hardware
 * path). With renderer->GetSelector() set, the primitives are traced once more at the full
 * viewport size with the primitive of every pixel recorded (sightline::RenderOptions::
 * primitiveIds; normal frames record nothing), and each selection pass draws, instead of shaded
 * colour, the value the pass asks for: the selector's prop colour (actor, composite index and
 * process passes) or the picked primitive's input point or cell id as 24-bit RGB (low and
 * high passes), with the primitive's window depth, so ordinary actors in front still win.
 * Translucent actors are selected at their nearest surface. Which input ids a primitive stands
 * for is the subclass's (ComputeSelectionIds(); by default primitive i is point i and has no
 * cell).
 *
 * Limitations: positional and spot lights are treated as directional lights along their axis;
 * translucent surfaces cast no shadows.
 *
 * @sa vtkSightlineSphereMapper vtkSightlineImageRenderer
 */
#ifndef vtkSightlineMapper_h
#define vtkSightlineMapper_h

#include "SightlineRenderingModule.h" // for export macro
#include "SightlineTracer.h"          // for the interface the window frame and image renderer use
#include "vtkMapper.h"

#ifndef __VTK_WRAP__
#include <memory> // for std::shared_ptr
#include <string> // for std::string
#include <vector> // for std::vector
namespace sightline
{
class EmbreeScene;
class Framebuffer;
class Geometry;
struct RenderOptions;
}
#endif

class vtkCamera;
class vtkDataSet;
class vtkLightCollection;
class vtkPointSet;

class SIGHTLINERENDERING_EXPORT vtkSightlineMapper
  : public vtkMapper
  , public SightlineTracer
{
public:
  vtkTypeMacro(vtkSightlineMapper, vtkMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Ray-trace the primitives for this actor and draw colour and depth into the current
   * viewport. Called by vtkActor during the opaque pass.
   */
  void Render(vtkRenderer* renderer, vtkActor* actor) override;

  /**
   * Release the OpenGL textures and shader this mapper holds for the window.
   */
  void ReleaseGraphicsResources(vtkWindow* window) override;

  /**
   * Bounds of the primitives (not only of the input points: a sphere's radius counts), so
   * vtkRenderer::ResetCamera frames them.
   */
  double* GetBounds() VTK_SIZEHINT(6) override;
  using vtkAbstractMapper3D::GetBounds;

  /**
   * Always 0: ray-traced primitives have no texture coordinates, so scalars are mapped to
   * colours per point (or cell) whatever InterpolateScalarsBeforeMapping says.
   */
  int CanUseTextureMapForColoring(vtkDataObject* input) override;

  /**
   * The mapper's own geometry has no translucent parts; vtkActor makes the whole actor
   * translucent when its property's opacity is below 1 (see the class documentation).
   */
  bool HasOpaqueGeometry() override { return true; }
  bool HasTranslucentPolygonalGeometry() override { return false; }

  /**
   * The primitives can be picked with vtkHardwareSelector (see the class documentation).
   */
  bool GetSupportsSelection() override { return true; }

  /**
   * Whether this actor is drawn translucent: its property's opacity is below 1 and this
   * mapper's primitives support it.
   */
  bool IsTranslucentFor(vtkActor* actor);

  ///@{
  /**
   * Pixel step used while the render window asks for an interactive frame rate
   * (1 disables subsampling), clamped to [1, 16]. Default 2.
   */
  void SetInteractiveSubsampling(int step);
  int GetInteractiveSubsampling();
  ///@}

  enum ShadowModes
  {
    SHADOWS_OFF = 0,
    SHADOWS_HARD,
    SHADOWS_SOFT
  };

  ///@{
  /**
   * Shadows cast by the primitives onto each other, from every light. Default SHADOWS_OFF.
   */
  vtkSetClampMacro(ShadowMode, int, SHADOWS_OFF, SHADOWS_SOFT);
  vtkGetMacro(ShadowMode, int);
  void SetShadowModeToOff() { this->SetShadowMode(SHADOWS_OFF); }
  void SetShadowModeToHard() { this->SetShadowMode(SHADOWS_HARD); }
  void SetShadowModeToSoft() { this->SetShadowMode(SHADOWS_SOFT); }
  const char* GetShadowModeAsString();
  ///@}

  ///@{
  /**
   * Soft shadows: rays per pixel and light (default 16), and the angular radius of the
   * spherical lights in degrees (default 8.6, about 0.15 rad; larger gives wider penumbrae).
   */
  vtkSetClampMacro(ShadowSamples, int, 1, 1024);
  vtkGetMacro(ShadowSamples, int);
  vtkSetClampMacro(LightAngularRadius, double, 0.0, 45.0);
  vtkGetMacro(LightAngularRadius, double);
  ///@}

  ///@{
  /**
   * The box of world space this mapper draws: xmin, xmax, ymin, ymax, zmin, zmax, faces
   * possibly infinite. Every ray is clipped to it, so that each MPI rank draws only its region
   * of a kd-tree partition and the ranks' images, blended front to back in the regions'
   * visibility order, give the one-process image, translucent unions included
   * (vtkSightlineTubeRepresentation sets it under ParaView's ordered compositing). Default:
   * all of space. A NaN or a min above its max is an error, and nothing is drawn.
   */
  vtkSetVector6Macro(Region, double);
  vtkGetVector6Macro(Region, double);
  void SetRegionToAllOfSpace();
  ///@}

  /**
   * How far beyond its points a primitive drawn from `data` (a point set or a composite of
   * them) reaches with this mapper's settings: a sphere's or tube's largest radius, 0 for no
   * points. Negative where the primitives are not centred on points (glyph images): such data
   * cannot be split into regions by its points. A radius array that is missing or malformed
   * counts as the constant radius (the render reports it). Used to pad each MPI rank's region
   * so that it holds every primitive reaching into it.
   */
  virtual double ComputeReach(vtkDataObject* vtkNotUsed(data)) { return -1.0; }

  ///@{
  /**
   * Desired update rate (frames per second) above which a frame counts as interactive.
   * vtkRenderWindowInteractor asks for 15 while the user drags and 0.0001 when still.
   * Default 1.
   */
  void SetInteractiveUpdateRate(double rate);
  double GetInteractiveUpdateRate();
  ///@}

  /**
   * Number of primitives in the last geometry built from the input (after invalid ones
   * were dropped).
   */
  vtkIdType GetNumberOfPrimitives();

  /**
   * Seconds the last ray-traced frame took, the last geometry build from the input
   * (BuildGeometry: e.g. glyph boxes) and the last BVH build over it.
   */
  vtkGetMacro(LastFrameSeconds, double);
  vtkGetMacro(LastGeometrySeconds, double);
  vtkGetMacro(LastBuildSeconds, double);
  /**
   * Whether the last frame or pick traced only the outer part of the geometry
   * (BuildOuterGeometry(): dense tubes seen from outside).
   */
  vtkGetMacro(LastFrameOuter, bool);

  ///@{
  /**
   * Bytes of the last geometry built from the input (the kernel's Geometry::memoryBytes: for
   * tubes 20 bytes per link with the default layout) and of its BVH (Embree's allocations
   * during the build, measured through its memory monitor); 0 when nothing is drawn. Both
   * count the outer part too where there is one (BuildOuterGeometry()), and the BVH only the
   * scenes built so far (the whole geometry's is built on first use then). Their
   * sum is what this mapper holds for ray tracing besides its input (per MPI rank: its piece).
   */
  vtkTypeInt64 GetGeometryMemoryBytes();
  vtkTypeInt64 GetBVHMemoryBytes();
  ///@}

#ifndef __VTK_WRAP__
  /**
   * The point sets of `data`: itself, or every leaf of a composite (no flattening, no
   * messages); what ComputeReach reads.
   */
  static std::vector<vtkPointSet*> PointSets(vtkDataObject* data);

  /**
   * GL-free path: ray-trace the primitives of `actor` (a vtkActor) as `camera` sees them in an
   * image of width x height pixels (aspect width/height), lit by `lights` (VTK's automatic
   * headlight when null or empty), into `framebuffer`. Returns false (after reporting an
   * error) if nothing could be rendered. The window path uses this same function.
   */
  bool RayTrace(vtkProp3D* actor, vtkCamera* camera, vtkLightCollection* lights, int width,
    int height, sightline::Framebuffer& framebuffer,
    const std::vector<float>* depthLimit = nullptr) override;
#endif

protected:
  vtkSightlineMapper();
  ~vtkSightlineMapper() override;

#ifndef __VTK_WRAP__
  /**
   * Build the kernel geometry from the current input. Report bad input with vtkErrorMacro
   * or vtkWarningMacro naming the problem, and return the valid part (or nullptr when nothing
   * is valid). Called only when the input, the mapper or the lookup table changed.
   */
  virtual std::shared_ptr<sightline::Geometry> BuildGeometry() = 0;

  /**
   * A smaller geometry whose nearest hit equals `whole`'s for every ray starting outside
   * whole.bounds() (sightline::outerLinks for dense tubes), or null (the default). When there
   * is one, opaque frames and picks from a view whose near plane lies outside those bounds,
   * with the Region all of space, trace it; other frames trace the whole geometry, whose BVH
   * is then built on first use. Called after each BuildGeometry().
   */
  virtual std::shared_ptr<sightline::Geometry> BuildOuterGeometry(
    const sightline::Geometry& vtkNotUsed(whole))
  {
    return nullptr;
  }

  /**
   * Whether the geometry is a union of solids that can be drawn translucent
   * (sightline::Geometry::insideIntervals). Default false.
   */
  virtual bool SupportsTranslucency() { return false; }

  /**
   * Lets a subclass add what its primitives need to the render options of a frame (e.g. the
   * volume geometries of uncertainty glyphs). Called after the geometry is current; shadows,
   * transform and progress are already set.
   */
  virtual void ConfigureRender(sightline::RenderOptions& vtkNotUsed(options)) {}

  /**
   * Hardware selection: the input point id and cell id (-1 for none) of every primitive of the
   * geometry BuildGeometry() returned (GetGeometry()), in the kernel's primitive order. Called
   * once after each geometry build, on the first selection that needs it; `pointIds` and
   * `cellIds` arrive sized to the primitive count and filled with -1. The default makes
   * primitive i point i.
   */
  virtual void ComputeSelectionIds(
    std::vector<vtkIdType>& pointIds, std::vector<vtkIdType>& cellIds);

  /**
   * The geometry of the last build (null when nothing is drawn), for ComputeSelectionIds().
   */
  sightline::Geometry* GetGeometry();

  /**
   * The one place where every Sightline mapper checks a point array against the points it
   * describes: false (after an error naming `label`, its tuple count and the point count,
   * ending with `consequence`) when the array is missing, has not exactly one tuple per point,
   * or has fewer than `components` components (other than exactly `components` when
   * `exactComponents`).
   */
  bool CheckPointArray(vtkDataArray* array, const std::string& label, vtkIdType points,
    int components, const char* consequence, bool exactComponents = false);

  /**
   * With appended composite leaves: the id in GetDrawnInput() of the first point of each
   * leaf (a single 0 otherwise), for point ids that a leaf's arrays hold.
   */
  const std::vector<vtkIdType>& GetLeafPointOffsets();

#endif

  /**
   * The input as the one dataset this mapper draws (SightlineMapperInput): a dataset of
   * GetDrawnInputType() as it is, a composite's non-empty leaves appended
   * (AppendsCompositeLeaves()) or its first one, or nullptr when there is nothing to draw
   * (no input, no points). Does not update the pipeline: UpdateScene() does, before
   * BuildGeometry().
   */
  vtkDataSet* GetDrawnInput();

  /**
   * The VTK class of the datasets this mapper draws (default "vtkDataSet") and whether the
   * leaves of a composite input are all drawn, appended into one dataset (default false: one
   * leaf). Constant for a mapper class.
   */
  virtual const char* GetDrawnInputType() { return "vtkDataSet"; }
  virtual bool AppendsCompositeLeaves() { return false; }

  /**
   * Whether BuildGeometry() pulls its input from the upstream pipeline itself, piece by piece
   * (vtkSightlineTubeMapper::StreamedPieces): then UpdateScene() neither updates the input
   * whole nor needs it to have points, and rebuilds when an upstream algorithm changed.
   * Default false.
   */
  virtual bool PullsInputPieces() { return false; }

  int FillInputPortInformation(int port, vtkInformation* info) override;

  int ShadowMode = SHADOWS_OFF;
  int ShadowSamples = 16;
  double LightAngularRadius = 8.6;
  double Region[6];
  double LastFrameSeconds = 0.0;
  double LastGeometrySeconds = 0.0;
  double LastBuildSeconds = 0.0;
  bool LastFrameOuter = false;

private:
  vtkSightlineMapper(const vtkSightlineMapper&) = delete;
  void operator=(const vtkSightlineMapper&) = delete;

#ifndef __VTK_WRAP__
  // SightlineTracer, for the window frame and vtkSightlineImageRenderer.
  Pass GetPass(vtkProp3D* prop) override;
  // Brings the geometry and BVH up to date with the input; false when there is nothing to draw.
  bool UpdateScene() override;
  /// The BVH of the whole geometry, built here on first use when there is an outer part.
  const sightline::EmbreeScene* WholeScene();
  vtkMTimeType GetSceneTime() override;
  const SelectionIds* GetSelectionIds() override;
  bool RayTraceSelection(vtkProp3D* prop, vtkCamera* camera, vtkLightCollection* lights,
    int width, int height, sightline::Framebuffer& framebuffer) override;
  // RayTrace and RayTraceSelection.
  bool Trace(vtkProp3D* prop, vtkCamera* camera, vtkLightCollection* lights, int width,
    int height, sightline::Framebuffer& framebuffer, const std::vector<float>* depthLimit,
    bool selection);
#endif

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
