// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineSphericalVolumeRepresentation.h"

#include "vtkCompositeDataSet.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPVLODVolume.h"
#include "vtkPVRenderView.h"
#include "vtkRectilinearGrid.h"
#include "vtkRenderer.h"
#include "vtkSightlineSphericalVolumeMapper.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkVolumeProperty.h"

vtkStandardNewMacro(vtkSightlineSphericalVolumeRepresentation);

vtkSightlineSphericalVolumeRepresentation::vtkSightlineSphericalVolumeRepresentation()
  : Mapper(vtkSmartPointer<vtkSightlineSphericalVolumeMapper>::New())
{
  this->Actor->SetMapper(this->Mapper);
  this->Actor->SetProperty(this->Property);
}

vtkSightlineSphericalVolumeRepresentation::~vtkSightlineSphericalVolumeRepresentation() = default;

vtkSightlineSphericalVolumeMapper* vtkSightlineSphericalVolumeRepresentation::GetSphericalVolumeMapper()
{
  return this->Mapper;
}

int vtkSightlineSphericalVolumeRepresentation::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkRectilinearGrid");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkSightlineSphericalVolumeRepresentation::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestUpdateExtent(request, inputVector, outputVector))
  {
    return 0;
  }
  // Until ranks blend volumes in visibility order, one rank traces the whole grid: IceT's
  // depth compositing of two ranks' halves of a translucent volume keeps only the nearer half
  // at each pixel. Rank 0 asks for the whole extent, the others for none (sources and readers
  // that honour sub-extents then make nothing there).
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const bool root = !controller || controller->GetLocalProcessId() == 0;
  for (int i = 0; i < inputVector[0]->GetNumberOfInformationObjects(); ++i)
  {
    vtkInformation* inInfo = inputVector[0]->GetInformationObject(i);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), root ? 0 : 1);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), root ? 1 : 2);
    if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    {
      int extent[6] = { 0, -1, 0, -1, 0, -1 };
      if (root)
      {
        inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
      }
      inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), extent, 6);
    }
  }
  return 1;
}

int vtkSightlineSphericalVolumeRepresentation::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMath::UninitializeBounds(this->DataBounds);
  this->DataSize = 0;
  this->Cache = nullptr;
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const bool root = !controller || controller->GetLocalProcessId() == 0;
  if (root && inputVector[0]->GetNumberOfInformationObjects() == 1)
  {
    if (vtkDataObject* input = vtkDataObject::GetData(inputVector[0], 0))
    {
      this->Cache.TakeReference(input->NewInstance());
      this->Cache->ShallowCopy(input);
      this->DataSize = this->Cache->GetActualMemorySize();
      // The mapper knows the world bounds of the grid's (r, theta, phi) cells.
      this->Mapper->SetInputDataObject(this->Cache);
      const double* bounds = this->Mapper->GetBounds();
      if (vtkMath::AreBoundsInitialized(bounds))
      {
        std::copy(bounds, bounds + 6, this->DataBounds);
      }
    }
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

int vtkSightlineSphericalVolumeRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request, inInfo, outInfo))
  {
    return 0;
  }
  if (request == vtkPVView::REQUEST_UPDATE())
  {
    vtkPVView::SetPiece(inInfo, this, this->Cache);
    vtkPVRenderView::SetGeometryBounds(inInfo, this, this->DataBounds);
    // Traced where the grid is (see REQUEST_RENDER): a pvserver's client, which has no grid,
    // must not render locally, so the view renders on the server whatever the data size.
    vtkPVRenderView::SetRequiresDistributedRendering(inInfo, this, true);
  }
  else if (request == vtkPVView::REQUEST_RENDER())
  {
    // The grid is traced where it was produced (builtin, pvbatch and pvserver ranks are data
    // and render server at once): ParaView 5.11's delivery turned each coordinate array of a
    // vtkRectilinearGrid into one value per point (36750 radii for a 30 x 25 x 49 grid).
    this->Mapper->SetInputDataObject(this->Cache);
  }
  return 1;
}

bool vtkSightlineSphericalVolumeRepresentation::AddToView(vtkView* view)
{
  auto* renderView = vtkPVRenderView::SafeDownCast(view);
  if (!renderView)
  {
    return false;
  }
  renderView->GetRenderer()->AddVolume(this->Actor);
  return this->Superclass::AddToView(view);
}

bool vtkSightlineSphericalVolumeRepresentation::RemoveFromView(vtkView* view)
{
  auto* renderView = vtkPVRenderView::SafeDownCast(view);
  if (!renderView)
  {
    return false;
  }
  renderView->GetRenderer()->RemoveVolume(this->Actor);
  return this->Superclass::RemoveFromView(view);
}

void vtkSightlineSphericalVolumeRepresentation::SetInputArrayToProcess(
  int idx, int port, int connection, int fieldAssociation, const char* name)
{
  this->Superclass::SetInputArrayToProcess(idx, port, connection, fieldAssociation, name);
  if (idx != 0)
  {
    return;
  }
  if (name && name[0])
  {
    this->Mapper->SelectScalarArray(name);
    this->Mapper->SetScalarMode(fieldAssociation == vtkDataObject::FIELD_ASSOCIATION_CELLS
        ? VTK_SCALAR_MODE_USE_CELL_FIELD_DATA
        : VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);
  }
  else
  {
    this->Mapper->SetScalarMode(VTK_SCALAR_MODE_DEFAULT);
  }
}

void vtkSightlineSphericalVolumeRepresentation::SetShade(bool shade)
{
  this->Property->SetShade(shade);
}

void vtkSightlineSphericalVolumeRepresentation::SetCoordinateSystem(int system)
{
  this->Mapper->SetCoordinateSystem(system);
}

void vtkSightlineSphericalVolumeRepresentation::SetAngleUnits(int units)
{
  this->Mapper->SetAngleUnits(units);
}

void vtkSightlineSphericalVolumeRepresentation::SetPolarAngle(int angle)
{
  this->Mapper->SetPolarAngle(angle);
}

void vtkSightlineSphericalVolumeRepresentation::SetInterpolatePointData(int interpolate)
{
  this->Mapper->SetInterpolatePointData(interpolate);
}

void vtkSightlineSphericalVolumeRepresentation::SetSampleDistance(double distance)
{
  this->Mapper->SetSampleDistance(distance);
}

void vtkSightlineSphericalVolumeRepresentation::SetMinimumTransmittance(double transmittance)
{
  this->Mapper->SetMinimumTransmittance(transmittance);
}

void vtkSightlineSphericalVolumeRepresentation::SetInteractiveSubsampling(int step)
{
  this->Mapper->SetInteractiveSubsampling(step);
}

void vtkSightlineSphericalVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Cache: " << (this->Cache ? this->Cache->GetClassName() : "(none)") << "\n";
}
