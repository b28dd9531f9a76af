// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineMapper.h"

#include "SightlineKernelConversions.h"
#include "SightlineMapperInput.h"
#include "SightlineWindowFrame.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkScalarsToColors.h"
#include "vtkTimerLog.h"

#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Framebuffer.h" // for sightline::Framebuffer
#include "sightline/core/Renderer.h"

#include <algorithm>
#include <exception>
#include <limits>
#include <vector>

class vtkSightlineMapper::vtkInternals
{
public:
  // Geometry and BVH, rebuilt when the input, the mapper or its lookup table change.
  std::shared_ptr<sightline::Geometry> Geometry;
  std::unique_ptr<sightline::EmbreeScene> Scene; ///< built on first use when there is Outer
  // BuildOuterGeometry's part of Geometry (null: none) and its BVH.
  std::shared_ptr<sightline::Geometry> Outer;
  std::unique_ptr<sightline::EmbreeScene> OuterScene;
  vtkTimeStamp BuildTime;
  double Bounds[6] = { 1, -1, 1, -1, 1, -1 };

  // The window path: frame cache, compositing, interactive subsampling.
  SightlineWindowFrame Window;

  // Translucent actors trace against this empty opaque scene, with their own as the
  // translucent one.
  std::unique_ptr<sightline::EmbreeScene> EmptyScene;

  // The input as the dataset drawn; made on first use, with the subclass's policy.
  std::unique_ptr<SightlineMapperInput> Input;
  SightlineMapperInput& InputOf(vtkSightlineMapper* self)
  {
    if (!this->Input)
    {
      this->Input = std::make_unique<SightlineMapperInput>(self->GetDrawnInputType(),
        self->AppendsCompositeLeaves() ? SightlineMapperInput::Leaves::Append
                                       : SightlineMapperInput::Leaves::First);
    }
    return *this->Input;
  }
  // Input ids of the primitives, for hardware selection; computed on the first selection
  // after a build.
  SightlineTracer::SelectionIds Selection;
  vtkTimeStamp SelectionTime;

  bool WarnedOpacity = false;
  bool WarnedPositionalLight = false;
};

namespace
{
// The latest modification time of the algorithms upstream of `algorithm` (their data objects
// included, as a vtkTrivialProducer reports them): what says that a pulled input changed
// without updating it.
vtkMTimeType UpstreamTime(vtkAlgorithm* algorithm)
{
  vtkMTimeType latest = 0;
  for (int port = 0; port < algorithm->GetNumberOfInputPorts(); ++port)
  {
    for (int c = 0; c < algorithm->GetNumberOfInputConnections(port); ++c)
    {
      if (vtkAlgorithm* producer = algorithm->GetInputAlgorithm(port, c))
      {
        latest = std::max({ latest, producer->GetMTime(), UpstreamTime(producer) });
      }
    }
  }
  return latest;
}
} // namespace

//------------------------------------------------------------------------------
vtkSightlineMapper::vtkSightlineMapper()
  : Internals(new vtkInternals)
{
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 6; ++i)
  {
    this->Region[i] = i % 2 ? inf : -inf;
  }
}

//------------------------------------------------------------------------------
std::vector<vtkPointSet*> vtkSightlineMapper::PointSets(vtkDataObject* data)
{
  return SightlineMapperInput::PointSets(data);
}

//------------------------------------------------------------------------------
void vtkSightlineMapper::SetRegionToAllOfSpace()
{
  const double inf = std::numeric_limits<double>::infinity();
  this->SetRegion(-inf, inf, -inf, inf, -inf, inf);
}

//------------------------------------------------------------------------------
vtkSightlineMapper::~vtkSightlineMapper() = default;

