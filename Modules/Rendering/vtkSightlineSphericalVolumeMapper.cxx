// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineSphericalVolumeMapper.h"

#include "SightlineKernelConversions.h"
#include "SightlineMapperInput.h"
#include "SightlineWindowFrame.h"

#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkAlgorithm.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRectilinearGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "sightline/volumes/CylindricalGrid.h"
#include "sightline/core/Framebuffer.h"
#include "sightline/volumes/SphericalFields.h"
#include "sightline/volumes/SphericalVolume.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>

class vtkSightlineSphericalVolumeMapper::vtkInternals
{
public:
  // The input as a kernel grid and cell values, rebuilt when the input or the mapper change.
  std::unique_ptr<sightline::SphericalTraversal> Traversal;  // spherical input, or
  std::unique_ptr<sightline::CylindricalTraversal> Cylinder; // cylindrical input
  std::vector<sightline::dvec3> Centres;                     // for shading, on first use
  std::vector<double> Values;      // per cell (point data: the mean of its corners)
  std::vector<double> PointValues; // point data in kernel order, empty for cell data
  double PointRange[2] = { 0.0, 1.0 };
  std::vector<sightline::dvec3> Gradients; // computed on first use with shading
  vtkTimeStamp GridTime;
  double Bounds[6] = { 1, -1, 1, -1, 1, -1 };

  // Transfer-function samples per cell, rebuilt when the values or the property change.
  std::vector<sightline::TransferSample> Unshaded;
  vtkMTimeType UnshadedPropertyTime = 0;
  vtkMTimeType UnshadedGridTime = 0;

  // The input as the grid drawn: one rectilinear grid, or the first non-empty one of a
  // composite input.
  SightlineMapperInput Input{ "vtkRectilinearGrid", SightlineMapperInput::Leaves::First };

  // The window path: frame cache, compositing, interactive subsampling.
  SightlineWindowFrame Window;
  bool WarnedShadedPoints = false;
};

vtkStandardNewMacro(vtkSightlineSphericalVolumeMapper);

//------------------------------------------------------------------------------
vtkSightlineSphericalVolumeMapper::vtkSightlineSphericalVolumeMapper()
  : Internals(new vtkInternals)
{
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 6; ++i)
  {
    this->Region[i] = i % 2 ? inf : -inf;
  }
}

//------------------------------------------------------------------------------
void vtkSightlineSphericalVolumeMapper::SetRegionToAllOfSpace()
{
  const double inf = std::numeric_limits<double>::infinity();
  this->SetRegion(-inf, inf, -inf, inf, -inf, inf);
}

//------------------------------------------------------------------------------
vtkSightlineSphericalVolumeMapper::~vtkSightlineSphericalVolumeMapper() = default;

