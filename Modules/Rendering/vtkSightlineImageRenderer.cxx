// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineImageRenderer.h"

#include "vtkActor.h"
#include "vtkActorCollection.h"
#include "vtkCamera.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkImageSlice.h"
#include "vtkImageSliceMapper.h"
#include "SightlineImageSliceTracer.h"
#include "SightlineTracer.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMapper.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkAbstractVolumeMapper.h"
#include "vtkVolume.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"

#include "sightline/core/Framebuffer.h"

#include <algorithm>
#include <exception>
#include <memory>
#include <cstring>
#include <vector>

vtkStandardNewMacro(vtkSightlineImageRenderer);

//------------------------------------------------------------------------------
vtkSightlineImageRenderer::vtkSightlineImageRenderer()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
vtkSightlineImageRenderer::~vtkSightlineImageRenderer()
{
  this->SetActiveCamera(nullptr);
}

//------------------------------------------------------------------------------
void vtkSightlineImageRenderer::AddActor(vtkActor* actor)
{
  if (actor && !this->Actors->IsItemPresent(actor))
  {
    this->Actors->AddItem(actor);
    this->Modified();
  }
}

void vtkSightlineImageRenderer::RemoveActor(vtkActor* actor)
{
  if (this->Actors->IsItemPresent(actor))
  {
    this->Actors->RemoveItem(actor);
    this->Modified();
  }
}

void vtkSightlineImageRenderer::RemoveAllActors()
{
  this->Actors->RemoveAllItems();
  this->Modified();
}

void vtkSightlineImageRenderer::AddVolume(vtkVolume* volume)
{
  if (volume && !this->Volumes->IsItemPresent(volume))
  {
    this->Volumes->AddItem(volume);
    this->Modified();
  }
}

void vtkSightlineImageRenderer::RemoveVolume(vtkVolume* volume)
{
  if (this->Volumes->IsItemPresent(volume))
  {
    this->Volumes->RemoveItem(volume);
    this->Modified();
  }
}

void vtkSightlineImageRenderer::RemoveAllVolumes()
{
  this->Volumes->RemoveAllItems();
  this->Modified();
}

void vtkSightlineImageRenderer::AddImageSlice(vtkImageSlice* slice)
{
  if (slice && !this->ImageSlices->IsItemPresent(slice))
  {
    this->ImageSlices->AddItem(slice);
    this->Modified();
  }
}

void vtkSightlineImageRenderer::RemoveImageSlice(vtkImageSlice* slice)
{
  if (this->ImageSlices->IsItemPresent(slice))
  {
    this->ImageSlices->RemoveItem(slice);
    this->Modified();
  }
}

void vtkSightlineImageRenderer::RemoveAllImageSlices()
{
  this->ImageSlices->RemoveAllItems();
  this->Modified();
}

vtkPropCollection* vtkSightlineImageRenderer::GetImageSlices()
{
  return this->ImageSlices;
}

vtkVolumeCollection* vtkSightlineImageRenderer::GetVolumes()
{
  return this->Volumes;
}

vtkActorCollection* vtkSightlineImageRenderer::GetActors()
{
  return this->Actors;
}

//------------------------------------------------------------------------------
void vtkSightlineImageRenderer::SetActiveCamera(vtkCamera* camera)
{
  vtkSetObjectBodyMacro(ActiveCamera, vtkCamera, camera);
}

void vtkSightlineImageRenderer::AddLight(vtkLight* light)
{
  if (light)
  {
    this->Lights->AddItem(light);
    this->Modified();
  }
}

void vtkSightlineImageRenderer::RemoveAllLights()
{
  this->Lights->RemoveAllItems();
  this->Modified();
}

vtkLightCollection* vtkSightlineImageRenderer::GetLights()
{
  return this->Lights;
}

//------------------------------------------------------------------------------
void vtkSightlineImageRenderer::ResetCamera()
{
  if (!this->ActiveCamera)
  {
    vtkNew<vtkCamera> camera;
    this->SetActiveCamera(camera);
  }
  // A renderer without a window computes bounds and camera placement exactly as it would
  // for the window; nothing here touches OpenGL.
  vtkNew<vtkRenderer> renderer;
  renderer->SetActiveCamera(this->ActiveCamera);
  vtkCollectionSimpleIterator it;
  this->Actors->InitTraversal(it);
  while (vtkActor* actor = this->Actors->GetNextActor(it))
  {
    renderer->AddActor(actor);
  }
  this->Volumes->InitTraversal(it);
  while (vtkVolume* volume = this->Volumes->GetNextVolume(it))
  {
    renderer->AddVolume(volume);
  }
  this->ImageSlices->InitTraversal(it);
  while (vtkProp* slice = this->ImageSlices->GetNextProp(it))
  {
    renderer->AddViewProp(slice);
  }
  // vtkRenderer::ResetCamera uses the viewport's aspect; without a window it is 1, so apply
  // this image's aspect the way vtkRenderer does for wide images.
  renderer->ResetCamera();
  const double aspect = double(this->Size[0]) / std::max(1, this->Size[1]);
  if (aspect < 1.0 && !this->ActiveCamera->GetParallelProjection())
  {
    this->ActiveCamera->Dolly(aspect);
  }
  else if (aspect < 1.0)
  {
    this->ActiveCamera->SetParallelScale(this->ActiveCamera->GetParallelScale() / aspect);
  }
  renderer->ResetCameraClippingRange();
  this->Modified();
}