//------------------------------------------------------------------------------
int vtkSightlineMapper::FillInputPortInformation(int vtkNotUsed(port), vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), this->GetDrawnInputType());
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  // Without an input the mapper draws nothing; updating it is no error.
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
bool vtkSightlineMapper::UpdateScene()
{
  // No input, or one without points, draws nothing, quietly: ParaView creates mappers before
  // data arrives, and an empty block is ordinary.
  vtkInternals& in = *this->Internals;
  SightlineMapperInput& input = in.InputOf(this);
  const bool pulls = this->PullsInputPieces();
  vtkDataSet* drawn = pulls ? nullptr : input.Get(this, !this->Static);

  vtkMTimeType changed =
    std::max(this->GetMTime(), pulls ? UpstreamTime(this) : input.GetInputTime(this));
  if (this->ScalarVisibility && this->LookupTable)
  {
    changed = std::max(changed, this->LookupTable->GetMTime());
  }
  if (changed > in.BuildTime.GetMTime())
  {
    in.Scene.reset();
    in.OuterScene.reset();
    in.Outer.reset();
    in.Geometry.reset();
    vtkMath::UninitializeBounds(in.Bounds);
    try
    {
      vtkNew<vtkTimerLog> timer;
      timer->StartTimer();
      in.Geometry = drawn || pulls ? this->BuildGeometry() : nullptr;
      if (in.Geometry && in.Geometry->size() > 0)
      {
        in.Outer = this->BuildOuterGeometry(*in.Geometry);
      }
      timer->StopTimer();
      this->LastGeometrySeconds = timer->GetElapsedTime();
      if (in.Geometry && in.Geometry->size() > 0)
      {
        if (in.Outer && in.Outer->size() > 0)
        {
          in.OuterScene = std::make_unique<sightline::EmbreeScene>();
          in.OuterScene->add(in.Outer);
          in.OuterScene->commit();
          this->LastBuildSeconds = in.OuterScene->buildSeconds();
        }
        else
        {
          in.Outer.reset();
          this->LastBuildSeconds = 0.0;
          this->WholeScene();
        }
        const sightline::Box3 box = in.Geometry->bounds();
        for (int axis = 0; axis < 3; ++axis)
        {
          in.Bounds[2 * axis] = box.lower[axis];
          in.Bounds[2 * axis + 1] = box.upper[axis];
        }
      }
    }
    catch (const std::exception& e)
    {
      vtkErrorMacro(<< "Could not build the ray-tracing scene: " << e.what());
      in.Geometry.reset();
      in.Scene.reset();
      in.Outer.reset();
      in.OuterScene.reset();
    }
    in.BuildTime.Modified();
  }
  return in.Scene != nullptr || in.OuterScene != nullptr;
}

//------------------------------------------------------------------------------
const sightline::EmbreeScene* vtkSightlineMapper::WholeScene()
{
  vtkInternals& in = *this->Internals;
  if (!in.Scene && in.Geometry && in.Geometry->size() > 0)
  {
    try
    {
      auto scene = std::make_unique<sightline::EmbreeScene>();
      scene->add(in.Geometry);
      scene->commit();
      this->LastBuildSeconds += scene->buildSeconds();
      in.Scene = std::move(scene);
    }
    catch (const std::exception& e)
    {
      vtkErrorMacro(<< "Could not build the ray-tracing scene: " << e.what());
    }
  }
  return in.Scene.get();
}

//------------------------------------------------------------------------------
vtkDataSet* vtkSightlineMapper::GetDrawnInput()
{
  return this->Internals->InputOf(this).Get(this, false);
}

//------------------------------------------------------------------------------
const std::vector<vtkIdType>& vtkSightlineMapper::GetLeafPointOffsets()
{
  return this->Internals->InputOf(this).GetLeafPointOffsets();
}

//------------------------------------------------------------------------------
int vtkSightlineMapper::CanUseTextureMapForColoring(vtkDataObject* vtkNotUsed(input))
{
  return 0;
}

//------------------------------------------------------------------------------
double* vtkSightlineMapper::GetBounds()
{
  // Uninitialized bounds without an input or geometry (UpdateScene reports bad input, not
  // emptiness): a renderer asks for bounds before it draws.
  this->UpdateScene();
  std::copy(this->Internals->Bounds, this->Internals->Bounds + 6, this->Bounds);
  return this->Bounds;
}

//------------------------------------------------------------------------------
vtkIdType vtkSightlineMapper::GetNumberOfPrimitives()
{
  const auto& geometry = this->Internals->Geometry;
  return geometry ? static_cast<vtkIdType>(geometry->size()) : 0;
}