//------------------------------------------------------------------------------
int vtkSightlineSphericalVolumeMapper::FillInputPortInformation(
  int vtkNotUsed(port), vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkRectilinearGrid");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  // Without an input the mapper draws nothing; updating it is no error.
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

namespace
{
std::vector<double> Coordinates(vtkDataArray* array, double scale)
{
  std::vector<double> values;
  if (array)
  {
    values.resize(static_cast<std::size_t>(array->GetNumberOfTuples()));
    for (std::size_t i = 0; i < values.size(); ++i)
    {
      values[i] = array->GetComponent(static_cast<vtkIdType>(i), 0) * scale;
    }
  }
  return values;
}

// Box of a spherical section: the extremes of x, y and z lie at the ends of each coordinate
// range or where an axis is crossed inside it.
void SectionBounds(const sightline::SphericalGrid& grid, double bounds[6])
{
  const double pi = vtkMath::Pi();
  std::vector<double> thetas{ grid.polar.front(), grid.polar.back() };
  for (double t : { 0.0, 0.5 * pi, pi })
  {
    if (t > grid.polar.front() && t < grid.polar.back())
    {
      thetas.push_back(t);
    }
  }
  std::vector<double> phis{ grid.azimuth.front(), grid.azimuth.back() };
  for (int quarter = -8; quarter <= 8; ++quarter)
  {
    const double p = 0.5 * pi * quarter;
    if (p > grid.azimuth.front() && p < grid.azimuth.back())
    {
      phis.push_back(p);
    }
  }
  bounds[0] = bounds[2] = bounds[4] = std::numeric_limits<double>::infinity();
  bounds[1] = bounds[3] = bounds[5] = -std::numeric_limits<double>::infinity();
  for (double r : { grid.radius.front(), grid.radius.back() })
  {
    for (double t : thetas)
    {
      for (double p : phis)
      {
        const sightline::dvec3 x = sightline::sphericalToCartesian(r, t, p);
        for (int axis = 0; axis < 3; ++axis)
        {
          bounds[2 * axis] = std::min(bounds[2 * axis], x[axis]);
          bounds[2 * axis + 1] = std::max(bounds[2 * axis + 1], x[axis]);
        }
      }
    }
  }
}

// Box of a cylindrical section: x and y as a spherical section's equator, z from the heights.
void SectionBounds(const sightline::CylindricalGrid& grid, double bounds[6])
{
  sightline::SphericalGrid equator{ grid.radius, { 0.0, 0.5 * vtkMath::Pi(), vtkMath::Pi() }, grid.azimuth };
  SectionBounds(equator, bounds);
  bounds[4] = grid.height.front();
  bounds[5] = grid.height.back();
}

// Values the renderer can use: finite and small enough that means of eight corners,
// differences for gradients and the span of the point-data table stay finite. Others are
// drawn empty, with a warning.
constexpr double kLargestUsableValue = 1e300;
bool IsUsableValue(double v)
{
  return std::abs(v) <= kLargestUsableValue;
}

// The property's colour and extinction at a value: opacity a per unit distance u is the
// extinction -ln(1 - a) / u.
sightline::TransferSample SampleTransfer(vtkVolumeProperty* property, double v)
{
  sightline::TransferSample sample;
  if (std::isnan(v))
  {
    return sample;
  }
  const double a = property->GetScalarOpacity(0)->GetValue(v);
  if (!(a > 0.0))
  {
    return sample;
  }
  const double unit = property->GetScalarOpacityUnitDistance(0);
  sample.extinction = a >= 1.0 ? std::numeric_limits<double>::infinity() : -std::log1p(-a) / unit;
  if (property->GetColorChannels(0) == 3)
  {
    double rgb[3];
    property->GetRGBTransferFunction(0)->GetColor(v, rgb);
    sample.color = sightline::vec3(rgb[0], rgb[1], rgb[2]);
  }
  else
  {
    sample.color = sightline::vec3(static_cast<float>(property->GetGrayTransferFunction(0)->GetValue(v)));
  }
  return sample;
}
} // namespace

//------------------------------------------------------------------------------
bool vtkSightlineSphericalVolumeMapper::UpdateScene()
{
  vtkInternals& in = *this->Internals;
  // No input, or a grid without points, draws nothing, quietly (ParaView creates mappers
  // before data arrives); a composite input gives its first non-empty grid.
  auto* input = vtkRectilinearGrid::SafeDownCast(in.Input.Get(this));
  if (!input)
  {
    in.Traversal.reset();
    in.Cylinder.reset();
    return false;
  }
  if ((in.Traversal || in.Cylinder) && in.GridTime > in.Input.GetInputTime(this) &&
    in.GridTime > this->GetMTime())
  {
    return true;
  }
  in.Traversal.reset();
  in.Cylinder.reset();
  in.Gradients.clear();
  in.Centres.clear();

  const bool cylindrical = this->CoordinateSystem == CYLINDRICAL;
  const bool latitude = !cylindrical && this->PolarAngle == LATITUDE;
  sightline::SphericalGrid sphere;
  sightline::CylindricalGrid cylinder;
  if (!this->ReadCoordinates(input, sphere, cylinder))
  {
    return false;
  }
  int dims[3]; // cells along x, y, z of the input
  if (cylindrical)
  {
    dims[0] = cylinder.radialCells();
    dims[1] = cylinder.azimuthalCells();
    dims[2] = cylinder.heightCells();
  }
  else
  {
    dims[0] = sphere.radialCells();
    dims[1] = sphere.polarCells();
    dims[2] = sphere.azimuthalCells();
  }

  int cellFlag = 0;
  vtkDataArray* scalars = vtkAbstractMapper::GetScalars(input, this->ScalarMode,
    this->ArrayAccessMode, this->ArrayId, this->ArrayName, cellFlag);
  if (!scalars)
  {
    vtkErrorMacro(<< "The input has no scalars to render (point or cell data; see ScalarMode and "
                     "SelectScalarArray).");
    return false;
  }
  const int n0 = dims[0], n1 = dims[1], n2 = dims[2];
  const vtkIdType cells = vtkIdType(n0) * n1 * n2;
  const vtkIdType expected =
    cellFlag == 1 ? cells : vtkIdType(n0 + 1) * vtkIdType(n1 + 1) * vtkIdType(n2 + 1);
  if (scalars->GetNumberOfTuples() != expected)
  {
    vtkErrorMacro(<< "The scalar array '" << (scalars->GetName() ? scalars->GetName() : "")
                  << "' has " << scalars->GetNumberOfTuples() << " tuples for " << expected
                  << (cellFlag == 1 ? " cells." : " points."));
    return false;
  }
  if (scalars->GetNumberOfComponents() > 1)
  {
    vtkWarningMacro(<< "Only the first of the " << scalars->GetNumberOfComponents()
                    << " components of '" << (scalars->GetName() ? scalars->GetName() : "")
                    << "' is rendered.");
  }
  // Both kernel grids order cells as the input does (x fastest, then y, then z), except that
  // latitude input reverses y.
  in.Values.assign(std::size_t(cells), 0.0);
  in.PointValues.clear();
  if (cellFlag == 0)
  {
    // Point data in kernel order (latitude input reverses y), and its range for the table.
    in.PointValues.resize(std::size_t(expected));
    in.PointRange[0] = std::numeric_limits<double>::infinity();
    in.PointRange[1] = -std::numeric_limits<double>::infinity();
    for (int k = 0; k <= n2; ++k)
      for (int j = 0; j <= n1; ++j)
        for (int i = 0; i <= n0; ++i)
        {
          const int jInput = latitude ? n1 - j : j;
          double v = scalars->GetComponent(i + vtkIdType(n0 + 1) * (jInput + vtkIdType(n1 + 1) * k), 0);
          if (!IsUsableValue(v))
          {
            v = std::numeric_limits<double>::quiet_NaN();
          }
          in.PointValues[std::size_t(i) + std::size_t(n0 + 1) * (std::size_t(j) + std::size_t(n1 + 1) * k)] = v;
          if (!std::isnan(v))
          {
            in.PointRange[0] = std::min(in.PointRange[0], v);
            in.PointRange[1] = std::max(in.PointRange[1], v);
          }
        }
  }
  vtkIdType nanCount = 0;
  double firstUnusable = 0.0;
  for (int k = 0; k < n2; ++k)
  {
    for (int j = 0; j < n1; ++j)
    {
      const int jInput = latitude ? n1 - 1 - j : j;
      for (int i = 0; i < n0; ++i)
      {
        double value = 0.0;
        if (cellFlag == 1)
        {
          value = scalars->GetComponent(i + vtkIdType(n0) * (jInput + vtkIdType(n1) * k), 0);
        }
        else
        {
          // Point data: the mean of the cell's eight corners.
          for (int corner = 0; corner < 8; ++corner)
          {
            const vtkIdType pi = i + (corner & 1), pj = jInput + ((corner >> 1) & 1),
                            pk = k + ((corner >> 2) & 1);
            value += scalars->GetComponent(pi + vtkIdType(n0 + 1) * (pj + vtkIdType(n1 + 1) * pk), 0);
          }
          value *= 0.125;
        }
        if (!IsUsableValue(value))
        {
          if (nanCount == 0)
          {
            firstUnusable = value;
          }
          ++nanCount;
          value = std::numeric_limits<double>::quiet_NaN();
        }
        in.Values[std::size_t(i) + std::size_t(n0) * (std::size_t(j) + std::size_t(n1) * k)] = value;
      }
    }
  }
  if (nanCount > 0)
  {
    vtkWarningMacro(<< nanCount << " cells have NaN, infinite or out-of-range values (|v| > "
                    << kLargestUsableValue << ", e.g. " << firstUnusable
                    << "); they are drawn empty.");
  }
  if (cylindrical)
  {
    SectionBounds(cylinder, in.Bounds);
    in.Cylinder = std::make_unique<sightline::CylindricalTraversal>(std::move(cylinder));
  }
  else
  {
    SectionBounds(sphere, in.Bounds);
    in.Traversal = std::make_unique<sightline::SphericalTraversal>(std::move(sphere));
  }
  in.GridTime.Modified();
  return true;
}

//------------------------------------------------------------------------------
bool vtkSightlineSphericalVolumeMapper::ReadCoordinates(
  vtkRectilinearGrid* input, sightline::SphericalGrid& sphere, sightline::CylindricalGrid& cylinder)
{
  const double angleScale = this->AngleUnits == DEGREES ? vtkMath::Pi() / 180.0 : 1.0;
  const bool latitude = this->CoordinateSystem != CYLINDRICAL && this->PolarAngle == LATITUDE;
  if (this->CoordinateSystem == CYLINDRICAL)
  {
    cylinder.radius = Coordinates(input->GetXCoordinates(), 1.0);
    cylinder.azimuth = Coordinates(input->GetYCoordinates(), angleScale);
    cylinder.height = Coordinates(input->GetZCoordinates(), 1.0);
    try
    {
      cylinder.validate();
    }
    catch (const std::exception& e)
    {
      vtkErrorMacro(<< "The input is not a cylindrical grid (x = rho, y = azimuth in "
                    << (this->AngleUnits == DEGREES ? "degrees" : "radians") << ", z = height): "
                    << e.what());
      return false;
    }
    return true;
  }
  sphere.radius = Coordinates(input->GetXCoordinates(), 1.0);
  sphere.polar = Coordinates(input->GetYCoordinates(), angleScale);
  sphere.azimuth = Coordinates(input->GetZCoordinates(), angleScale);
  if (latitude)
  {
    // Colatitude = pi/2 - latitude reverses the order of the polar breakpoints and cells.
    for (double& b : sphere.polar)
    {
      b = 0.5 * vtkMath::Pi() - b;
    }
    std::reverse(sphere.polar.begin(), sphere.polar.end());
  }
  // Degrees converted to radians may land a rounding error outside [0, pi].
  for (double& b : sphere.polar)
  {
    if (std::abs(b) < 1e-12)
      b = 0.0;
    if (std::abs(b - vtkMath::Pi()) < 1e-12)
      b = vtkMath::Pi();
  }
  try
  {
    sphere.validate();
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "The input is not a spherical grid (x = r, y = "
                  << (latitude ? "latitude" : "colatitude") << ", z = azimuth, angles in "
                  << (this->AngleUnits == DEGREES ? "degrees" : "radians") << "): " << e.what());
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkSightlineSphericalVolumeMapper::ComputeSectionBounds(vtkRectilinearGrid* grid, double bounds[6])
{
  sightline::SphericalGrid sphere;
  sightline::CylindricalGrid cylinder;
  vtkMath::UninitializeBounds(bounds);
  if (!grid || !this->ReadCoordinates(grid, sphere, cylinder))
  {
    return false;
  }
  if (this->CoordinateSystem == CYLINDRICAL)
  {
    SectionBounds(cylinder, bounds);
  }
  else
  {
    SectionBounds(sphere, bounds);
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkSightlineSphericalVolumeMapper::ComputeCellRangeInBox(
  vtkRectilinearGrid* grid, const double box[6], int cellRange[6], int margin)
{
  sightline::SphericalGrid sphere;
  sightline::CylindricalGrid cylinder;
  if (!grid || !this->ReadCoordinates(grid, sphere, cylinder))
  {
    return false;
  }
  const sightline::dvec3 lower(box[0], box[2], box[4]), upper(box[1], box[3], box[5]);
  int first[3], last[3];
  const bool any = this->CoordinateSystem == CYLINDRICAL
    ? sightline::cellRangeInBox(cylinder, lower, upper, first, last)
    : sightline::cellRangeInBox(sphere, lower, upper, first, last);
  if (!any)
  {
    return false;
  }
  const bool cylindrical = this->CoordinateSystem == CYLINDRICAL;
  const int cells[3] = { cylindrical ? cylinder.radialCells() : sphere.radialCells(),
    cylindrical ? cylinder.azimuthalCells() : sphere.polarCells(),
    cylindrical ? cylinder.heightCells() : sphere.azimuthalCells() };
  const int azimuthAxis = cylindrical ? 1 : 2;
  const bool fullCircle = cylindrical ? cylinder.fullCircle() : sphere.fullCircle();
  margin = std::max(margin, 0);
  for (int axis = 0; axis < 3; ++axis)
  {
    if (axis == azimuthAxis && fullCircle)
    {
      // A run of azimuth cells may cross the seam (first > last); the margin may take it there.
      const int n = cells[axis];
      const int length = last[axis] - first[axis] + 1 + (first[axis] > last[axis] ? n : 0);
      if (length + 2 * margin >= n)
      {
        first[axis] = 0;
        last[axis] = n - 1;
      }
      else
      {
        first[axis] = (first[axis] - margin + n) % n;
        last[axis] = (last[axis] + margin) % n;
      }
      continue;
    }
    first[axis] = std::max(first[axis] - margin, 0);
    last[axis] = std::min(last[axis] + margin, cells[axis] - 1);
  }
  if (this->CoordinateSystem != CYLINDRICAL && this->PolarAngle == LATITUDE)
  {
    // The kernel's polar cells run from the north pole; latitude input from the south.
    const int n = sphere.polarCells();
    std::swap(first[1], last[1]);
    first[1] = n - 1 - first[1];
    last[1] = n - 1 - last[1];
  }
  for (int axis = 0; axis < 3; ++axis)
  {
    cellRange[2 * axis] = first[axis];
    cellRange[2 * axis + 1] = last[axis];
  }
  return true;
}

//------------------------------------------------------------------------------
double vtkSightlineSphericalVolumeMapper::AutomaticSampleDistance()
{
  // Half the thinnest radial cell: layers are what radial grids resolve.
  const std::vector<double>& radius =
    this->Internals->Cylinder ? this->Internals->Cylinder->grid().radius : this->Internals->Traversal->grid().radius;
  double thinnest = radius.back() - radius.front();
  for (std::size_t i = 0; i + 1 < radius.size(); ++i)
  {
    thinnest = std::min(thinnest, radius[i + 1] - radius[i]);
  }
  return 0.5 * thinnest;
}

//------------------------------------------------------------------------------
double* vtkSightlineSphericalVolumeMapper::GetBounds()
{
  if (!this->UpdateScene())
  {
    vtkMath::UninitializeBounds(this->Bounds);
    return this->Bounds;
  }
  std::copy(this->Internals->Bounds, this->Internals->Bounds + 6, this->Bounds);
  return this->Bounds;
}

//------------------------------------------------------------------------------
bool vtkSightlineSphericalVolumeMapper::RayTrace(vtkProp3D* prop, vtkCamera* camera,
  vtkLightCollection* lights, int width, int height, sightline::Framebuffer& framebuffer,
  const std::vector<float>* depthLimit)
{
  auto* volume = vtkVolume::SafeDownCast(prop);
  if (!volume || !camera)
  {
    vtkErrorMacro(<< "RayTrace needs a volume and a camera.");
    return false;
  }
  if (width <= 0 || height <= 0)
  {
    vtkErrorMacro(<< "Cannot ray-cast an image of " << width << "x" << height << " pixels.");
    return false;
  }
  framebuffer.resize(width, height);
  if (!this->UpdateScene())
  {
    return false;
  }
  if (depthLimit && depthLimit->size() != static_cast<std::size_t>(width) * height)
  {
    vtkErrorMacro(<< "The depth limit has " << depthLimit->size() << " values for " << width
                  << "x" << height << " pixels.");
    return false;
  }
  sightline::dvec3 regionLower, regionUpper;
  if (!SightlineKernelConversions::ToKernelRegion(this, this->Region, regionLower, regionUpper))
  {
    return false;
  }
  if (this->BlendMode != vtkVolumeMapper::COMPOSITE_BLEND)
  {
    vtkErrorMacro(<< "Blend mode " << this->BlendMode
                  << " is not supported; vtkSightlineSphericalVolumeMapper composites "
                     "(SetBlendModeToComposite).");
    return false;
  }
  vtkVolumeProperty* property = volume->GetProperty();
  vtkInternals& in = *this->Internals;

  // Colour and extinction per cell: the transfer functions once per cell, not per ray.
  if (in.Unshaded.size() != in.Values.size() || in.UnshadedPropertyTime != property->GetMTime() ||
    in.UnshadedGridTime != in.GridTime.GetMTime())
  {
    in.Unshaded.resize(in.Values.size());
    for (std::size_t c = 0; c < in.Values.size(); ++c)
    {
      in.Unshaded[c] = SampleTransfer(property, in.Values[c]);
    }
    in.UnshadedPropertyTime = property->GetMTime();
    in.UnshadedGridTime = in.GridTime.GetMTime();
  }

  const double aspect = double(width) / height;
  using SightlineKernelConversions::ToKernelMatrix;
  const sightline::dmat4 objectToWorld = ToKernelMatrix(volume->GetMatrix());
  const sightline::dmat4 worldToClip =
    ToKernelMatrix(camera->GetCompositeProjectionTransformMatrix(aspect, -1, 1));
  try
  {
    const sightline::Camera view(worldToClip * objectToWorld, width, height);
    std::vector<sightline::TransferSample> shaded;
    const std::vector<sightline::TransferSample>* cells = &in.Unshaded;
    if (property->GetShade(0))
    {
      if (!in.PointValues.empty() && this->InterpolatePointData && !in.WarnedShadedPoints)
      {
        vtkWarningMacro(<< "Shading lights each cell once: point data is averaged per cell while "
                           "shading is on.");
        in.WarnedShadedPoints = true;
      }
      if (in.Gradients.empty())
      {
        in.Gradients = in.Cylinder
          ? sightline::cylindricalCellGradients(in.Cylinder->grid(), in.Values)
          : sightline::sphericalCellGradients(in.Traversal->grid(), in.Values);
        in.Centres = in.Cylinder ? sightline::cellCentres(in.Cylinder->grid())
                                 : sightline::cellCentres(in.Traversal->grid());
      }
      const sightline::Material material =
        SightlineKernelConversions::MaterialFromVolumeProperty(property);
      // Lights travel in world space; the cells are lit in the grid's own coordinates.
      sightline::Lighting lighting = SightlineKernelConversions::MakeLighting(lights, camera);
      const glm::dmat3 worldToGrid = glm::inverse(glm::dmat3(objectToWorld));
      for (auto& light : lighting.lights)
      {
        light.direction =
          sightline::vec3(glm::normalize(worldToGrid * sightline::dvec3(light.direction)));
      }
      shaded = in.Unshaded;
      sightline::shadeCells(in.Centres, in.Gradients, material, lighting, view, shaded);
      cells = &shaded;
    }
    sightline::SphericalVolumeOptions options;
    options.depthLimit = depthLimit;
    options.minimumTransmittance = this->MinimumTransmittance;
    options.regionLower = regionLower;
    options.regionUpper = regionUpper;
    options.objectToWorld = objectToWorld;
    options.progress = SightlineKernelConversions::ProgressCallback(this);
    sightline::SphericalVolumeStatistics stats;
    if (!in.PointValues.empty() && this->InterpolatePointData && !property->GetShade(0))
    {
      // Point data: trilinear inside the cells, the transfer function tabulated as VTK's own
      // mappers do (1024 entries over the data range), samples at most SampleDistance apart.
      sightline::TransferTable table;
      table.minimum = in.PointRange[0];
      table.maximum = in.PointRange[1] > in.PointRange[0] ? in.PointRange[1] : in.PointRange[0] + 1.0;
      table.entries.resize(1024);
      for (std::size_t e = 0; e < table.entries.size(); ++e)
      {
        table.entries[e] = SampleTransfer(property,
          table.minimum + (table.maximum - table.minimum) * double(e) / double(table.entries.size() - 1));
        // A finite extinction for opacity 1, so that neighbouring entries interpolate.
        table.entries[e].extinction = std::min(table.entries[e].extinction, 1e6 / property->GetScalarOpacityUnitDistance(0));
      }
      const double distance = this->SampleDistance > 0.0 ? this->SampleDistance : this->AutomaticSampleDistance();
      stats = in.Cylinder
        ? sightline::renderCylindricalVolumePoints(*in.Cylinder, in.PointValues, table, distance, view, framebuffer, options)
        : sightline::renderSphericalVolumePoints(*in.Traversal, in.PointValues, table, distance, view, framebuffer, options);
    }
    else
    {
      stats = in.Cylinder
        ? sightline::renderCylindricalVolume(*in.Cylinder, *cells, view, framebuffer, options)
        : sightline::renderSphericalVolume(*in.Traversal, *cells, view, framebuffer, options);
    }
    this->LastFrameSeconds = stats.seconds;
    this->LastCellsVisited = static_cast<vtkIdType>(stats.cellsVisited);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Ray casting failed: " << e.what());
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
vtkMTimeType vtkSightlineSphericalVolumeMapper::GetSceneTime()
{
  return this->Internals->GridTime.GetMTime();
}

//------------------------------------------------------------------------------
void vtkSightlineSphericalVolumeMapper::Render(vtkRenderer* renderer, vtkVolume* volume)
{
  this->Internals->Window.Render(this, *this, renderer, volume);
}

//------------------------------------------------------------------------------
void vtkSightlineSphericalVolumeMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  this->Internals->Window.ReleaseGraphicsResources(window);
  this->Superclass::ReleaseGraphicsResources(window);
}

//------------------------------------------------------------------------------
sightlineWindowFrameSettingsMacro(vtkSightlineSphericalVolumeMapper, Internals->Window)

//------------------------------------------------------------------------------
void vtkSightlineSphericalVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "AngleUnits: " << (this->AngleUnits == DEGREES ? "degrees" : "radians") << "\n";
  os << indent << "Region: " << this->Region[0] << " " << this->Region[1] << " " << this->Region[2]
     << " " << this->Region[3] << " " << this->Region[4] << " " << this->Region[5] << "\n";
  os << indent << "PolarAngle: " << (this->PolarAngle == LATITUDE ? "latitude" : "colatitude")
     << "\n";
  os << indent << "MinimumTransmittance: " << this->MinimumTransmittance << "\n";
  os << indent << "InterpolatePointData: " << (this->InterpolatePointData ? "on" : "off") << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance
     << (this->SampleDistance > 0.0 ? "" : " (automatic)") << "\n";
  this->Internals->Window.PrintSelf(os, indent);
  os << indent << "LastFrameSeconds: " << this->LastFrameSeconds << "\n";
  os << indent << "LastCellsVisited: " << this->LastCellsVisited << "\n";
  os << indent << "CoordinateSystem: "
     << (this->CoordinateSystem == CYLINDRICAL ? "cylindrical" : "spherical") << "\n";
  if (const auto& cylinder = this->Internals->Cylinder)
  {
    const sightline::CylindricalGrid& grid = cylinder->grid();
    os << indent << "Grid: " << grid.radialCells() << " x " << grid.azimuthalCells() << " x "
       << grid.heightCells() << " cells (rho, phi, z)\n";
  }
  if (const auto& traversal = this->Internals->Traversal)
  {
    const sightline::SphericalGrid& grid = traversal->grid();
    os << indent << "Grid: " << grid.radialCells() << " x " << grid.polarCells() << " x "
       << grid.azimuthalCells() << " cells\n";
  }
}