//------------------------------------------------------------------------------
vtkMTimeType vtkSightlineImageRenderer::GetMTime()
{
  vtkMTimeType time = this->Superclass::GetMTime();
  if (this->ActiveCamera)
  {
    time = std::max(time, this->ActiveCamera->GetMTime());
  }
  time = std::max(time, this->Lights->GetMTime());
  vtkCollectionSimpleIterator it;
  this->Lights->InitTraversal(it);
  while (vtkLight* light = this->Lights->GetNextLight(it))
  {
    time = std::max(time, light->GetMTime());
  }
  this->Actors->InitTraversal(it);
  while (vtkActor* actor = this->Actors->GetNextActor(it))
  {
    time = std::max(time, actor->GetMTime());
    if (vtkMapper* mapper = actor->GetMapper())
    {
      time = std::max(time, mapper->GetMTime());
      if (mapper->GetNumberOfInputConnections(0) > 0)
      {
        time = std::max(time, mapper->GetInputAlgorithm()->GetMTime());
      }
    }
  }
  this->Volumes->InitTraversal(it);
  while (vtkVolume* volume = this->Volumes->GetNextVolume(it))
  {
    time = std::max(time, volume->GetMTime()); // includes its property and transfer functions
    if (vtkAbstractVolumeMapper* mapper = volume->GetMapper())
    {
      time = std::max(time, mapper->GetMTime());
      if (mapper->GetNumberOfInputConnections(0) > 0)
      {
        time = std::max(time, mapper->GetInputAlgorithm()->GetMTime());
      }
    }
  }
  this->ImageSlices->InitTraversal(it);
  while (vtkProp* prop = this->ImageSlices->GetNextProp(it))
  {
    auto* slice = vtkImageSlice::SafeDownCast(prop);
    time = std::max(time, slice->GetMTime()); // includes its property and lookup table
    if (vtkImageMapper3D* mapper = slice->GetMapper())
    {
      time = std::max(time, mapper->GetMTime());
      if (mapper->GetNumberOfInputConnections(0) > 0)
      {
        time = std::max(time, mapper->GetInputAlgorithm()->GetMTime());
      }
    }
  }
  return time;
}

//------------------------------------------------------------------------------
int vtkSightlineImageRenderer::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  const int extent[6] = { 0, std::max(this->Size[0], 1) - 1, 0, std::max(this->Size[1], 1) - 1,
    0, 0 };
  vtkInformation* info = outputVector->GetInformationObject(0);
  info->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  vtkDataObject::SetPointDataActiveScalarInfo(info, VTK_UNSIGNED_CHAR, 4);
  return 1;
}

namespace
{
// The most memory an image may take (see RequestData): 8 GiB.
constexpr vtkTypeInt64 MaximumImageBytes = vtkTypeInt64(8) << 30;
}

