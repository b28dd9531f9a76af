// SPDX-License-Identifier: BSD-3-Clause
// The window side of every Sightline mapper: the one render loop that traces a prop at the
// viewport's size (every InteractiveSubsampling-th pixel while the user drags), reads the depth
// drawn before it when its pass needs it, reuses the last frame while nothing it depends on
// changed, and draws colour and depth through SightlineWindowCompositor. Also owns the
// interactive-subsampling settings the mappers expose.
// Private to the Rendering module (not wrapped, not installed).
#pragma once

#include "SightlineWindowCompositor.h"

#include "vtkIndent.h"
#include "vtkWeakPointer.h"

#include "sightline/core/Framebuffer.h"

#include <cstdint>
#include <ostream>
#include <vector>

class SightlineTracer;
class vtkAbstractMapper3D;
class vtkHardwareSelector;
class vtkOpenGLRenderWindow;
class vtkProp3D;
class vtkRenderer;
class vtkWindow;

class SightlineWindowFrame
{
public:
  SightlineWindowFrame() = default;
  ~SightlineWindowFrame();
  SightlineWindowFrame(const SightlineWindowFrame&) = delete;
  SightlineWindowFrame& operator=(const SightlineWindowFrame&) = delete;

  ///@{
  /// Pixel step while the render window asks for more frames per second than
  /// InteractiveUpdateRate (1 disables subsampling). The setters clamp the step to [1, 16]
  /// and return whether the value changed (the mapper then calls Modified()).
  bool SetInteractiveSubsampling(int step);
  int GetInteractiveSubsampling() const { return this->InteractiveSubsampling; }
  bool SetInteractiveUpdateRate(double rate);
  double GetInteractiveUpdateRate() const { return this->InteractiveUpdateRate; }
  ///@}

  /// Prints the interactive-subsampling settings, for the mappers' PrintSelf.
  void PrintSelf(std::ostream& os, vtkIndent indent) const;

  /// Draws `prop` into the renderer's viewport: StartEvent, the tracer's scene update, a
  /// frame traced (or the cached one), compositing for the tracer's pass, EndEvent. Events and
  /// messages go to `mapper`, the tracer's own mapper.
  void Render(
    vtkAbstractMapper3D* mapper, SightlineTracer& tracer, vtkRenderer* renderer, vtkProp3D* prop);

  void ReleaseGraphicsResources(vtkWindow* window);

private:
  /// A pass of hardware selection (renderer->GetSelector() set): the prop traced once at full
  /// size with per-pixel primitives (kept while the view and scene hold), drawn as the value
  /// the selector's current pass asks for, with depth. Tracers without selection ids draw
  /// nothing.
  void RenderSelection(vtkAbstractMapper3D* mapper, SightlineTracer& tracer, vtkRenderer* renderer,
    vtkProp3D* prop, vtkHardwareSelector* selector, vtkOpenGLRenderWindow* window, int width,
    int height);

  int InteractiveSubsampling = 2;
  double InteractiveUpdateRate = 1.0;

  // Last frame, reused while its key (view, size, lights, scene time, depth behind) holds.
  sightline::Framebuffer Frame;
  std::vector<double> Key;
  std::vector<std::uint8_t> Rgba;
  SightlineWindowCompositor Compositor;

  // The selection passes' frame (with primitives) and its key, apart from the shaded frame so
  // that a selection does not cost the next normal frame a trace; whether the compositor's
  // textures hold a selection pass's values rather than the shaded frame.
  sightline::Framebuffer SelectionFrame;
  std::vector<double> SelectionKey;
  std::vector<std::uint8_t> SelectionRgba;
  bool TexturesHoldSelection = false;

  /// Counts the renderer's frames (its StartEvent): a translucent or volumetric layer is blended
  /// over the frame once per frame and key, although a depth-peeling pass (ParaView's default)
  /// hands translucent props to their mapper in each of its stages.
  void CountFrames(vtkRenderer* renderer);
  vtkWeakPointer<vtkRenderer> CountedRenderer;
  unsigned long FrameObserver = 0;
  std::uint64_t FrameNumber = 0;
  std::uint64_t BlendedFrame = 0;
  std::vector<double> BlendedKey;
};

/// Defines a mapper's Set/GetInteractiveSubsampling and Set/GetInteractiveUpdateRate (declared
/// in its header) by forwarding to its SightlineWindowFrame `frame` (a member path from
/// `this`); a setter that changes the value calls Modified().
#define sightlineWindowFrameSettingsMacro(mapperClass, frame)                                   \
  void mapperClass::SetInteractiveSubsampling(int step)                                        \
  {                                                                                             \
    if (this->frame.SetInteractiveSubsampling(step)) { this->Modified(); }                      \
  }                                                                                             \
  int mapperClass::GetInteractiveSubsampling() { return this->frame.GetInteractiveSubsampling(); } \
  void mapperClass::SetInteractiveUpdateRate(double rate)                                       \
  {                                                                                             \
    if (this->frame.SetInteractiveUpdateRate(rate)) { this->Modified(); }                       \
  }                                                                                             \
  double mapperClass::GetInteractiveUpdateRate() { return this->frame.GetInteractiveUpdateRate(); }
