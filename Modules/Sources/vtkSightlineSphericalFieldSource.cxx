// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineSphericalFieldSource.h"

#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkRectilinearGrid.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include "sightline/volumes/EarthModel.h"
#include "sightline/volumes/SphericalFields.h"

#include <algorithm>
#include <cmath>
#include <exception>

vtkStandardNewMacro(vtkSightlineSphericalFieldSource);

namespace
{
constexpr double kEarthRadiusKm = 6371.0;
constexpr double kCoreMantleBoundaryKm = 3480.0;
constexpr double kMohoKm = 6346.6;

std::vector<double> Uniform(double a, double b, int cells)
{
  std::vector<double> breakpoints(static_cast<std::size_t>(cells) + 1);
  for (int i = 0; i <= cells; ++i)
  {
    breakpoints[i] = a + (b - a) * i / cells;
  }
  breakpoints.back() = b;
  return breakpoints;
}
} // namespace

//------------------------------------------------------------------------------
vtkSightlineSphericalFieldSource::vtkSightlineSphericalFieldSource()
{
  this->SetNumberOfInputPorts(0);
  this->PolarRange[0] = 0.0;
  this->PolarRange[1] = vtkMath::Pi();
  this->AzimuthRange[0] = 0.0;
  this->AzimuthRange[1] = 2.0 * vtkMath::Pi();
}

//------------------------------------------------------------------------------
const char* vtkSightlineSphericalFieldSource::GetFieldAsString()
{
  switch (this->Field)
  {
    case RADIUS_SQUARED:
      return "r2";
    case PREM_DENSITY:
      return "density";
    default:
      return "chi";
  }
}