//------------------------------------------------------------------------------
int vtkSightlineImageRenderer::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  const int width = this->Size[0];
  const int height = this->Size[1];
  if (width <= 0 || height <= 0)
  {
    vtkErrorMacro(<< "The image size must be positive, got " << width << "x" << height << ".");
    return 0;
  }
  // Memory per pixel: the image and one prop's layer (24 bytes each: RGBA and depth as floats),
  // the 8-bit colours twice (conversion and output array) and the output depth. Refused
  // before anything is allocated, so a typo in the size is an error, not an abort.
  constexpr double kBytesPerPixel = 2 * 24 + 2 * 4 + 4;
  const double bytes = double(width) * double(height) * kBytesPerPixel;
  if (bytes > double(MaximumImageBytes))
  {
    vtkErrorMacro(<< "An image of " << width << "x" << height << " pixels needs "
                  << bytes / double(1 << 30) << " GiB, beyond the renderer's budget of "
                  << MaximumImageBytes / (1 << 30) << " GiB (about "
                  << vtkIdType(double(MaximumImageBytes) / kBytesPerPixel) / 1000000
                  << " million pixels).");
    return 0;
  }
  if (!this->ActiveCamera)
  {
    vtkErrorMacro(<< "No camera: call SetActiveCamera (or ResetCamera) first.");
    return 0;
  }

  // Every prop whose mapper is a Sightline tracer, by pass: opaque actors composited by depth
  // as the depth test does in a window; then translucent actors, each stopped at that depth
  // and blended over, as VTK's translucent pass does; volumes last, as its volumetric pass.
  struct TracedProp
  {
    vtkProp3D* Prop;
    SightlineTracer* Tracer;
    SightlineTracer::Pass Pass;
  };
  std::vector<TracedProp> props;
  auto collect = [&](vtkProp3D* prop, vtkAbstractMapper* mapper)
  {
    if (!prop->GetVisibility())
    {
      return;
    }
    if (SightlineTracer* tracer = SightlineTracer::Of(mapper))
    {
      props.push_back({ prop, tracer, tracer->GetPass(prop) });
      return;
    }
    vtkWarningMacro(<< "Skipping a " << prop->GetClassName() << " whose mapper is "
                    << (mapper ? mapper->GetClassName() : "null")
                    << "; only Sightline mappers (vtkSightlineMapper subclasses, "
                       "vtkSightlineSphericalVolumeMapper) can be rendered without OpenGL.");
  };
  vtkCollectionSimpleIterator it;
  this->Actors->InitTraversal(it);
  while (vtkActor* actor = this->Actors->GetNextActor(it))
  {
    collect(actor, actor->GetMapper());
  }
  this->Volumes->InitTraversal(it);
  while (vtkVolume* volume = this->Volumes->GetNextVolume(it))
  {
    collect(volume, volume->GetMapper());
  }
  // Image slices are traced through an adapter of their own (their mapper is VTK's).
  std::vector<std::unique_ptr<SightlineImageSliceTracer>> sliceTracers;
  this->ImageSlices->InitTraversal(it);
  while (vtkProp* prop = this->ImageSlices->GetNextProp(it))
  {
    auto* slice = vtkImageSlice::SafeDownCast(prop);
    const char* why = nullptr;
    if (!slice->GetVisibility())
    {
      continue;
    }
    if (!SightlineImageSliceTracer::CanTrace(slice, why))
    {
      vtkWarningMacro(<< "Skipping a " << slice->GetClassName() << " whose mapper is "
                      << (slice->GetMapper() ? slice->GetMapper()->GetClassName() : "null")
                      << "; " << why << ".");
      continue;
    }
    sliceTracers.push_back(std::make_unique<SightlineImageSliceTracer>(slice, this->ActiveCamera));
    props.push_back({ slice, sliceTracers.back().get(), sliceTracers.back()->GetPass(slice) });
  }
  std::stable_sort(props.begin(), props.end(),
    [](const TracedProp& a, const TracedProp& b) { return a.Pass < b.Pass; });

  try
  {
    sightline::Framebuffer image(width, height);
    sightline::Framebuffer layer;
    int done = 0;
    for (const TracedProp& traced : props)
    {
      this->UpdateProgress(double(done++) / props.size());
      const bool opaque = traced.Pass == SightlineTracer::Pass::Opaque;
      traced.Tracer->SetView(traced.Prop, this->ActiveCamera, static_cast<double>(width) / height, false);
      if (!traced.Tracer->RayTrace(traced.Prop, this->ActiveCamera, this->Lights, width, height,
            layer, opaque ? nullptr : &image.Depth))
      {
        continue;
      }
      if (opaque)
      {
        image.compositeNearest(layer);
      }
      else
      {
        // Volumes keep the depth of their first visible sample, as in a window.
        image.blendUnder(layer, traced.Pass == SightlineTracer::Pass::Volumetric);
      }
    }
    this->UpdateProgress(1.0);

    output->SetExtent(0, width - 1, 0, height - 1, 0, 0);
    output->SetSpacing(1, 1, 1);
    output->SetOrigin(0, 0, 0);
    const sightline::vec3 background(this->Background[0], this->Background[1], this->Background[2]);
    std::vector<std::uint8_t> rgba = image.toRGBA8(background);
    for (std::size_t i = 3; i < rgba.size(); i += 4)
    {
      rgba[i] = 255; // composited over the background, the image is opaque like a window's
    }
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetName("Colors");
    colors->SetNumberOfComponents(4);
    colors->SetNumberOfTuples(image.pixelCount());
    std::memcpy(colors->GetPointer(0), rgba.data(), rgba.size());
    vtkNew<vtkFloatArray> depth;
    depth->SetName("Depth");
    depth->SetNumberOfTuples(image.pixelCount());
    std::copy(image.Depth.begin(), image.Depth.end(), depth->GetPointer(0));
    output->GetPointData()->SetScalars(colors);
    output->GetPointData()->AddArray(depth);
  }
  catch (const std::exception& e) // e.g. std::bad_alloc on a machine with less free memory
  {
    vtkErrorMacro(<< "Could not render a " << width << "x" << height << " image: " << e.what());
    return 0;
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkSightlineImageRenderer::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Size: " << this->Size[0] << " x " << this->Size[1] << "\n";
  os << indent << "Background: (" << this->Background[0] << ", " << this->Background[1] << ", "
     << this->Background[2] << ")\n";
  os << indent << "ActiveCamera: " << this->ActiveCamera << "\n";
  os << indent << "Actors: " << this->Actors->GetNumberOfItems() << "\n";
  os << indent << "Volumes: " << this->Volumes->GetNumberOfItems() << "\n";
  os << indent << "ImageSlices: " << this->ImageSlices->GetNumberOfItems() << "\n";
  os << indent << "Lights: " << this->Lights->GetNumberOfItems() << "\n";
}
