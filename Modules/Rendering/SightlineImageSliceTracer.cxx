// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineImageSliceTracer.h"

#include "SightlineKernelConversions.h"

#include "vtkAlgorithm.h"
#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkImageProperty.h"
#include "vtkImageSlice.h"
#include "vtkImageSliceMapper.h"
#include "vtkInformation.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkScalarsToColors.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include "sightline/images/ImagePlane.h"

#include <algorithm>
#include <cmath>
#include <exception>

namespace
{
// The slice's texels as vtkImageMapper3D makes its texture: through the property's lookup
// table (its range set from window/level unless UseLookupTableScalarRange), or else each
// component shifted and scaled from [level - window/2, level + window/2] to [0, 255] and
// rounded (1 component: grey; 2: grey and alpha; 3: RGB; 4: RGBA).
std::vector<std::uint8_t> Texels(vtkImageProperty* property, vtkDataArray* scalars,
  const std::vector<vtkIdType>& ids)
{
  const int components = scalars->GetNumberOfComponents();
  double window = 255.0, level = 127.5;
  vtkScalarsToColors* table = nullptr;
  if (property)
  {
    window = property->GetColorWindow();
    level = property->GetColorLevel();
    table = property->GetLookupTable();
  }
  const double low = level - 0.5 * window, high = level + 0.5 * window;
  std::vector<double> values(ids.size() * components);
  for (std::size_t i = 0; i < ids.size(); ++i)
  {
    scalars->GetTuple(ids[i], &values[i * components]);
  }
  std::vector<std::uint8_t> rgba(ids.size() * 4, 255);
  if (table)
  {
    if (!property->GetUseLookupTableScalarRange())
    {
      table->SetRange(low, high); // as the OpenGL mapper does: the table's own range changes
    }
    if (components == 1)
    {
      table->MapScalarsThroughTable(
        values.data(), rgba.data(), VTK_DOUBLE, int(ids.size()), 1, VTK_RGBA);
    }
    else
    {
      table->MapVectorsThroughTable(
        values.data(), rgba.data(), VTK_DOUBLE, int(ids.size()), components, VTK_RGBA);
    }
    return rgba;
  }
  const double scale = low < high ? 255.0 / (high - low) : 1e32;
  auto grey = [&](double value)
  { return std::uint8_t(std::clamp((value - low) * scale, 0.0, 255.0) + 0.5); };
  for (std::size_t i = 0; i < ids.size(); ++i)
  {
    const double* v = &values[i * components];
    std::uint8_t* out = &rgba[i * 4];
    if (components <= 2)
    {
      out[0] = out[1] = out[2] = grey(v[0]);
      out[3] = components == 2 ? grey(v[1]) : 255;
    }
    else
    {
      for (int c = 0; c < std::min(components, 4); ++c)
      {
        out[c] = grey(v[c]);
      }
    }
  }
  return rgba;
}

// A point of `matrix` applied to p (homogeneous, divided).
void Apply(vtkMatrix4x4* matrix, const double p[3], double out[3])
{
  double in[4] = { p[0], p[1], p[2], 1.0 }, result[4];
  matrix->MultiplyPoint(in, result);
  for (int i = 0; i < 3; ++i)
  {
    out[i] = result[i] / result[3];
  }
}
} // namespace

//------------------------------------------------------------------------------
bool SightlineImageSliceTracer::CanTrace(vtkImageSlice* slice, const char*& why)
{
  if (!vtkImageSliceMapper::SafeDownCast(slice->GetMapper()))
  {
    why = "only image slices drawn by vtkImageSliceMapper (vtkImageSlice, vtkImageActor) can be "
          "rendered without OpenGL";
    return false;
  }
  return true;
}

SightlineImageSliceTracer::SightlineImageSliceTracer(vtkImageSlice* slice, vtkCamera* camera)
  : Slice(slice)
  , Camera(camera)
{
}

SightlineImageSliceTracer::~SightlineImageSliceTracer() = default;

