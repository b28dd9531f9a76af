// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineWindowFrame.h"

#include "SightlineKernelConversions.h"
#include "SightlineTracer.h"

#include "vtkAbstractMapper3D.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkDataObject.h"
#include "vtkHardwareSelector.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkProp3D.h"
#include "vtkRenderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

namespace
{
// What a frame depends on besides the scene: the renderer's projection at its tiled aspect,
// the prop's matrix, the traced size and the renderer's lights as the kernel sees them.
std::vector<double> ViewKey(
  vtkRenderer* renderer, vtkMatrix4x4* propMatrix, int traceWidth, int traceHeight)
{
  std::vector<double> key;
  vtkCamera* camera = renderer->GetActiveCamera();
  vtkMatrix4x4* projection =
    camera->GetCompositeProjectionTransformMatrix(renderer->GetTiledAspectRatio(), -1, 1);
  key.insert(key.end(), &projection->Element[0][0], &projection->Element[0][0] + 16);
  key.insert(key.end(), &propMatrix->Element[0][0], &propMatrix->Element[0][0] + 16);
  key.push_back(traceWidth);
  key.push_back(traceHeight);
  const sightline::Lighting lighting =
    SightlineKernelConversions::MakeLighting(renderer->GetLights(), camera);
  for (const auto& light : lighting.lights)
  {
    key.insert(key.end(), { light.direction.x, light.direction.y, light.direction.z, light.color.r,
                            light.color.g, light.color.b, light.intensity });
  }
  return key;
}

// A key entry for a depth image the rays stop at (FNV-1a hash of its bits).
double DepthKey(const std::vector<float>& depth)
{
  std::uint64_t hash = 1469598103934665603ull;
  for (float d : depth)
  {
    std::uint32_t bits;
    std::memcpy(&bits, &d, sizeof(bits));
    hash = (hash ^ bits) * 1099511628211ull;
  }
  return static_cast<double>(hash >> 11); // exact in a double
}

SightlineWindowCompositor::Blending BlendingFor(SightlineTracer::Pass pass)
{
  switch (pass)
  {
    case SightlineTracer::Pass::Translucent:
      return SightlineWindowCompositor::Blending::Premultiplied; // writes no depth, as VTK's
    case SightlineTracer::Pass::Volumetric:
      return SightlineWindowCompositor::Blending::PremultipliedDepth;
    default:
      return SightlineWindowCompositor::Blending::Replace;
  }
}
} // namespace

//------------------------------------------------------------------------------
bool SightlineWindowFrame::SetInteractiveSubsampling(int step)
{
  step = std::clamp(step, 1, 16);
  const bool changed = step != this->InteractiveSubsampling;
  this->InteractiveSubsampling = step;
  return changed;
}

//------------------------------------------------------------------------------
bool SightlineWindowFrame::SetInteractiveUpdateRate(double rate)
{
  const bool changed = rate != this->InteractiveUpdateRate;
  this->InteractiveUpdateRate = rate;
  return changed;
}

//------------------------------------------------------------------------------
void SightlineWindowFrame::PrintSelf(std::ostream& os, vtkIndent indent) const
{
  os << indent << "InteractiveSubsampling: " << this->InteractiveSubsampling << "\n";
  os << indent << "InteractiveUpdateRate: " << this->InteractiveUpdateRate << "\n";
}

//------------------------------------------------------------------------------
SightlineWindowFrame::~SightlineWindowFrame()
{
  if (this->CountedRenderer)
  {
    this->CountedRenderer->RemoveObserver(this->FrameObserver);
  }
}

//------------------------------------------------------------------------------
void SightlineWindowFrame::CountFrames(vtkRenderer* renderer)
{
  if (this->CountedRenderer == renderer)
  {
    return;
  }
  if (this->CountedRenderer)
  {
    this->CountedRenderer->RemoveObserver(this->FrameObserver);
  }
  vtkNew<vtkCallbackCommand> count;
  count->SetClientData(this);
  count->SetCallback([](vtkObject*, unsigned long, void* self, void*)
    { ++static_cast<SightlineWindowFrame*>(self)->FrameNumber; });
  this->FrameObserver = renderer->AddObserver(vtkCommand::StartEvent, count);
  this->CountedRenderer = renderer;
  // This frame started before the observer: count it now.
  ++this->FrameNumber;
}

