// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineWindowCompositor.h"

#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderUtilities.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkShaderProgram.h"
#include "SightlineOpenGL.h"

#include <algorithm>
#include <string>

namespace
{
const char* const QuadFragmentDeclarations = "uniform sampler2D colorTexture;\n"
                                             "uniform sampler2D depthTexture;\n";
// Misses carry window depth 1 and are discarded so whatever VTK drew there stays.
const char* const QuadFragmentImplementation =
  "  float depth = texture(depthTexture, texCoord).r;\n"
  "  if (depth >= 1.0) { discard; }\n"
  "  gl_FragData[0] = texture(colorTexture, texCoord);\n"
  "  gl_FragDepth = depth;\n";
} // namespace

SightlineWindowCompositor::SightlineWindowCompositor() = default;
SightlineWindowCompositor::~SightlineWindowCompositor() = default;

SightlineWindowCompositor::RenderFramebufferBinding::RenderFramebufferBinding(
  vtkOpenGLRenderWindow* window)
{
  if (vtkOpenGLFramebufferObject* target = window->GetRenderFramebuffer())
  {
    this->State = window->GetState();
    this->State->PushFramebufferBindings();
    target->Bind();
  }
}

SightlineWindowCompositor::RenderFramebufferBinding::~RenderFramebufferBinding()
{
  if (this->State)
  {
    this->State->PopFramebufferBindings();
  }
}

std::vector<float> SightlineWindowCompositor::ReadDepth(vtkOpenGLRenderWindow* window, int x0, int y0, int width, int height, int step, int traceWidth, int traceHeight)
{
  std::vector<float> viewportDepth(static_cast<std::size_t>(width) * height);
  // VTK resolves a multisampled frame before reading it back (glReadPixels cannot).
  window->GetZbufferData(x0, y0, x0 + width - 1, y0 + height - 1, viewportDepth.data());
  std::vector<float> depth(static_cast<std::size_t>(traceWidth) * traceHeight);
  for (int ty = 0; ty < traceHeight; ++ty)
  {
    const int sy = std::min(height - 1, ty * step + step / 2);
    for (int tx = 0; tx < traceWidth; ++tx)
    {
      const int sx = std::min(width - 1, tx * step + step / 2);
      depth[static_cast<std::size_t>(ty) * traceWidth + tx] =
        viewportDepth[static_cast<std::size_t>(sy) * width + sx];
    }
  }
  return depth;
}

bool SightlineWindowCompositor::Draw(vtkOpenGLRenderWindow* window, int width, int height,
  const std::uint8_t* rgba, const float* depth, bool changed, Blending blending)
{
  if (changed || !this->TexturesCurrent || this->ColorTexture->GetContext() != window)
  {
    for (vtkTextureObject* texture : { this->ColorTexture.Get(), this->DepthTexture.Get() })
    {
      texture->SetContext(window);
      texture->SetMinificationFilter(vtkTextureObject::Nearest);
      texture->SetMagnificationFilter(vtkTextureObject::Nearest);
      texture->SetWrapS(vtkTextureObject::ClampToEdge);
      texture->SetWrapT(vtkTextureObject::ClampToEdge);
    }
    this->ColorTexture->Create2DFromRaw(
      width, height, 4, VTK_UNSIGNED_CHAR, const_cast<std::uint8_t*>(rgba));
    this->DepthTexture->Create2DFromRaw(width, height, 1, VTK_FLOAT, const_cast<float*>(depth));
    this->TexturesCurrent = true;
  }

  if (!this->Quad)
  {
    std::string fragment = vtkOpenGLRenderUtilities::GetFullScreenQuadFragmentShaderTemplate();
    vtkShaderProgram::Substitute(fragment, "//VTK::FSQ::Decl", QuadFragmentDeclarations);
    vtkShaderProgram::Substitute(fragment, "//VTK::FSQ::Impl", QuadFragmentImplementation);
    this->Quad = std::make_unique<vtkOpenGLQuadHelper>(window,
      vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(), fragment.c_str(), "");
  }
  else
  {
    window->GetShaderCache()->ReadyShaderProgram(this->Quad->Program);
  }
  if (!this->Quad->Program || !this->Quad->Program->GetCompiled())
  {
    return false;
  }

  vtkOpenGLState* state = window->GetState();
  vtkOpenGLState::ScopedglDepthMask depthMask(state);
  vtkOpenGLState::ScopedglDepthFunc depthFunc(state);
  vtkOpenGLState::ScopedglEnableDisable blend(state, GL_BLEND);
  vtkOpenGLState::ScopedglBlendFuncSeparate blendFunction(state);
  // What the pass drawing around us set (restored after the quad).
  GLint blendEquation[2] = { GL_FUNC_ADD, GL_FUNC_ADD };
  glGetIntegerv(GL_BLEND_EQUATION_RGB, &blendEquation[0]);
  glGetIntegerv(GL_BLEND_EQUATION_ALPHA, &blendEquation[1]);
  state->vtkglEnable(GL_DEPTH_TEST);
  state->vtkglDepthFunc(GL_LEQUAL);
  if (blending == Blending::Replace)
  {
    state->vtkglDepthMask(GL_TRUE);
  }
  else
  {
    // Colours are premultiplied (composited over black), and rays already stopped at the
    // opaque depth.
    state->vtkglEnable(GL_BLEND);
    state->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    // "Over" needs addition; a dual depth-peeling pass leaves GL_MAX set while translucent
    // props draw (its depth passes), which kept only the brighter of layer and background.
    state->ResetGLBlendEquationState(); // the cache may not know what was set behind it
    state->vtkglBlendEquation(GL_FUNC_ADD);
    state->vtkglDepthMask(blending == Blending::PremultipliedDepth ? GL_TRUE : GL_FALSE);
  }

  this->ColorTexture->Activate();
  this->DepthTexture->Activate();
  this->Quad->Program->SetUniformi("colorTexture", this->ColorTexture->GetTextureUnit());
  this->Quad->Program->SetUniformi("depthTexture", this->DepthTexture->GetTextureUnit());
  this->Quad->Render();
  this->DepthTexture->Deactivate();
  this->ColorTexture->Deactivate();
  if (blending != Blending::Replace)
  {
    state->vtkglBlendEquationSeparate(blendEquation[0], blendEquation[1]);
  }
  return true;
}

void SightlineWindowCompositor::ReleaseGraphicsResources(vtkWindow* window)
{
  this->ColorTexture->ReleaseGraphicsResources(window);
  this->DepthTexture->ReleaseGraphicsResources(window);
  if (this->Quad)
  {
    this->Quad->ReleaseGraphicsResources(window);
    this->Quad.reset();
  }
  this->TexturesCurrent = false;
}