//------------------------------------------------------------------------------
bool SightlineImageSliceTracer::UpdateScene()
{
  if (this->Built)
  {
    return this->Plane != nullptr;
  }
  this->Built = true;
  this->BuildTime = this->Slice->GetMTime();
  auto* mapper = vtkImageSliceMapper::SafeDownCast(this->Slice->GetMapper());
  vtkAlgorithm* producer = mapper ? mapper->GetInputAlgorithm() : nullptr;
  if (!producer)
  {
    vtkErrorWithObjectMacro(this->Slice, << "The image slice has no vtkImageSliceMapper with an input.");
    return false;
  }
  // The displayed slice only: ask the producer for its information, then for that extent.
  producer->UpdateInformation();
  vtkInformation* info = mapper->GetInputInformation();
  int whole[6];
  info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  if (whole[0] > whole[1] || whole[2] > whole[3] || whole[4] > whole[5])
  {
    return false; // an empty image draws nothing, in a window too
  }
  double spacing[3] = { 1, 1, 1 }, origin[3] = { 0, 0, 0 };
  if (info->Has(vtkDataObject::SPACING()))
  {
    info->Get(vtkDataObject::SPACING(), spacing);
  }
  if (info->Has(vtkDataObject::ORIGIN()))
  {
    info->Get(vtkDataObject::ORIGIN(), origin);
  }
  vtkMatrix4x4* propMatrix = this->Slice->GetMatrix();
  int orientation = mapper->GetOrientation();
  if (mapper->GetSliceFacesCamera() && this->Camera)
  {
    // The data axis most nearly along the view direction, in data coordinates.
    vtkNew<vtkMatrix4x4> inverse;
    vtkMatrix4x4::Invert(propMatrix, inverse);
    double position[3], focal[3], p[3], f[3];
    this->Camera->GetPosition(position);
    this->Camera->GetFocalPoint(focal);
    Apply(inverse, position, p);
    Apply(inverse, focal, f);
    double best = -1;
    for (int axis = 0; axis < 3; ++axis)
    {
      const double along = std::abs(f[axis] - p[axis]);
      if (along > best)
      {
        best = along;
        orientation = axis;
      }
    }
  }
  int sliceNumber = mapper->GetSliceNumber();
  if (mapper->GetSliceAtFocalPoint() && this->Camera)
  {
    vtkNew<vtkMatrix4x4> inverse;
    vtkMatrix4x4::Invert(propMatrix, inverse);
    double focal[3], f[3];
    this->Camera->GetFocalPoint(focal);
    Apply(inverse, focal, f);
    sliceNumber = int(std::lround((f[orientation] - origin[orientation]) / spacing[orientation]));
  }
  sliceNumber = std::clamp(sliceNumber, whole[2 * orientation], whole[2 * orientation + 1]);
  int extent[6];
  std::copy(whole, whole + 6, extent);
  if (mapper->GetCropping())
  {
    const int* crop = mapper->GetCroppingRegion();
    for (int axis = 0; axis < 3; ++axis)
    {
      extent[2 * axis] = std::max(extent[2 * axis], crop[2 * axis]);
      extent[2 * axis + 1] = std::min(extent[2 * axis + 1], crop[2 * axis + 1]);
    }
  }
  extent[2 * orientation] = extent[2 * orientation + 1] = sliceNumber;
  if (extent[0] > extent[1] || extent[2] > extent[3] || extent[4] > extent[5])
  {
    return false; // cropped away
  }
  producer->UpdateExtent(extent);
  vtkImageData* image = mapper->GetInput();
  vtkDataArray* scalars = image ? image->GetPointData()->GetScalars() : nullptr;
  if (!scalars || scalars->GetNumberOfTuples() == 0)
  {
    vtkErrorWithObjectMacro(this->Slice, << "The image slice's input has no point scalars to show.");
    return false;
  }
  // Texture axes as vtkImageMapper3D picks them: the two other axes, in increasing order.
  const int xAxis = orientation == 0 ? 1 : 0;
  const int yAxis = orientation == 2 ? 1 : 2;
  const int width = extent[2 * xAxis + 1] - extent[2 * xAxis] + 1;
  const int height = extent[2 * yAxis + 1] - extent[2 * yAxis] + 1;
  std::vector<vtkIdType> ids;
  ids.reserve(std::size_t(width) * height);
  int ijk[3];
  ijk[orientation] = sliceNumber;
  for (int j = 0; j < height; ++j)
  {
    for (int i = 0; i < width; ++i)
    {
      ijk[xAxis] = extent[2 * xAxis] + i;
      ijk[yAxis] = extent[2 * yAxis] + j;
      const vtkIdType id = image->ComputePointId(ijk);
      if (id < 0 || id >= scalars->GetNumberOfTuples())
      {
        vtkErrorWithObjectMacro(this->Slice, << "The image slice's input does not cover the "
                                                   "requested slice.");
        return false;
      }
      ids.push_back(id);
    }
  }
  // Texture coordinate (s, t) lies at the continuous index (first texel - 0.5 + s, ...),
  // placed by the image's origin, spacing and direction, then the prop's matrix.
  double corner[3], sEnd[3], tEnd[3];
  double index[3];
  index[orientation] = sliceNumber;
  index[xAxis] = extent[2 * xAxis] - 0.5;
  index[yAxis] = extent[2 * yAxis] - 0.5;
  image->TransformContinuousIndexToPhysicalPoint(index, corner);
  index[xAxis] += 1.0;
  image->TransformContinuousIndexToPhysicalPoint(index, sEnd);
  index[xAxis] -= 1.0;
  index[yAxis] += 1.0;
  image->TransformContinuousIndexToPhysicalPoint(index, tEnd);
  double worldCorner[3], worldS[3], worldT[3];
  Apply(propMatrix, corner, worldCorner);
  Apply(propMatrix, sEnd, worldS);
  Apply(propMatrix, tEnd, worldT);
  const sightline::dvec3 origin3(worldCorner[0], worldCorner[1], worldCorner[2]);
  const sightline::dvec3 sStep = sightline::dvec3(worldS[0], worldS[1], worldS[2]) - origin3;
  const sightline::dvec3 tStep = sightline::dvec3(worldT[0], worldT[1], worldT[2]) - origin3;
  // The quad: from the first to the last texel centre, or the texels' whole extent (Border).
  const double inset = mapper->GetBorder() ? 0.0 : 0.5;
  const sightline::dvec2 lower(inset), upper(width - inset, height - inset);
  if (!(lower.x < upper.x) || !(lower.y < upper.y))
  {
    return false; // one texel wide without a border: OpenGL draws a zero-area quad
  }
  vtkImageProperty* property = this->Slice->GetProperty();
  try
  {
    this->Plane = std::make_unique<sightline::ImagePlane>(
      origin3, sStep, tStep, width, height, Texels(property, scalars, ids), lower, upper);
  }
  catch (const std::exception& e)
  {
    vtkErrorWithObjectMacro(this->Slice, << "Cannot draw the image slice: " << e.what());
    return false;
  }
  if (property)
  {
    // Nearest and linear as OpenGL filters the texture; cubic is drawn as linear.
    this->Plane->setFilter(property->GetInterpolationType() == VTK_NEAREST_INTERPOLATION
        ? sightline::ImagePlane::Filter::Nearest
        : sightline::ImagePlane::Filter::Linear);
    this->Plane->setOpacity(float(property->GetOpacity()));
    this->Plane->setBrightness(float(property->GetAmbient()));
  }
  return true;
}

vtkMTimeType SightlineImageSliceTracer::GetSceneTime()
{
  return this->BuildTime;
}

SightlineTracer::Pass SightlineImageSliceTracer::GetPass(vtkProp3D*)
{
  return this->UpdateScene() && !this->Plane->opaque() ? Pass::Translucent : Pass::Opaque;
}

bool SightlineImageSliceTracer::RayTrace(vtkProp3D*, vtkCamera* camera, vtkLightCollection*,
  int width, int height, sightline::Framebuffer& framebuffer, const std::vector<float>* depthLimit)
{
  framebuffer.resize(width, height);
  if (!this->UpdateScene())
  {
    return false;
  }
  try
  {
    using SightlineKernelConversions::ToKernelMatrix;
    const sightline::Camera view(
      ToKernelMatrix(camera->GetCompositeProjectionTransformMatrix(double(width) / height, -1, 1)),
      width, height);
    this->Plane->render(view, framebuffer, depthLimit);
  }
  catch (const std::exception& e)
  {
    vtkErrorWithObjectMacro(this->Slice, << "Cannot draw the image slice: " << e.what());
    return false;
  }
  return true;
}