//------------------------------------------------------------------------------
void SightlineWindowFrame::Render(
  vtkAbstractMapper3D* mapper, SightlineTracer& tracer, vtkRenderer* renderer, vtkProp3D* prop)
{
  int width = 0, height = 0, x0 = 0, y0 = 0;
  renderer->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  if (width <= 0 || height <= 0)
  {
    vtkWarningWithObjectMacro(mapper, << "The viewport has no pixels (" << width << "x" << height
                                      << "); nothing to ray-trace.");
    return;
  }
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(renderer->GetRenderWindow());
  if (!window)
  {
    vtkErrorWithObjectMacro(
      mapper, << mapper->GetClassName() << " needs an OpenGL render window.");
    return;
  }

  // Trace fewer rays while the user drags; the still frame afterwards has every pixel.
  const int step = window->GetDesiredUpdateRate() > this->InteractiveUpdateRate
    ? this->InteractiveSubsampling
    : 1;
  mapper->InvokeEvent(vtkCommand::StartEvent, nullptr);
  tracer.SetView(prop, renderer->GetActiveCamera(), static_cast<double>(width) / height, step > 1);
  if (!tracer.UpdateScene())
  {
    mapper->InvokeEvent(vtkCommand::EndEvent, nullptr);
    return;
  }
  if (vtkHardwareSelector* selector = renderer->GetSelector())
  {
    this->RenderSelection(mapper, tracer, renderer, prop, selector, window, width, height);
    mapper->InvokeEvent(vtkCommand::EndEvent, nullptr);
    return;
  }

  const int traceWidth = (width + step - 1) / step;
  const int traceHeight = (height + step - 1) / step;

  // Translucent surfaces and volumes are drawn after the opaque geometry, whose depth is in
  // the window's render framebuffer: rays stop there. VTK's translucent pass draws into
  // framebuffers of its own (order-independent transparency, depth peeling), but the ray
  // tracer sorts its layers itself, so it reads from and blends into the render framebuffer;
  // other translucent geometry is then blended over it whatever its depth.
  const SightlineTracer::Pass pass = tracer.GetPass(prop);
  const bool behind = pass != SightlineTracer::Pass::Opaque;
  std::unique_ptr<SightlineWindowCompositor::RenderFramebufferBinding> binding;
  std::vector<float> depthLimit;
  if (behind)
  {
    binding = std::make_unique<SightlineWindowCompositor::RenderFramebufferBinding>(window);
    depthLimit = SightlineWindowCompositor::ReadDepth(
      window, x0, y0, width, height, step, traceWidth, traceHeight);
  }

  // Everything the frame depends on; an unchanged key reuses the last image.
  std::vector<double> key = ViewKey(renderer, prop->GetMatrix(), traceWidth, traceHeight);
  // The prop's time covers its property (and a volume's transfer functions).
  key.push_back(static_cast<double>(
    std::max({ tracer.GetSceneTime(), mapper->GetMTime(), prop->GetMTime() })));
  key.push_back(static_cast<double>(pass));
  if (behind)
  {
    key.push_back(DepthKey(depthLimit)); // what is behind changes the image
  }

  bool changed = false;
  if (key != this->Key)
  {
    this->Key.clear();
    if (!tracer.RayTrace(prop, renderer->GetActiveCamera(), renderer->GetLights(), traceWidth,
          traceHeight, this->Frame, behind ? &depthLimit : nullptr))
    {
      mapper->InvokeEvent(vtkCommand::EndEvent, nullptr);
      return;
    }
    this->Rgba = this->Frame.toRGBA8(sightline::vec3(0.0f));
    this->Key = std::move(key);
    changed = true;
  }

  if (behind)
  {
    // Blended over what is in the frame: once per frame, whatever the translucent pass's stages.
    this->CountFrames(renderer);
    if (this->BlendedFrame == this->FrameNumber && this->BlendedKey == this->Key)
    {
      mapper->InvokeEvent(vtkCommand::EndEvent, nullptr);
      return;
    }
    this->BlendedFrame = this->FrameNumber;
    this->BlendedKey = this->Key;
  }

  changed = changed || this->TexturesHoldSelection;
  this->TexturesHoldSelection = false;
  if (!this->Compositor.Draw(window, traceWidth, traceHeight, this->Rgba.data(),
        this->Frame.Depth.data(), changed, BlendingFor(pass)))
  {
    vtkErrorWithObjectMacro(mapper, << "Could not compile the compositing shader.");
  }
  mapper->InvokeEvent(vtkCommand::EndEvent, nullptr);
}

