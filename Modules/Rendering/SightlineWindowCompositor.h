// SPDX-License-Identifier: BSD-3-Clause
// Draws a CPU-rendered frame (colour and window depth) into a VTK OpenGL window with a
// full-viewport quad, and reads back the depth of what OpenGL has drawn so far: the same
// contract as VTK's own CPU ray casters, opaque geometry first, depth-aware. OpenGL only; the
// frame loop that decides what to draw is SightlineWindowFrame.
// Private to the Rendering module (not wrapped, not installed).
#pragma once

#include "vtkNew.h"
#include "vtkTextureObject.h"

#include <cstdint>
#include <memory>
#include <vector>

class vtkOpenGLQuadHelper;
class vtkOpenGLRenderWindow;
class vtkOpenGLState;
class vtkWindow;

class SightlineWindowCompositor
{
public:
  enum class Blending
  {
    Replace,            ///< opaque: colour replaces the frame, depth is written
    Premultiplied,      ///< translucent: colour over the frame, depth is not written
    PremultipliedDepth, ///< volumes: colour over the frame, depth of the first visible sample
  };

  SightlineWindowCompositor();
  ~SightlineWindowCompositor();

  /// Binds the window's render framebuffer (not VTK's order-independent-transparency or
  /// depth-peeling buffers) until the guard goes out of scope: reading the opaque depth and
  /// blending a self-sorted frame both need the real frame.
  class RenderFramebufferBinding
  {
  public:
    explicit RenderFramebufferBinding(vtkOpenGLRenderWindow* window);
    ~RenderFramebufferBinding();

  private:
    vtkOpenGLState* State = nullptr;
  };

  /// Window depth of the viewport (x0, y0, width, height) sampled at the centre of every
  /// step x step block: traceWidth x traceHeight values, bottom row first.
  static std::vector<float> ReadDepth(vtkOpenGLRenderWindow* window, int x0, int y0, int width, int height, int step,
    int traceWidth, int traceHeight);

  /// Draws the frame (RGBA8 premultiplied over black, window depth with 1 for "nothing") over
  /// the current viewport. `changed` uploads the buffers again. Returns false when the shader
  /// could not be compiled.
  bool Draw(vtkOpenGLRenderWindow* window, int width, int height, const std::uint8_t* rgba,
    const float* depth, bool changed, Blending blending);

  void ReleaseGraphicsResources(vtkWindow* window);

private:
  vtkNew<vtkTextureObject> ColorTexture;
  vtkNew<vtkTextureObject> DepthTexture;
  std::unique_ptr<vtkOpenGLQuadHelper> Quad;
  bool TexturesCurrent = false;
};