//------------------------------------------------------------------------------
int vtkSightlineSphericalFieldSource::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  int extent[6] = { 0, this->RadialResolution, 0, this->PolarResolution, 0,
    this->AzimuthalResolution };
  // Aligned breakpoints may add a cell or two per discontinuity; RequestData reports the
  // extent it actually produced, and the whole extent is computed the same way here.
  if (this->AlignWithDiscontinuities)
  {
    std::vector<double> jumps;
    const double outer = this->RadiusRange[1];
    if (this->Field == STEP)
      jumps.push_back(0.5 * outer);
    else if (this->Field == PREM_DENSITY)
      for (const auto& layer : sightline::premLayers())
        jumps.push_back(layer.outerRadiusKm / kEarthRadiusKm * outer);
    std::vector<double> ends{ this->RadiusRange[0] };
    for (double j : jumps)
      if (j > this->RadiusRange[0] && j < this->RadiusRange[1])
        ends.push_back(j);
    ends.push_back(this->RadiusRange[1]);
    int cells = 0;
    const double total = this->RadiusRange[1] - this->RadiusRange[0];
    for (std::size_t s = 0; s + 1 < ends.size(); ++s)
      cells += std::max(1, int(std::lround(this->RadialResolution * (ends[s + 1] - ends[s]) / total)));
    extent[1] = cells;
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  // Any sub-extent can be produced: the pipeline splits piece requests into extents.
  outInfo->Set(CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkSightlineSphericalFieldSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkRectilinearGrid* output = vtkRectilinearGrid::GetData(outInfo);
  const double r0 = this->RadiusRange[0], r1 = this->RadiusRange[1];
  if (!(r1 > 0.0))
  {
    vtkErrorMacro(<< "RadiusRange must end above 0, got [" << r0 << ", " << r1 << "].");
    return 0;
  }

  // Radii where the field jumps, in output units.
  std::vector<double> jumps;
  if (this->Field == STEP)
  {
    jumps.push_back(0.5 * r1);
  }
  else if (this->Field == PREM_DENSITY)
  {
    for (const auto& layer : sightline::premLayers())
      jumps.push_back(layer.outerRadiusKm / kEarthRadiusKm * r1);
  }

  sightline::SphericalGrid grid;
  if (this->AlignWithDiscontinuities)
  {
    std::vector<double> ends{ r0 };
    for (double j : jumps)
      if (j > r0 && j < r1)
        ends.push_back(j);
    ends.push_back(r1);
    grid.radius.push_back(r0);
    for (std::size_t s = 0; s + 1 < ends.size(); ++s)
    {
      const int cells =
        std::max(1, int(std::lround(this->RadialResolution * (ends[s + 1] - ends[s]) / (r1 - r0))));
      const std::vector<double> piece = Uniform(ends[s], ends[s + 1], cells);
      grid.radius.insert(grid.radius.end(), piece.begin() + 1, piece.end());
    }
  }
  else
  {
    grid.radius = Uniform(r0, r1, this->RadialResolution);
  }
  grid.polar = Uniform(this->PolarRange[0], this->PolarRange[1], this->PolarResolution);
  grid.azimuth = Uniform(this->AzimuthRange[0], this->AzimuthRange[1], this->AzimuthalResolution);
  try
  {
    grid.validate();
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Bad grid settings: " << e.what());
    return 0;
  }

  // The field at (r, theta, phi), r in output units.
  sightline::SphericalFunction field;
  const sightline::RadialStepField chi = sightline::RadialStepField::chiHalf();
  const double amplitude = this->PerturbationAmplitude;
  switch (this->Field)
  {
    case RADIUS_SQUARED:
      field = [r1](double r, double, double) { return r <= r1 ? (r / r1) * (r / r1) : 0.0; };
      break;
    case PREM_DENSITY:
      field = [r1, amplitude](double r, double theta, double phi)
      {
        const double km = std::min(r / r1 * kEarthRadiusKm, kEarthRadiusKm);
        double density = sightline::premDensity(km);
        if (km > kCoreMantleBoundaryKm && km < kMohoKm)
        {
          const double s = std::sin(theta);
          density *= 1.0 + amplitude * s * s * std::cos(2.0 * phi);
        }
        return density;
      };
      break;
    default:
      field = [r1, chi](double r, double, double) { return chi(r / r1); };
  }

  // The requested extent, cut from the whole grid's breakpoints (so the alignment with the
  // discontinuities is the whole grid's, whatever the split): point indices along r, theta, phi.
  int extent[6] = { 0, int(grid.radius.size()) - 1, 0, int(grid.polar.size()) - 1, 0,
    int(grid.azimuth.size()) - 1 };
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    int update[6];
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), update);
    for (int a = 0; a < 3; ++a)
    {
      extent[2 * a] = std::max(extent[2 * a], update[2 * a]);
      extent[2 * a + 1] = std::min(extent[2 * a + 1], update[2 * a + 1]);
    }
  }
  if (extent[0] > extent[1] || extent[2] > extent[3] || extent[4] > extent[5])
  {
    output->Initialize(); // an empty piece (more pieces than cells)
    return 1;
  }
  auto cut = [&](const std::vector<double>& b, int axis) {
    return std::vector<double>(b.begin() + extent[2 * axis], b.begin() + extent[2 * axis + 1] + 1);
  };
  const std::vector<double> radius = cut(grid.radius, 0), polar = cut(grid.polar, 1),
                            azimuth = cut(grid.azimuth, 2);

  vtkNew<vtkDoubleArray> values;
  values->SetName(this->GetFieldAsString());
  try
  {
    if (this->OutputCellData)
    {
      // Each cell at its coordinate midpoint, as sightline::sampleCellMidpoints samples it.
      const std::size_t nr = radius.size() - 1, np = polar.size() - 1, na = azimuth.size() - 1;
      values->SetNumberOfTuples(vtkIdType(nr * np * na));
      vtkIdType id = 0;
      for (std::size_t k = 0; k < na; ++k)
        for (std::size_t j = 0; j < np; ++j)
          for (std::size_t i = 0; i < nr; ++i)
            values->SetValue(id++, field(0.5 * (radius[i] + radius[i + 1]),
              0.5 * (polar[j] + polar[j + 1]), 0.5 * (azimuth[k] + azimuth[k + 1])));
    }
    else
    {
      values->SetNumberOfTuples(vtkIdType(radius.size() * polar.size() * azimuth.size()));
      vtkIdType id = 0;
      for (double phi : azimuth)
        for (double theta : polar)
          for (double r : radius)
            values->SetValue(id++, field(r, theta, phi));
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Could not sample the " << this->GetFieldAsString() << " field: " << e.what());
    return 0;
  }

  auto coordinates = [](const std::vector<double>& b)
  {
    vtkNew<vtkDoubleArray> array;
    array->SetNumberOfTuples(static_cast<vtkIdType>(b.size()));
    std::copy(b.begin(), b.end(), array->GetPointer(0));
    return vtkSmartPointer<vtkDoubleArray>(array.Get());
  };
  output->SetExtent(extent);
  output->SetXCoordinates(coordinates(radius));
  output->SetYCoordinates(coordinates(polar));
  output->SetZCoordinates(coordinates(azimuth));
  if (this->OutputCellData)
    output->GetCellData()->SetScalars(values);
  else
    output->GetPointData()->SetScalars(values);
  return 1;
}

//------------------------------------------------------------------------------
void vtkSightlineSphericalFieldSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Field: " << this->GetFieldAsString() << "\n";
  os << indent << "Resolution (r, theta, phi): " << this->RadialResolution << ", "
     << this->PolarResolution << ", " << this->AzimuthalResolution << "\n";
  os << indent << "RadiusRange: " << this->RadiusRange[0] << " " << this->RadiusRange[1] << "\n";
  os << indent << "PolarRange: " << this->PolarRange[0] << " " << this->PolarRange[1] << "\n";
  os << indent << "AzimuthRange: " << this->AzimuthRange[0] << " " << this->AzimuthRange[1] << "\n";
  os << indent << "AlignWithDiscontinuities: " << (this->AlignWithDiscontinuities ? "on" : "off")
     << "\n";
  os << indent << "PerturbationAmplitude: " << this->PerturbationAmplitude << "\n";
  os << indent << "OutputCellData: " << (this->OutputCellData ? "on" : "off") << "\n";
}
