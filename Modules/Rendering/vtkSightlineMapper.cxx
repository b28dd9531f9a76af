#include "vtkSightlineMapper.h"

#include "SightlineWindowCompositor.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkDataObject.h"
#include "vtkInformation.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkScalarsToColors.h"
#include "vtkTimerLog.h"

#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Framebuffer.h"
#include "sightline/core/Renderer.h"

#include <algorithm>
#include <exception>
#include <vector>

class vtkSightlineMapper::vtkInternals
{
public:
  // Geometry and BVH, rebuilt when the input, the mapper or its lookup table change.
  std::shared_ptr<sightline::Geometry> Geometry;
  std::unique_ptr<sightline::EmbreeScene> Scene;
  vtkTimeStamp BuildTime;
  double Bounds[6] = { 1, -1, 1, -1, 1, -1 };

  // Last window frame, reused while nothing that affects it changes.
  sightline::Framebuffer Frame;
  std::vector<double> FrameKey;
  std::vector<unsigned char> Rgba;

  // OpenGL resources for the window path.
  SightlineWindowCompositor Compositor;

  // Translucent actors trace against this empty opaque scene, with their own as the
  // translucent one.
  std::unique_ptr<sightline::EmbreeScene> EmptyScene;

  bool WarnedOpacity = false;
  bool WarnedPositionalLight = false;
};

namespace
{
sightline::Material MaterialFromProperty(vtkProperty* p)
{
  sightline::Material m;
  double c[3];
  p->GetDiffuseColor(c);
  m.color = sightline::vec3(c[0], c[1], c[2]);
  p->GetAmbientColor(c);
  m.ambientColor = sightline::vec3(c[0], c[1], c[2]);
  p->GetSpecularColor(c);
  m.specularColor = sightline::vec3(c[0], c[1], c[2]);
  m.ambient = static_cast<float>(p->GetAmbient());
  m.diffuse = static_cast<float>(p->GetDiffuse());
  m.specular = static_cast<float>(p->GetSpecular());
  m.specularPower = static_cast<float>(p->GetSpecularPower());
  if (p->GetInterpolation() == VTK_PBR)
  {
    m.model = sightline::ShadingModel::GltfDielectric;
    m.roughness = static_cast<float>(p->GetRoughness());
  }
  m.opacity = static_cast<float>(p->GetOpacity());
  return m;
}

} // namespace

//------------------------------------------------------------------------------
vtkSightlineMapper::vtkSightlineMapper()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkSightlineMapper::~vtkSightlineMapper() = default;

//------------------------------------------------------------------------------
int vtkSightlineMapper::FillInputPortInformation(int vtkNotUsed(port), vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  return 1;
}

//------------------------------------------------------------------------------
bool vtkSightlineMapper::UpdateScene()
{
  if (this->GetNumberOfInputConnections(0) < 1)
  {
    vtkErrorMacro(<< "No input connection: set one with SetInputConnection or SetInputDataObject.");
    return false;
  }
  if (!this->Static)
  {
    this->GetInputAlgorithm()->Update();
  }
  vtkDataObject* input = this->GetInputDataObject(0, 0);
  if (!input)
  {
    vtkErrorMacro(<< "The input is null.");
    return false;
  }

  vtkMTimeType changed = std::max(this->GetMTime(), input->GetMTime());
  if (this->ScalarVisibility && this->LookupTable)
  {
    changed = std::max(changed, this->LookupTable->GetMTime());
  }
  vtkInternals& in = *this->Internals;
  if (changed > in.BuildTime.GetMTime())
  {
    in.Scene.reset();
    in.Geometry.reset();
    vtkMath::UninitializeBounds(in.Bounds);
    try
    {
      vtkNew<vtkTimerLog> timer;
      timer->StartTimer();
      in.Geometry = this->BuildGeometry();
      timer->StopTimer();
      this->LastGeometrySeconds = timer->GetElapsedTime();
      if (in.Geometry && in.Geometry->size() > 0)
      {
        auto scene = std::make_unique<sightline::EmbreeScene>();
        scene->add(in.Geometry);
        scene->commit();
        this->LastBuildSeconds = scene->buildSeconds();
        in.Scene = std::move(scene);
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
    }
    in.BuildTime.Modified();
    in.FrameKey.clear();
  }
  return in.Scene != nullptr;
}

//------------------------------------------------------------------------------
double* vtkSightlineMapper::GetBounds()
{
  // UpdateScene reports a missing input: a renderer asks for bounds before it draws, and an
  // actor without bounds is culled before Render() could say why.
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
glm::dmat4 vtkSightlineMapper::ToKernelMatrix(vtkMatrix4x4* matrix)
{
  glm::dmat4 g;
  for (int row = 0; row < 4; ++row)
  {
    for (int col = 0; col < 4; ++col)
    {
      g[col][row] = matrix->GetElement(row, col); // GLM is column-major
    }
  }
  return g;
}

//------------------------------------------------------------------------------
sightline::Lighting vtkSightlineMapper::MakeLighting(vtkLightCollection* lights, vtkCamera* camera)
{
  double position[3], focal[3];
  camera->GetPosition(position);
  camera->GetFocalPoint(focal);
  const sightline::vec3 viewDirection(
    focal[0] - position[0], focal[1] - position[1], focal[2] - position[2]);
  if (!lights || lights->GetNumberOfItems() == 0)
  {
    return sightline::Lighting::headlight(viewDirection);
  }

  sightline::Lighting lighting;
  vtkCollectionSimpleIterator it;
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it))
  {
    if (!light->GetSwitch())
    {
      continue;
    }
    double from[3], to[3];
    if (light->LightTypeIsHeadlight())
    {
      std::copy(position, position + 3, from);
      std::copy(focal, focal + 3, to);
    }
    else if (light->LightTypeIsCameraLight())
    {
      // Camera lights are given in the camera's frame; VTK moves them with the camera.
      vtkMatrix4x4* m = camera->GetCameraLightTransformMatrix();
      double p[4] = { 0, 0, 0, 1 }, f[4] = { 0, 0, 0, 1 };
      light->GetPosition(p);
      light->GetFocalPoint(f);
      m->MultiplyPoint(p, p);
      m->MultiplyPoint(f, f);
      for (int i = 0; i < 3; ++i)
      {
        from[i] = p[i] / p[3];
        to[i] = f[i] / f[3];
      }
    }
    else
    {
      light->GetTransformedPosition(from);
      light->GetTransformedFocalPoint(to);
    }
    const sightline::vec3 direction(to[0] - from[0], to[1] - from[1], to[2] - from[2]);
    if (glm::length(direction) == 0.0f)
    {
      continue;
    }
    double color[3];
    light->GetDiffuseColor(color);
    lighting.lights.push_back({ glm::normalize(direction),
      sightline::vec3(color[0], color[1], color[2]), static_cast<float>(light->GetIntensity()) });
  }
  return lighting;
}

