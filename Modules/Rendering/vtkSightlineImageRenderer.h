// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineImageRenderer
 * @brief   Renders Sightline actors straight to an image, without OpenGL or a window.
 *
 * The GL-free path for batch and server use. Give it actors whose mappers are
 * vtkSightlineMapper subclasses (volumes whose mapper is a vtkSightlineSphericalVolumeMapper,
 * and image slices drawn by a vtkImageSliceMapper: vtkImageSlice, vtkImageActor), a camera, an image size, a background and optionally lights
 * (VTK's automatic headlight otherwise); its output is a vtkImageData of Width x Height
 * points with
 * - "Colors": unsigned char RGBA (the active scalars), the actors composited over the
 *   background (so alpha is 255), bottom row first like vtkWindowToImageFilter's output;
 * - "Depth": float window depth in [0, 1] as OpenGL would store it (1 where nothing was hit).
 *
 * The pixels equal what the same actors show in a vtkRenderWindow of the same size (within
 * one 8-bit level: both trace through the mappers' SightlineTracer interface, as the window
 * does). Write the image with
 * vtkPNGWriter, or keep the depth with the kernel's EXR output.
 *
 * The output is recomputed when this filter, its camera, lights, actors (and their
 * properties and mappers) or the mappers' input algorithms are modified.
 *
 * @sa vtkSightlineMapper vtkWindowToImageFilter
 */
#ifndef vtkSightlineImageRenderer_h
#define vtkSightlineImageRenderer_h

#include "SightlineRenderingModule.h" // for export macro
#include "vtkImageAlgorithm.h"
#include "vtkNew.h" // for vtkNew
#include "vtkPropCollection.h"   // for vtkNew<vtkPropCollection>
#include "vtkVolumeCollection.h" // for vtkNew<vtkVolumeCollection>

class vtkActor;
class vtkActorCollection;
class vtkImageSlice;
class vtkPropCollection;
class vtkVolume;
class vtkCamera;
class vtkLight;
class vtkLightCollection;

class SIGHTLINERENDERING_EXPORT vtkSightlineImageRenderer : public vtkImageAlgorithm
{
public:
  static vtkSightlineImageRenderer* New();
  vtkTypeMacro(vtkSightlineImageRenderer, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Actors to render. Actors whose mapper is not a vtkSightlineMapper, and invisible
   * actors, are skipped (the former with a warning).
   */
  void AddActor(vtkActor* actor);
  void RemoveActor(vtkActor* actor);
  void RemoveAllActors();
  vtkActorCollection* GetActors();
  ///@}

  ///@{
  /**
   * Volumes to render after the actors (as VTK's volumetric pass): rays stop at the actors'
   * depth. Volumes whose mapper is not a vtkSightlineSphericalVolumeMapper are skipped with a
   * warning.
   */
  void AddVolume(vtkVolume* volume);
  void RemoveVolume(vtkVolume* volume);
  void RemoveAllVolumes();
  vtkVolumeCollection* GetVolumes();
  ///@}

  ///@{
  /**
   * Image slices (vtkImageSlice or vtkImageActor with a vtkImageSliceMapper, e.g. an
   * anatomical underlay) drawn as OpenGL draws their textured quad: the displayed slice's
   * voxels coloured by the vtkImageProperty (window/level or lookup table, opacity, nearest or
   * linear interpolation; cubic is drawn as linear), placed by the prop's matrix and the
   * image's origin, spacing and direction, with the mapper's Border, Cropping,
   * SliceFacesCamera and SliceAtFocalPoint. Each slice is a plane traced exactly, so glyphs
   * crossing it are cut by it as the depth test cuts them in a window. Only the displayed slice
   * is requested from the slice's input (a streaming reader reads just that). Slices drawn by
   * other mappers (vtkImageResliceMapper) are skipped with a warning.
   */
  void AddImageSlice(vtkImageSlice* slice);
  void RemoveImageSlice(vtkImageSlice* slice);
  void RemoveAllImageSlices();
  vtkPropCollection* GetImageSlices();
  ///@}

  ///@{
  /**
   * The camera that views the scene (required).
   */
  void SetActiveCamera(vtkCamera* camera);
  vtkCamera* GetActiveCamera() { return this->ActiveCamera; }
  ///@}

  ///@{
  /**
   * Lights. With none, VTK's automatic headlight is used, as vtkRenderer does.
   */
  void AddLight(vtkLight* light);
  void RemoveAllLights();
  vtkLightCollection* GetLights();
  ///@}

  ///@{
  /**
   * Image size in pixels. Default 300 x 300, as vtkRenderWindow. A size whose buffers would
   * take more than 8 GiB (60 bytes a pixel: about 143 million pixels, e.g. 11900 x 11900) is
   * refused with an error before anything is allocated.
   */
  vtkSetVector2Macro(Size, int);
  vtkGetVector2Macro(Size, int);
  ///@}

  ///@{
  /**
   * Background colour (RGB in [0, 1]). Default black, as vtkRenderer.
   */
  vtkSetVector3Macro(Background, double);
  vtkGetVector3Macro(Background, double);
  ///@}

  /**
   * Reset the camera so every actor, volume and image slice is visible, as vtkRenderer::ResetCamera does (view
   * direction and view-up kept). Creates a camera if none is set.
   */
  void ResetCamera();

  vtkMTimeType GetMTime() override;

protected:
  vtkSightlineImageRenderer();
  ~vtkSightlineImageRenderer() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Size[2] = { 300, 300 };
  double Background[3] = { 0.0, 0.0, 0.0 };
  vtkCamera* ActiveCamera = nullptr;
  vtkNew<vtkActorCollection> Actors;
  vtkNew<vtkVolumeCollection> Volumes;
  vtkNew<vtkPropCollection> ImageSlices;
  vtkNew<vtkLightCollection> Lights;

private:
  vtkSightlineImageRenderer(const vtkSightlineImageRenderer&) = delete;
  void operator=(const vtkSightlineImageRenderer&) = delete;
};

#endif
