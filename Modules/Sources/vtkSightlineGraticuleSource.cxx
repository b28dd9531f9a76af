// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineGraticuleSource.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkSightlineGraticuleSource);

namespace
{
constexpr double Degree = 3.14159265358979323846 / 180.0;

// Collects polylines, splitting each where it leaves the visible hemisphere.
class LineWriter
{
public:
  LineWriter(double radius, const double facing[3])
    : Radius(radius)
  {
    const double norm =
      std::sqrt(facing[0] * facing[0] + facing[1] * facing[1] + facing[2] * facing[2]);
    this->Clipped = norm > 0.0;
    for (int i = 0; i < 3; ++i)
    {
      this->Facing[i] = this->Clipped ? facing[i] / norm : 0.0;
    }
    // Double points: float32 would put them up to 5e-4 km off an Earth-sized sphere.
    this->Points->SetDataTypeToDouble();
    this->Latitudes->SetName("Latitude");
    this->Longitudes->SetName("Longitude");
  }

  // One line through (latitude, longitude) samples in degrees.
  void Line(const std::vector<double>& latitude, const std::vector<double>& longitude)
  {
    std::vector<vtkIdType> run;
    for (std::size_t i = 0; i < latitude.size(); ++i)
    {
      const double lat = latitude[i] * Degree;
      const double lon = longitude[i] * Degree;
      const double p[3] = { this->Radius * std::cos(lat) * std::cos(lon),
        this->Radius * std::cos(lat) * std::sin(lon), this->Radius * std::sin(lat) };
      const bool visible = !this->Clipped ||
        p[0] * this->Facing[0] + p[1] * this->Facing[1] + p[2] * this->Facing[2] > 0.0;
      if (visible)
      {
        run.push_back(this->Points->InsertNextPoint(p));
        this->Latitudes->InsertNextValue(latitude[i]);
        this->Longitudes->InsertNextValue(longitude[i]);
      }
      if (!visible || i + 1 == latitude.size())
      {
        if (run.size() >= 2)
        {
          this->Lines->InsertNextCell(static_cast<vtkIdType>(run.size()), run.data());
        }
        run.clear();
      }
    }
  }

  void Output(vtkPolyData* output)
  {
    output->SetPoints(this->Points);
    output->SetLines(this->Lines);
    output->GetPointData()->AddArray(this->Latitudes);
    output->GetPointData()->AddArray(this->Longitudes);
  }

private:
  double Radius;
  bool Clipped = false;
  double Facing[3];
  vtkNew<vtkPoints> Points;
  vtkNew<vtkCellArray> Lines;
  vtkNew<vtkDoubleArray> Latitudes;
  vtkNew<vtkDoubleArray> Longitudes;
};

std::vector<double> Samples(double from, double to, double perDegree)
{
  const int n = std::max(2, static_cast<int>(std::ceil((to - from) * perDegree)) + 1);
  std::vector<double> values(n);
  for (int i = 0; i < n; ++i)
  {
    values[i] = from + (to - from) * i / (n - 1);
  }
  return values;
}

// Multiples of `step` in [from, to] (with a little slack for rounding).
std::vector<double> Multiples(double from, double to, double step)
{
  std::vector<double> values;
  const double slack = 1e-9 * step;
  for (double k = std::ceil((from - slack) / step); k * step <= to + slack; k += 1.0)
  {
    values.push_back(k * step);
  }
  return values;
}
} // namespace

vtkSightlineGraticuleSource::vtkSightlineGraticuleSource()
{
  this->SetNumberOfInputPorts(0);
}

int vtkSightlineGraticuleSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  const double lat0 = std::max(-90.0, std::min(this->LatitudeRange[0], this->LatitudeRange[1]));
  const double lat1 = std::min(90.0, std::max(this->LatitudeRange[0], this->LatitudeRange[1]));
  const double lon0 = std::min(this->LongitudeRange[0], this->LongitudeRange[1]);
  double lon1 = std::max(this->LongitudeRange[0], this->LongitudeRange[1]);
  if (!std::isfinite(lat0) || !std::isfinite(lat1) || !std::isfinite(lon0) ||
    !std::isfinite(lon1) || !std::isfinite(this->Radius))
  {
    vtkErrorMacro(<< "ranges and radius must be finite");
    return 0;
  }
  const bool wholeTurn = lon1 - lon0 >= 360.0 - 1e-9;
  lon1 = std::min(lon1, lon0 + 360.0);
  LineWriter writer(this->Radius, this->FacingDirection);
  const std::vector<double> longitudes = Samples(lon0, lon1, this->SamplesPerDegree);
  const std::vector<double> latitudes = Samples(lat0, lat1, this->SamplesPerDegree);
  std::vector<double> constant;
  for (double lat : Multiples(lat0, lat1, this->Step))
  {
    if (std::abs(lat) < 90.0 - 1e-9) // the poles are points
    {
      constant.assign(longitudes.size(), lat);
      writer.Line(constant, longitudes);
    }
  }
  for (double lon : Multiples(lon0, lon1, this->Step))
  {
    if (wholeTurn && lon >= lon0 + 360.0 - 1e-9)
    {
      continue; // a whole turn's last meridian is its first
    }
    constant.assign(latitudes.size(), lon);
    writer.Line(latitudes, constant);
  }
  writer.Output(output);
  return 1;
}

void vtkSightlineGraticuleSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "Step: " << this->Step << "\n";
  os << indent << "LatitudeRange: " << this->LatitudeRange[0] << " " << this->LatitudeRange[1]
     << "\n";
  os << indent << "LongitudeRange: " << this->LongitudeRange[0] << " "
     << this->LongitudeRange[1] << "\n";
  os << indent << "SamplesPerDegree: " << this->SamplesPerDegree << "\n";
  os << indent << "FacingDirection: " << this->FacingDirection[0] << " "
     << this->FacingDirection[1] << " " << this->FacingDirection[2] << "\n";
}