//------------------------------------------------------------------------------
vtkTypeInt64 vtkSightlineMapper::GetGeometryMemoryBytes()
{
  const vtkInternals& in = *this->Internals;
  return static_cast<vtkTypeInt64>(
    (in.Geometry ? in.Geometry->memoryBytes() : 0) + (in.Outer ? in.Outer->memoryBytes() : 0));
}

//------------------------------------------------------------------------------
vtkTypeInt64 vtkSightlineMapper::GetBVHMemoryBytes()
{
  const vtkInternals& in = *this->Internals;
  return static_cast<vtkTypeInt64>(
    (in.Scene ? in.Scene->bvhBytes() : 0) + (in.OuterScene ? in.OuterScene->bvhBytes() : 0));
}

//------------------------------------------------------------------------------
bool vtkSightlineMapper::IsTranslucentFor(vtkActor* actor)
{
  return actor && actor->GetProperty()->GetOpacity() < 1.0 && this->SupportsTranslucency();
}

//------------------------------------------------------------------------------
bool vtkSightlineMapper::RayTrace(vtkProp3D* prop, vtkCamera* camera, vtkLightCollection* lights,
  int width, int height, sightline::Framebuffer& framebuffer, const std::vector<float>* depthLimit)
{
  return this->Trace(prop, camera, lights, width, height, framebuffer, depthLimit, false);
}

//------------------------------------------------------------------------------
bool vtkSightlineMapper::RayTraceSelection(vtkProp3D* prop, vtkCamera* camera,
  vtkLightCollection* lights, int width, int height, sightline::Framebuffer& framebuffer)
{
  return this->Trace(prop, camera, lights, width, height, framebuffer, nullptr, true);
}

//------------------------------------------------------------------------------
sightline::Geometry* vtkSightlineMapper::GetGeometry()
{
  return this->Internals->Geometry.get();
}

//------------------------------------------------------------------------------
void vtkSightlineMapper::ComputeSelectionIds(
  std::vector<vtkIdType>& pointIds, std::vector<vtkIdType>& vtkNotUsed(cellIds))
{
  for (std::size_t i = 0; i < pointIds.size(); ++i)
  {
    pointIds[i] = static_cast<vtkIdType>(i);
  }
}

//------------------------------------------------------------------------------
const SightlineTracer::SelectionIds* vtkSightlineMapper::GetSelectionIds()
{
  vtkInternals& in = *this->Internals;
  if (!in.Geometry)
  {
    return nullptr;
  }
  if (in.SelectionTime.GetMTime() < in.BuildTime.GetMTime())
  {
    SelectionIds& ids = in.Selection;
    // One per selectable element: a primitive, or a tube chunk's link.
    const std::size_t n = in.Geometry->selectionCount();
    ids.PointIds.assign(n, -1);
    ids.CellIds.assign(n, -1);
    this->ComputeSelectionIds(ids.PointIds, ids.CellIds);
    ids.PointIds.resize(n, -1); // whatever a subclass did, one per element
    ids.CellIds.resize(n, -1);
    ids.MaximumPointId = ids.PointIds.empty()
      ? -1
      : *std::max_element(ids.PointIds.begin(), ids.PointIds.end());
    ids.MaximumCellId =
      ids.CellIds.empty() ? -1 : *std::max_element(ids.CellIds.begin(), ids.CellIds.end());
    in.SelectionTime.Modified();
  }
  return &in.Selection;
}

