// SPDX-License-Identifier: BSD-3-Clause
// VTK -> kernel conversions shared by every Sightline mapper: matrices, lights, materials,
// mapped scalars, progress and the kernel's validation reports. The one place where VTK
// objects become sightline:: values, so the window and GL-free paths convert alike.
// Private to the Rendering module (not wrapped, not installed).
#pragma once

#include "SightlineRenderingModule.h" // for export macro

#include "vtkType.h" // for vtkIdType

#include "sightline/core/Shading.h" // for sightline::Lighting, sightline::Material
#include "sightline/math/Math.h"    // for sightline::dmat4

#include <cstdint>
#include <functional>
#include <vector>

class vtkAlgorithm;
class vtkCamera;
class vtkDataSet;
class vtkLightCollection;
class vtkMapper;
class vtkMatrix4x4;
class vtkObject;
class vtkProperty;
class vtkVolumeProperty;

namespace sightline
{
struct ValidationReport;
}

namespace SightlineKernelConversions
{
/// A vtkMatrix4x4 (row-major, column vectors) as the kernel's column-major GLM matrix.
SIGHTLINERENDERING_EXPORT sightline::dmat4 ToKernelMatrix(vtkMatrix4x4* matrix);

/// The kernel lighting VTK would apply with these lights and this camera: headlights follow
/// the camera, camera lights are transformed with it, scene lights stay. An empty or null
/// collection gives VTK's automatic headlight.
SIGHTLINERENDERING_EXPORT sightline::Lighting MakeLighting(
  vtkLightCollection* lights, vtkCamera* camera);

/// Whether any switched-on light is positional (the kernel treats it as directional).
bool HasPositionalLight(vtkLightCollection* lights);

/// An actor's surface material: Phong terms, or the glTF dielectric for VTK_PBR, and opacity.
sightline::Material MaterialFromProperty(vtkProperty* property);

/// The Phong terms of a volume's shading (component 0).
sightline::Material MaterialFromVolumeProperty(vtkVolumeProperty* property);

/// The mapper's colours for the input's points, packed RGBA8 (sightline::packRGBA8), or
/// empty when scalar colouring is off or gives no per-point colours. `cellScalars` is set
/// when the mapped scalars are cell data, which per-point primitives cannot use.
std::vector<std::uint32_t> PointColors(
  vtkMapper* mapper, vtkDataSet* input, bool* cellScalars = nullptr);

/// The mapper's colours for the input's cells, packed RGBA8, or empty when scalar colouring is
/// off or the mapped scalars are not cell data (e.g. a tractogram's per-streamline values).
std::vector<std::uint32_t> CellColors(vtkMapper* mapper, vtkDataSet* input);

/// The mapper's colours for the input's points, or for its cells when the mapped scalars are
/// cell data (at most one of the two filled): what a primitive drawn per point or per cell takes.
struct PointOrCellColors
{
  std::vector<std::uint32_t> points, cells;
  bool empty() const { return points.empty() && cells.empty(); }
};
PointOrCellColors ColorsByPointOrCell(vtkMapper* mapper, vtkDataSet* input);

/// Each reason of a kernel geometry's report as a warning of `reporter` (observers of its
/// WarningEvent see them as they see the reporter's own warnings).
void WarnAboutReport(vtkObject* reporter, const sightline::ValidationReport& report);

/// Positions handed to a kernel set: the origin (in double) is the centre of the finite
/// positions' bounding box (rounded to a multiple of a power of two near 1/64 of its extent,
/// so that it is a float with few bits: compact tube chunks rely on it), and `local` holds each position relative to it as floats, so the
/// set keeps float precision relative to its own extent wherever the data sit in the world
/// (the kernel intersects each primitive in its own frame with double rays). Non-finite
/// positions stay non-finite, so the kernel drops and reports them as before.
sightline::dvec3 ToLocalFrame(
  const std::vector<sightline::dvec3>& world, std::vector<sightline::vec3>& local);

/// A kernel progress callback that reports through `algorithm`'s ProgressEvent and stops
/// when its AbortExecute is set.
std::function<bool(double)> ProgressCallback(vtkAlgorithm* algorithm);

/// A mapper's world region (xmin, xmax, ymin, ymax, zmin, zmax) as the kernel's box; false
/// after reporting through `reporter` when a range is empty or NaN.
bool ToKernelRegion(vtkObject* reporter, const double region[6], sightline::dvec3& lower, sightline::dvec3& upper);
} // namespace SightlineKernelConversions
