// SPDX-License-Identifier: BSD-3-Clause
// A vtkImageSlice (or vtkImageActor) drawn by vtkImageSliceMapper, traced without OpenGL: the
// slice's texels are coloured as vtkImageMapper3D colours its texture (window/level or the
// property's lookup table), placed as its textured quad is (prop matrix, image origin, spacing
// and direction, Border, Cropping) and traced as a kernel sightline::ImagePlane, so that
// vtkSightlineImageRenderer composites it with every Sightline primitive by exact depth.
// Only the displayed slice is requested from the input (as the OpenGL mapper requests it).
// Private to the Rendering module (not wrapped, not installed).
#pragma once

#include "SightlineTracer.h"

#include <memory>

class vtkCamera;
class vtkImageSlice;

namespace sightline
{
class ImagePlane;
}

class SightlineImageSliceTracer : public SightlineTracer
{
public:
  /// Whether `slice` can be traced this way (its mapper is a vtkImageSliceMapper); otherwise
  /// `why` names what cannot be (e.g. vtkImageResliceMapper).
  static bool CanTrace(vtkImageSlice* slice, const char*& why);

  /// Traces `slice` seen by `camera` (which places the slice when the mapper's
  /// SliceFacesCamera or SliceAtFocalPoint is on, as the OpenGL mapper does at render time).
  SightlineImageSliceTracer(vtkImageSlice* slice, vtkCamera* camera);
  ~SightlineImageSliceTracer() override;

  Pass GetPass(vtkProp3D* prop) override;
  bool UpdateScene() override;
  vtkMTimeType GetSceneTime() override;
  bool RayTrace(vtkProp3D* prop, vtkCamera* camera, vtkLightCollection* lights, int width,
    int height, sightline::Framebuffer& framebuffer,
    const std::vector<float>* depthLimit = nullptr) override;

private:
  vtkImageSlice* Slice;
  vtkCamera* Camera;
  std::unique_ptr<sightline::ImagePlane> Plane; // null until built, or when nothing is shown
  bool Built = false;
  vtkMTimeType BuildTime = 0;
};