//------------------------------------------------------------------------------
bool vtkSightlineMapper::Trace(vtkProp3D* prop, vtkCamera* camera, vtkLightCollection* lights,
  int width, int height, sightline::Framebuffer& framebuffer, const std::vector<float>* depthLimit,
  bool selection)
{
  auto* actor = vtkActor::SafeDownCast(prop);
  if (!actor || !camera)
  {
    vtkErrorMacro(<< "RayTrace needs an actor and a camera.");
    return false;
  }
  if (width <= 0 || height <= 0)
  {
    vtkErrorMacro(<< "Cannot ray-trace an image of " << width << "x" << height << " pixels.");
    return false;
  }
  framebuffer.resize(width, height);
  if (!this->UpdateScene())
  {
    return false;
  }
  // A selection pass traces a translucent union as opaque solids: the nearest hit is the
  // union's nearest surface.
  const bool translucent = !selection && this->IsTranslucentFor(actor);
  if (actor->GetProperty()->GetOpacity() < 1.0 && !this->IsTranslucentFor(actor) &&
    !this->Internals->WarnedOpacity)
  {
    vtkWarningMacro(<< "Property opacity " << actor->GetProperty()->GetOpacity() << " is not supported by "
                    << this->GetClassName() << "; the primitives are rendered opaque.");
    this->Internals->WarnedOpacity = true;
  }
  if (depthLimit && depthLimit->size() != static_cast<std::size_t>(width) * height)
  {
    vtkErrorMacro(<< "The depth limit has " << depthLimit->size() << " values for " << width << "x"
                  << height << " pixels.");
    return false;
  }
  sightline::dvec3 regionLower, regionUpper;
  if (!SightlineKernelConversions::ToKernelRegion(this, this->Region, regionLower, regionUpper))
  {
    return false;
  }
  if (!this->Internals->WarnedPositionalLight &&
    SightlineKernelConversions::HasPositionalLight(lights))
  {
    vtkWarningMacro(<< "Positional lights are treated as directional lights along their axis.");
    this->Internals->WarnedPositionalLight = true;
  }

  vtkInternals& in = *this->Internals;
  in.Geometry->material = SightlineKernelConversions::MaterialFromProperty(actor->GetProperty());
  if (!translucent)
  {
    in.Geometry->material.opacity = 1.0f;
  }
  using SightlineKernelConversions::ToKernelMatrix;
  const sightline::dmat4 worldToClip =
    ToKernelMatrix(camera->GetCompositeProjectionTransformMatrix(double(width) / height, -1, 1));
  sightline::RenderOptions options;
  options.objectToWorld = ToKernelMatrix(actor->GetMatrix());
  // Selection passes draw ids, not shading: no shadow rays.
  options.shadows.mode = selection           ? sightline::ShadowMode::None
    : this->ShadowMode == SHADOWS_SOFT       ? sightline::ShadowMode::Soft
    : this->ShadowMode == SHADOWS_HARD       ? sightline::ShadowMode::Hard
                                             : sightline::ShadowMode::None;
  options.shadows.samples = this->ShadowSamples;
  options.shadows.lightAngularRadius =
    static_cast<float>(vtkMath::RadiansFromDegrees(this->LightAngularRadius));
  this->ConfigureRender(options);
  options.depthLimit = depthLimit;
  options.primitiveIds = selection;
  options.regionLower = regionLower;
  options.regionUpper = regionUpper;
  const sightline::Camera view(worldToClip * options.objectToWorld, width, height);
  // The outer part draws what the whole draws for rays that start outside its bounds: opaque
  // views whose near plane (where rays start) lies outside them, nothing clipped away.
  sightline::Box3 nearPlane;
  for (double px : { 0.0, double(width) })
    for (double py : { 0.0, double(height) })
      nearPlane.extend(sightline::vec3(view.unproject(px, py, 0.0)));
  const sightline::Box3 whole = in.Geometry->bounds();
  const bool outside = nearPlane.upper.x < whole.lower.x || nearPlane.lower.x > whole.upper.x ||
    nearPlane.upper.y < whole.lower.y || nearPlane.lower.y > whole.upper.y ||
    nearPlane.upper.z < whole.lower.z || nearPlane.lower.z > whole.upper.z;
  // The region is in world coordinates: its box must hold the geometry's, moved there.
  sightline::dvec3 worldLower(std::numeric_limits<double>::infinity()), worldUpper(-worldLower);
  for (int corner = 0; corner < 8; ++corner)
  {
    const sightline::dvec3 p(corner & 1 ? whole.upper.x : whole.lower.x,
      corner & 2 ? whole.upper.y : whole.lower.y, corner & 4 ? whole.upper.z : whole.lower.z);
    const sightline::dvec3 world(options.objectToWorld * sightline::dvec4(p, 1.0));
    worldLower = glm::min(worldLower, world);
    worldUpper = glm::max(worldUpper, world);
  }
  const bool unclipped = glm::all(glm::lessThanEqual(regionLower, worldLower)) &&
    glm::all(glm::greaterThanEqual(regionUpper, worldUpper));
  const bool outer = in.OuterScene && !translucent && outside && unclipped;
  if (outer)
  {
    in.Outer->material = in.Geometry->material;
  }
  const sightline::EmbreeScene* opaqueScene = outer ? in.OuterScene.get() : this->WholeScene();
  if (!opaqueScene)
  {
    return false;
  }
  this->LastFrameOuter = outer;
  if (translucent)
  {
    // The union of solids is drawn by the translucent path only.
    if (!in.EmptyScene)
    {
      in.EmptyScene = std::make_unique<sightline::EmbreeScene>();
      in.EmptyScene->commit();
    }
    options.translucent.scene = opaqueScene;
    opaqueScene = in.EmptyScene.get();
  }
  options.progress = SightlineKernelConversions::ProgressCallback(this);
  try
  {
    const sightline::RenderStatistics stats = sightline::Renderer().render(
      *opaqueScene, view, SightlineKernelConversions::MakeLighting(lights, camera), framebuffer, options);
    this->LastFrameSeconds = stats.seconds;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Ray tracing failed: " << e.what());
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
SightlineTracer::Pass vtkSightlineMapper::GetPass(vtkProp3D* prop)
{
  return this->IsTranslucentFor(vtkActor::SafeDownCast(prop)) ? Pass::Translucent : Pass::Opaque;
}

//------------------------------------------------------------------------------
vtkMTimeType vtkSightlineMapper::GetSceneTime()
{
  return this->Internals->BuildTime.GetMTime();
}

//------------------------------------------------------------------------------
void vtkSightlineMapper::Render(vtkRenderer* renderer, vtkActor* actor)
{
  this->Internals->Window.Render(this, *this, renderer, actor);
}

//------------------------------------------------------------------------------
void vtkSightlineMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  this->Internals->Window.ReleaseGraphicsResources(window);
  this->Superclass::ReleaseGraphicsResources(window);
}

//------------------------------------------------------------------------------
sightlineWindowFrameSettingsMacro(vtkSightlineMapper, Internals->Window)

//------------------------------------------------------------------------------
const char* vtkSightlineMapper::GetShadowModeAsString()
{
  switch (this->ShadowMode)
  {
    case SHADOWS_HARD:
      return "Hard";
    case SHADOWS_SOFT:
      return "Soft";
    default:
      return "Off";
  }
}

//------------------------------------------------------------------------------
void vtkSightlineMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ShadowMode: " << this->GetShadowModeAsString() << "\n";
  os << indent << "ShadowSamples: " << this->ShadowSamples << "\n";
  os << indent << "LightAngularRadius: " << this->LightAngularRadius << " degrees\n";
  os << indent << "Region: " << this->Region[0] << " " << this->Region[1] << " " << this->Region[2]
     << " " << this->Region[3] << " " << this->Region[4] << " " << this->Region[5] << "\n";
  this->Internals->Window.PrintSelf(os, indent);
  os << indent << "NumberOfPrimitives: "
     << (this->Internals->Geometry ? this->Internals->Geometry->size() : 0) << "\n";
  os << indent << "LastGeometrySeconds: " << this->LastGeometrySeconds << "\n";
  os << indent << "LastBuildSeconds: " << this->LastBuildSeconds << "\n";
  os << indent << "LastFrameSeconds: " << this->LastFrameSeconds << "\n";
}

//------------------------------------------------------------------------------
bool vtkSightlineMapper::CheckPointArray(vtkDataArray* array, const std::string& label,
  vtkIdType points, int components, const char* consequence, bool exactComponents)
{
  if (!array)
  {
    vtkErrorMacro(<< "The " << label << " is not in the input's point data; " << consequence
                  << ".");
    return false;
  }
  if (array->GetNumberOfTuples() != points)
  {
    vtkErrorMacro(<< "The " << label << " has " << array->GetNumberOfTuples() << " tuples for "
                  << points << " points (one per point is needed); " << consequence << ".");
    return false;
  }
  if (array->GetNumberOfComponents() < components ||
    (exactComponents && array->GetNumberOfComponents() != components))
  {
    vtkErrorMacro(<< "The " << label << " has " << array->GetNumberOfComponents()
                  << " components where " << components << (exactComponents ? " is" : " are")
                  << " read; " << consequence << ".");
    return false;
  }
  return true;
}
