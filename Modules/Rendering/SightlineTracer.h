// SPDX-License-Identifier: BSD-3-Clause
// The one interface through which Sightline props are traced, in a window
// (SightlineWindowFrame) or without one (vtkSightlineImageRenderer). vtkSightlineMapper
// (surfaces) and vtkSightlineSphericalVolumeMapper (volumes) implement it, so neither the
// window loop nor the image renderer needs to know the concrete mapper classes.
// C++ only (not wrapped), no third-party headers; installed because the mappers' public headers
// derive from it.
#ifndef SightlineTracer_h
#define SightlineTracer_h

#include "SightlineRenderingModule.h" // for export macro
#include "vtkType.h"                  // for vtkMTimeType

#include <vector> // for std::vector

class vtkAbstractMapper;
class vtkCamera;
class vtkLightCollection;
class vtkProp3D;
namespace sightline
{
class Framebuffer;
}

class SIGHTLINERENDERING_EXPORT SightlineTracer
{
public:
  /// Where a prop's frame goes, as in VTK's render passes. Opaque surfaces replace colour and
  /// depth. Translucent surfaces are blended over the frame without writing depth; volumes are
  /// blended over it and write the depth of their first visible sample. Rays of both stop at
  /// the depth drawn before them.
  enum class Pass
  {
    Opaque,
    Translucent,
    Volumetric
  };

  virtual ~SightlineTracer();

  /// The tracer behind a mapper, or null when it is not a Sightline mapper.
  static SightlineTracer* Of(vtkAbstractMapper* mapper);

  /// The pass `prop` (whose mapper this is) is drawn in.
  virtual Pass GetPass(vtkProp3D* prop) = 0;

  /// The view about to be traced (before UpdateScene): `camera` at image aspect `aspect` on
  /// `prop`; `interactive` while the user drags (a frame that may stay approximate). Tracers
  /// that build less for what the view cannot see (frustum culling) use it; the default
  /// ignores it.
  virtual void SetView(vtkProp3D* /*prop*/, vtkCamera* /*camera*/, double /*aspect*/, bool /*interactive*/) {}

  /// Brings what is traced up to date with the input; false (after reporting why) when there
  /// is nothing to draw.
  virtual bool UpdateScene() = 0;

  /// When what is traced was last rebuilt from the input (a frame also depends on the view,
  /// the prop and the mapper, whose times the window frame reads itself).
  virtual vtkMTimeType GetSceneTime() = 0;

  /// Traces `prop` as `camera` sees it into a width x height framebuffer, lit by `lights`
  /// (VTK's automatic headlight when null or empty), with rays stopped at `depthLimit` (window
  /// depths, bottom row first) when given. Returns false after reporting an error when nothing
  /// could be traced.
  virtual bool RayTrace(vtkProp3D* prop, vtkCamera* camera, vtkLightCollection* lights,
    int width, int height, sightline::Framebuffer& framebuffer,
    const std::vector<float>* depthLimit = nullptr) = 0;

  /// Hardware selection (vtkHardwareSelector): the input ids each traced primitive stands for,
  /// indexed as the kernel's pixels name them (sightline::PixelPrimitive::primitive: a
  /// primitive, or a tube chunk's link, Geometry::selectionIndex); -1 for none.
  struct SelectionIds
  {
    std::vector<vtkIdType> PointIds;
    std::vector<vtkIdType> CellIds;
    vtkIdType MaximumPointId = -1;
    vtkIdType MaximumCellId = -1;
  };

  /// The ids of the current scene's primitives (call after UpdateScene()), or null when this
  /// tracer's props cannot be selected (the default).
  virtual const SelectionIds* GetSelectionIds() { return nullptr; }

  /// For a selection pass: traces `prop` as RayTrace does, but always as an opaque surface
  /// (a translucent union gives its nearest surface), and records the primitive each pixel
  /// shows in framebuffer.Primitives. Only called when GetSelectionIds() is not null.
  virtual bool RayTraceSelection(vtkProp3D* /*prop*/, vtkCamera* /*camera*/,
    vtkLightCollection* /*lights*/, int /*width*/, int /*height*/,
    sightline::Framebuffer& /*framebuffer*/)
  {
    return false;
  }
};

#endif