//------------------------------------------------------------------------------
void SightlineWindowFrame::RenderSelection(vtkAbstractMapper3D* mapper, SightlineTracer& tracer,
  vtkRenderer* renderer, vtkProp3D* prop, vtkHardwareSelector* selector,
  vtkOpenGLRenderWindow* window, int width, int height)
{
  const SightlineTracer::SelectionIds* ids = tracer.GetSelectionIds();
  if (!ids)
  {
    return; // not selectable (volumes): nothing drawn in selection passes
  }

  // Every pixel at full size, whatever the interaction; traced once for all the passes of a
  // selection (and for later selections while the view and scene hold).
  std::vector<double> key = ViewKey(renderer, prop->GetMatrix(), width, height);
  key.push_back(static_cast<double>(
    std::max({ tracer.GetSceneTime(), mapper->GetMTime(), prop->GetMTime() })));
  if (key != this->SelectionKey)
  {
    this->SelectionKey.clear();
    if (!tracer.RayTraceSelection(prop, renderer->GetActiveCamera(), renderer->GetLights(), width,
          height, this->SelectionFrame) ||
      this->SelectionFrame.Primitives.size() != this->SelectionFrame.pixelCount())
    {
      return;
    }
    this->SelectionKey = std::move(key);
  }

  selector->BeginRenderProp();
  const int pass = selector->GetCurrentPass();
  if (pass == vtkHardwareSelector::COMPOSITE_INDEX_PASS)
  {
    selector->RenderCompositeIndex(1); // one block, as vtkOpenGLPolyDataMapper says
  }
  // The selector renders the high 24 bits of ids only when someone reported ids that need them.
  selector->UpdateMaximumPointId(ids->MaximumPointId);
  selector->UpdateMaximumCellId(ids->MaximumCellId);

  // What each hit pixel shows in this pass: the selector's colour (actor, composite index and
  // process passes) or the id itself as 24-bit RGB, low byte in red (VTK 9.1's
  // vtkHardwareSelector decodes attribute ids without an offset: "nothing there" is the actor
  // pass's black). A primitive without an id for the selector's field association (a sphere in
  // no vertex cell, in a cell selection) is drawn black in the actor pass, with its depth: it
  // hides what is behind it but selects nothing. A prop pick (ActorPassOnly, as vtkPropPicker's)
  // asks for no ids: every primitive counts.
  const bool propsOnly = selector->GetActorPassOnly();
  const std::vector<vtkIdType>& selectable =
    selector->GetFieldAssociation() == vtkDataObject::FIELD_ASSOCIATION_POINTS ? ids->PointIds
                                                                               : ids->CellIds;
  const std::vector<vtkIdType>* attribute = nullptr;
  bool high = false;
  switch (pass)
  {
    case vtkHardwareSelector::POINT_ID_LOW24:
    case vtkHardwareSelector::POINT_ID_HIGH24:
      attribute = &ids->PointIds;
      high = pass == vtkHardwareSelector::POINT_ID_HIGH24;
      break;
    case vtkHardwareSelector::CELL_ID_LOW24:
    case vtkHardwareSelector::CELL_ID_HIGH24:
      attribute = &ids->CellIds;
      high = pass == vtkHardwareSelector::CELL_ID_HIGH24;
      break;
    default:
      break;
  }
  std::uint8_t propColor[3];
  const float* value = selector->GetPropColorValue();
  for (int c = 0; c < 3; ++c)
  {
    propColor[c] = static_cast<std::uint8_t>(std::lround(std::clamp(value[c], 0.0f, 1.0f) * 255.0f));
  }
  const sightline::Framebuffer& frame = this->SelectionFrame;
  this->SelectionRgba.assign(4 * frame.pixelCount(), 0);
  for (std::size_t i = 0; i < frame.pixelCount(); ++i)
  {
    const sightline::PixelPrimitive& hit = frame.Primitives[i];
    if (!hit.hit())
    {
      continue; // depth 1 there: the compositor discards the pixel
    }
    std::uint8_t* rgba = &this->SelectionRgba[4 * i];
    rgba[3] = 255;
    const bool hasId =
      propsOnly || (hit.primitive < selectable.size() && selectable[hit.primitive] >= 0);
    if (!attribute)
    {
      if (pass != vtkHardwareSelector::ACTOR_PASS || hasId)
      {
        std::copy(propColor, propColor + 3, rgba);
      }
      continue;
    }
    const vtkIdType id = hit.primitive < attribute->size() ? (*attribute)[hit.primitive] : -1;
    std::uint64_t encoded = id >= 0 ? static_cast<std::uint64_t>(id) : 0;
    if (high)
    {
      encoded >>= 24;
    }
    rgba[0] = static_cast<std::uint8_t>(encoded & 0xff);
    rgba[1] = static_cast<std::uint8_t>((encoded >> 8) & 0xff);
    rgba[2] = static_cast<std::uint8_t>((encoded >> 16) & 0xff);
  }
  // Exact values: replaced, not blended (the selector has turned blending and multisampling
  // off), nearest texels at the viewport's size, depth written and tested.
  if (!this->Compositor.Draw(window, width, height, this->SelectionRgba.data(),
        frame.Depth.data(), true, SightlineWindowCompositor::Blending::Replace))
  {
    vtkErrorWithObjectMacro(mapper, << "Could not compile the compositing shader.");
  }
  this->TexturesHoldSelection = true;
  selector->EndRenderProp();
}

//------------------------------------------------------------------------------
void SightlineWindowFrame::ReleaseGraphicsResources(vtkWindow* window)
{
  this->Compositor.ReleaseGraphicsResources(window);
}