//------------------------------------------------------------------------------
bool vtkSightlineMapper::IsTranslucentFor(vtkActor* actor)
{
  return actor && actor->GetProperty()->GetOpacity() < 1.0 && this->SupportsTranslucency();
}

//------------------------------------------------------------------------------
bool vtkSightlineMapper::RayTrace(vtkActor* actor, vtkCamera* camera, vtkLightCollection* lights,
  int width, int height, sightline::Framebuffer& framebuffer, const std::vector<float>* depthLimit)
{
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
  const bool translucent = this->IsTranslucentFor(actor);
  if (actor->GetProperty()->GetOpacity() < 1.0 && !translucent && !this->Internals->WarnedOpacity)
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
  if (lights && !this->Internals->WarnedPositionalLight)
  {
    vtkCollectionSimpleIterator it;
    lights->InitTraversal(it);
    while (vtkLight* light = lights->GetNextLight(it))
    {
      if (light->GetSwitch() && light->GetPositional())
      {
        vtkWarningMacro(<< "Positional lights are treated as directional lights along their axis.");
        this->Internals->WarnedPositionalLight = true;
        break;
      }
    }
  }

  vtkInternals& in = *this->Internals;
  in.Geometry->material = MaterialFromProperty(actor->GetProperty());
  if (!translucent)
  {
    in.Geometry->material.opacity = 1.0f;
  }
  const sightline::dmat4 worldToClip =
    vtkSightlineMapper::ToKernelMatrix(camera->GetCompositeProjectionTransformMatrix(double(width) / height, -1, 1));
  sightline::RenderOptions options;
  options.objectToWorld = vtkSightlineMapper::ToKernelMatrix(actor->GetMatrix());
  options.shadows.mode = this->ShadowMode == SHADOWS_SOFT ? sightline::ShadowMode::Soft
    : this->ShadowMode == SHADOWS_HARD                    ? sightline::ShadowMode::Hard
                                                          : sightline::ShadowMode::None;
  options.shadows.samples = this->ShadowSamples;
  options.shadows.lightAngularRadius =
    static_cast<float>(vtkMath::RadiansFromDegrees(this->LightAngularRadius));
  this->ConfigureRender(options);
  options.depthLimit = depthLimit;
  const sightline::EmbreeScene* opaqueScene = in.Scene.get();
  if (translucent)
  {
    // The union of solids is drawn by the translucent path only.
    if (!in.EmptyScene)
    {
      in.EmptyScene = std::make_unique<sightline::EmbreeScene>();
      in.EmptyScene->commit();
    }
    options.translucent.scene = in.Scene.get();
    opaqueScene = in.EmptyScene.get();
  }
  options.progress = [this](double fraction)
  {
    this->UpdateProgress(fraction);
    return !this->AbortExecute;
  };
  try
  {
    const sightline::Camera view(worldToClip * options.objectToWorld, width, height);
    const sightline::RenderStatistics stats = sightline::Renderer().render(
      *opaqueScene, view, MakeLighting(lights, camera), framebuffer, options);
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
void vtkSightlineMapper::Render(vtkRenderer* renderer, vtkActor* actor)
{
  int width = 0, height = 0, x0 = 0, y0 = 0;
  renderer->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  if (width <= 0 || height <= 0)
  {
    vtkWarningMacro(<< "The viewport has no pixels (" << width << "x" << height
                    << "); nothing to ray-trace.");
    return;
  }
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(renderer->GetRenderWindow());
  if (!window)
  {
    vtkErrorMacro(<< "vtkSightlineMapper needs an OpenGL render window.");
    return;
  }
  vtkCamera* camera = renderer->GetActiveCamera();
  vtkInternals& in = *this->Internals;

  this->InvokeEvent(vtkCommand::StartEvent, nullptr);
  if (!this->UpdateScene())
  {
    this->InvokeEvent(vtkCommand::EndEvent, nullptr);
    return;
  }

  // Trace fewer rays while the user drags; the still frame afterwards has every pixel.
  const int step = SightlineWindowCompositor::TraceStep(
    window, this->InteractiveUpdateRate, this->InteractiveSubsampling);
  const int traceWidth = (width + step - 1) / step;
  const int traceHeight = (height + step - 1) / step;

  // Translucent actors are drawn in VTK's translucent pass: the opaque geometry is already in
  // the depth buffer, and rays stop there.
  const bool translucent = this->IsTranslucentFor(actor);
  std::vector<float> depthLimit;
  // VTK's translucent pass draws into framebuffers of its own (order-independent transparency,
  // or depth peeling). The ray tracer composites its layers itself, so it reads the opaque
  // depth from and blends into the window's render framebuffer directly; other translucent
  // geometry is then blended over the tubes whatever its depth.
  std::unique_ptr<SightlineWindowCompositor::RenderFramebufferBinding> binding;
  if (translucent)
  {
    binding = std::make_unique<SightlineWindowCompositor::RenderFramebufferBinding>(window);
    depthLimit = SightlineWindowCompositor::ReadDepth(
      window, x0, y0, width, height, step, traceWidth, traceHeight);
  }

  // Everything the frame depends on; an unchanged key reuses the last image.
  std::vector<double> key =
    SightlineWindowCompositor::ViewKey(renderer, actor->GetMatrix(), traceWidth, traceHeight);
  key.push_back(static_cast<double>(in.BuildTime.GetMTime()));
  key.push_back(static_cast<double>(actor->GetProperty()->GetMTime()));
  if (translucent)
  {
    // What is behind changes the image.
    key.push_back(SightlineWindowCompositor::DepthKey(depthLimit));
    key.push_back(1.0);
  }

  bool changed = false;
  if (key != in.FrameKey)
  {
    in.FrameKey.clear();
    if (!this->RayTrace(actor, camera, renderer->GetLights(), traceWidth, traceHeight, in.Frame,
          translucent ? &depthLimit : nullptr))
    {
      this->InvokeEvent(vtkCommand::EndEvent, nullptr);
      return;
    }
    in.Rgba = in.Frame.toRGBA8(sightline::vec3(0.0f));
    in.FrameKey = key;
    changed = true;
  }

  // Translucent surfaces write no depth, as VTK's alpha blending.
  if (!in.Compositor.Draw(window, traceWidth, traceHeight, in.Rgba.data(), in.Frame.Depth.data(),
        changed,
        translucent ? SightlineWindowCompositor::Blending::Premultiplied
                    : SightlineWindowCompositor::Blending::Replace))
  {
    vtkErrorMacro(<< "Could not compile the compositing shader.");
  }

  this->InvokeEvent(vtkCommand::EndEvent, nullptr);
}

//------------------------------------------------------------------------------
void vtkSightlineMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  this->Internals->Compositor.ReleaseGraphicsResources(window);
  this->Superclass::ReleaseGraphicsResources(window);
}

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
  os << indent << "InteractiveSubsampling: " << this->InteractiveSubsampling << "\n";
  os << indent << "InteractiveUpdateRate: " << this->InteractiveUpdateRate << "\n";
  os << indent << "NumberOfPrimitives: "
     << (this->Internals->Geometry ? this->Internals->Geometry->size() : 0) << "\n";
  os << indent << "LastGeometrySeconds: " << this->LastGeometrySeconds << "\n";
  os << indent << "LastBuildSeconds: " << this->LastBuildSeconds << "\n";
  os << indent << "LastFrameSeconds: " << this->LastFrameSeconds << "\n";
}
