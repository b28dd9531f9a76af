// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineNetCDFSphericalReader.h"

#include "SightlineGeographicAxes.h"
#include "SightlineNetCDFClassicHeader.h"
#include "SightlineReaderInput.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkRectilinearGrid.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include "vtk_netcdf.h"
// nc_open_mem (fuzzing and ReadFromInputString), beside the netcdf.h VTK chose. VTK's own
// netCDF builds it but installs its header only up to VTK 9.3 (not in the VTK 9.5 SDK), so
// there it is declared as netCDF documents it; VTK's mangling header renames it as it renames
// the rest of netCDF's API.
#if VTK_MODULE_USE_EXTERNAL_vtknetcdf
#include <netcdf_mem.h>
#elif __has_include(<vtknetcdf/include/netcdf_mem.h>)
#include <vtknetcdf/include/netcdf_mem.h>
#else
extern "C" int nc_open_mem(const char* path, int mode, size_t size, void* memory, int* ncid);
#endif

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

vtkStandardNewMacro(vtkSightlineNetCDFSphericalReader);

namespace
{
using sightline_io::AxisRole;
using sightline_io::CoordinateAttributes;
using sightline_io::Quote;
using sightline_io::SphericalAxis;

// Deflate expands at most about 1032 times: a compressed netCDF-4 variable cannot be larger
// than this many times its file, so a bigger header is damaged (or a bomb).
constexpr double MostExpansion = 1100.0;

// An open netCDF file or in-memory image, closed on destruction.
class NetCDFFile
{
public:
  ~NetCDFFile()
  {
    if (this->Id >= 0)
    {
      nc_close(this->Id);
    }
  }

  bool Open(const char* fileName, bool fromString, std::string& bytes, std::string& error)
  {
    sightline_io::InputFile input;
    if (!input.Open(fileName, fromString, bytes, error) ||
      !sightline_io::CheckNetCDFClassicHeader(input, error))
    {
      return false;
    }
    this->Bytes = static_cast<double>(input.Size());
    const int status = fromString
      ? (bytes.empty() ? NC_ENOTNC
                       : nc_open_mem("input string", NC_NOWRITE, bytes.size(), &bytes[0], &this->Id))
      : nc_open(fileName, NC_NOWRITE, &this->Id);
    if (status != NC_NOERR)
    {
      this->Id = -1;
      error = std::string("netCDF cannot open it: ") + nc_strerror(status);
      return false;
    }
    int format = 0;
    nc_inq_format(this->Id, &format);
    this->Compressible = format == NC_FORMAT_NETCDF4 || format == NC_FORMAT_NETCDF4_CLASSIC;
    return true;
  }

  int Id = -1;
  double Bytes = 0.0;
  bool Compressible = false;

  /// The most bytes a variable of this file can hold.
  double MostBytes() const { return this->Compressible ? MostExpansion * this->Bytes : this->Bytes; }
};

std::string TextAttribute(int file, int variable, const char* name)
{
  nc_type type = NC_NAT;
  size_t length = 0;
  if (nc_inq_att(file, variable, name, &type, &length) != NC_NOERR || length == 0)
  {
    return {};
  }
  if (type == NC_CHAR)
  {
    std::string text(length, '\0');
    if (nc_get_att_text(file, variable, name, &text[0]) != NC_NOERR)
    {
      return {};
    }
    text.erase(std::find(text.begin(), text.end(), '\0'), text.end());
    return text;
  }
  if (type == NC_STRING && length == 1)
  {
    char* value = nullptr;
    if (nc_get_att_string(file, variable, name, &value) != NC_NOERR)
    {
      return {};
    }
    std::string text = value ? value : "";
    nc_free_string(1, &value);
    return text;
  }
  return {};
}

// Up to 16 numeric values of an attribute (none when it is missing or text).
std::vector<double> NumericAttribute(int file, int variable, const char* name)
{
  nc_type type = NC_NAT;
  size_t length = 0;
  if (nc_inq_att(file, variable, name, &type, &length) != NC_NOERR || length == 0 ||
    length > 16 || type == NC_CHAR || type == NC_STRING || type > NC_STRING)
  {
    return {};
  }
  std::vector<double> values(length);
  if (nc_get_att_double(file, variable, name, values.data()) != NC_NOERR)
  {
    return {};
  }
  return values;
}

std::string NameOfVariable(int file, int variable)
{
  char name[NC_MAX_NAME + 1] = {};
  nc_inq_varname(file, variable, name);
  return name;
}

// The coordinate variable of dimension `dimension` (a 1-D variable of the same name), or -1.
int CoordinateVariable(int file, int dimension)
{
  char name[NC_MAX_NAME + 1] = {};
  int variable = -1;
  int dimensions = 0;
  int only = -1;
  if (nc_inq_dimname(file, dimension, name) != NC_NOERR ||
    nc_inq_varid(file, name, &variable) != NC_NOERR ||
    nc_inq_varndims(file, variable, &dimensions) != NC_NOERR || dimensions != 1 ||
    nc_inq_vardimid(file, variable, &only) != NC_NOERR || only != dimension)
  {
    return -1;
  }
  return variable;
}

CoordinateAttributes AttributesOf(int file, int variable)
{
  CoordinateAttributes a;
  a.name = NameOfVariable(file, variable);
  a.units = TextAttribute(file, variable, "units");
  a.standardName = TextAttribute(file, variable, "standard_name");
  a.longName = TextAttribute(file, variable, "long_name");
  a.positive = TextAttribute(file, variable, "positive");
  a.axis = TextAttribute(file, variable, "axis");
  return a;
}

bool Numeric(nc_type type)
{
  return type != NC_CHAR && type != NC_STRING && type >= NC_BYTE && type <= NC_UINT64;
}
} // namespace

// One variable over the grid: where its axes sit among its dimensions.
struct GridVariable
{
  int id = -1;
  std::string name;
  nc_type type = NC_NAT;
  std::vector<int> dimensions;     // the variable's dimension ids, in file order
  int position[3] = { -1, -1, -1 }; // where the radial, polar and azimuth axes are among them
};

struct vtkSightlineNetCDFSphericalReader::Internals
{
  std::string InputString;
  // What RequestInformation found, for RequestData.
  std::vector<GridVariable> Variables;
  int ActiveVariable = 0;
  SphericalAxis Axes[3]; // radial, polar, azimuth

  // Finds the grid and its axes in `file`; false with `error` set.
  bool Scan(int file, double mostBytes, const char* wanted, int verticalKind,
    double referenceRadius, std::string& error);
};

bool vtkSightlineNetCDFSphericalReader::Internals::Scan(int file, double mostBytes,
  const char* wanted, int verticalKind, double referenceRadius, std::string& error)
{
  this->Variables.clear();
  int count = 0;
  if (nc_inq_nvars(file, &count) != NC_NOERR)
  {
    error = "netCDF cannot list its variables";
    return false;
  }
  // The role of each dimension, by its coordinate variable's attributes (cached).
  std::map<int, AxisRole> roles;
  const auto roleOf = [&](int dimension) {
    auto found = roles.find(dimension);
    if (found == roles.end())
    {
      const int coordinate = CoordinateVariable(file, dimension);
      found = roles
                .emplace(dimension,
                  coordinate < 0 ? AxisRole::Other
                                 : sightline_io::RoleOf(AttributesOf(file, coordinate)))
                .first;
    }
    return found->second;
  };
  std::vector<GridVariable> candidates;
  for (int v = 0; v < count; ++v)
  {
    GridVariable variable;
    variable.id = v;
    int dimensions = 0;
    if (nc_inq_varndims(file, v, &dimensions) != NC_NOERR || dimensions < 3 ||
      dimensions > NC_MAX_VAR_DIMS || nc_inq_vartype(file, v, &variable.type) != NC_NOERR ||
      !Numeric(variable.type))
    {
      continue;
    }
    variable.dimensions.resize(dimensions);
    nc_inq_vardimid(file, v, variable.dimensions.data());
    bool grid = true;
    for (int p = 0; p < dimensions && grid; ++p)
    {
      size_t length = 0;
      nc_inq_dimlen(file, variable.dimensions[p], &length);
      const AxisRole role = roleOf(variable.dimensions[p]);
      const int axis = role == AxisRole::Vertical ? 0
        : role == AxisRole::Latitude || role == AxisRole::Colatitude ? 1
        : role == AxisRole::Longitude                                 ? 2
                                                                      : -1;
      if (axis < 0)
      {
        grid = length == 1; // e.g. a time of one step
      }
      else if (variable.position[axis] >= 0)
      {
        grid = false; // two axes of one kind
      }
      else
      {
        variable.position[axis] = p;
      }
    }
    if (grid && variable.position[0] >= 0 && variable.position[1] >= 0 &&
      variable.position[2] >= 0)
    {
      variable.name = NameOfVariable(file, v);
      candidates.push_back(variable);
    }
  }
  if (candidates.empty())
  {
    error = "no variable lies on a longitude (degrees_east), a latitude (degrees_north) and a "
            "vertical axis (depth, radius or altitude with length units)";
    return false;
  }
  // The grid of the wanted variable, or of the first; every variable on its axes is read.
  std::size_t chosen = 0;
  if (wanted && *wanted)
  {
    chosen = candidates.size();
    for (std::size_t c = 0; c < candidates.size(); ++c)
    {
      if (candidates[c].name == wanted)
      {
        chosen = c;
      }
    }
    if (chosen == candidates.size())
    {
      int id = -1;
      error = std::string("variable '") + Quote(wanted) + "' " +
        (nc_inq_varid(file, wanted, &id) == NC_NOERR
            ? "does not lie on a longitude, a latitude and a vertical axis"
            : "is not in the file");
      return false;
    }
  }
  const auto axisDimension = [](const GridVariable& v, int axis) {
    return v.dimensions[v.position[axis]];
  };
  for (const GridVariable& v : candidates)
  {
    if (axisDimension(v, 0) == axisDimension(candidates[chosen], 0) &&
      axisDimension(v, 1) == axisDimension(candidates[chosen], 1) &&
      axisDimension(v, 2) == axisDimension(candidates[chosen], 2))
    {
      if (v.id == candidates[chosen].id)
      {
        this->ActiveVariable = static_cast<int>(this->Variables.size());
      }
      this->Variables.push_back(v);
    }
  }

  // The axes.
  const GridVariable& grid = candidates[chosen];
  double nodes = 1.0;
  for (int axis = 0; axis < 3; ++axis)
  {
    const int dimension = axisDimension(grid, axis);
    const int coordinate = CoordinateVariable(file, dimension);
    size_t length = 0;
    nc_inq_dimlen(file, dimension, &length);
    nodes *= static_cast<double>(length);
    if (8.0 * static_cast<double>(length) > std::max(mostBytes, 64.0) || length < 1)
    {
      error = "its coordinate '" + Quote(NameOfVariable(file, coordinate)) + "' claims " +
        std::to_string(length) + " values, more than the file holds";
      return false;
    }
    std::vector<double> values(length);
    const int status = nc_get_var_double(file, coordinate, values.data());
    if (status != NC_NOERR)
    {
      error = "cannot read coordinate '" + Quote(NameOfVariable(file, coordinate)) +
        "': " + nc_strerror(status);
      return false;
    }
    const CoordinateAttributes attributes = AttributesOf(file, coordinate);
    const AxisRole role = sightline_io::RoleOf(attributes);
    bool good = false;
    if (axis == 0)
    {
      good = sightline_io::RadialAxis(values, attributes,
        static_cast<sightline_io::VerticalKind>(verticalKind), referenceRadius, this->Axes[0],
        error);
    }
    else if (axis == 1)
    {
      good = sightline_io::PolarAxis(values, attributes, role, this->Axes[1], error);
    }
    else
    {
      good = sightline_io::AzimuthAxis(values, attributes, this->Axes[2], error);
    }
    if (!good)
    {
      return false;
    }
  }
  for (const GridVariable& v : this->Variables)
  {
    size_t typeSize = 1;
    nc_inq_type(file, v.type, nullptr, &typeSize);
    if (nodes * static_cast<double>(typeSize) > mostBytes)
    {
      error = "variable '" + Quote(v.name) + "' claims " + std::to_string(nodes) +
        " values, more than the file can hold";
      return false;
    }
  }
  return true;
}

vtkSightlineNetCDFSphericalReader::vtkSightlineNetCDFSphericalReader()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(0);
}

vtkSightlineNetCDFSphericalReader::~vtkSightlineNetCDFSphericalReader()
{
  this->SetFileName(nullptr);
  this->SetVariableName(nullptr);
}

void vtkSightlineNetCDFSphericalReader::SetInputString(const std::string& bytes)
{
  this->Internal->InputString = bytes;
  this->Modified();
}

const std::string& vtkSightlineNetCDFSphericalReader::GetInputString() const
{
  return this->Internal->InputString;
}

int vtkSightlineNetCDFSphericalReader::GetNumberOfVariables()
{
  return static_cast<int>(this->Internal->Variables.size());
}

const char* vtkSightlineNetCDFSphericalReader::GetVariableNameOf(int index)
{
  if (index < 0 || index >= this->GetNumberOfVariables())
  {
    return nullptr;
  }
  return this->Internal->Variables[index].name.c_str();
}

int vtkSightlineNetCDFSphericalReader::CanReadFile(const char* fileName)
{
  NetCDFFile file;
  std::string none;
  std::string error;
  Internals scan;
  return file.Open(fileName, false, none, error) &&
      scan.Scan(file.Id, file.MostBytes(), nullptr, AUTOMATIC, 6371.0, error)
    ? 1
    : 0;
}

int vtkSightlineNetCDFSphericalReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  NetCDFFile file;
  std::string error;
  Internals& in = *this->Internal;
  if (!file.Open(this->FileName, this->ReadFromInputString, in.InputString, error) ||
    !in.Scan(file.Id, file.MostBytes(), this->VariableName, this->VerticalCoordinate,
      this->ReferenceRadius, error))
  {
    in.Variables.clear();
    vtkErrorMacro(<< sightline_io::InputName(this->FileName, this->ReadFromInputString) << ": "
                  << error);
    return 0;
  }
  int extent[6] = { 0, static_cast<int>(in.Axes[0].coordinates.size()) - 1, 0,
    static_cast<int>(in.Axes[1].coordinates.size()) - 1, 0,
    static_cast<int>(in.Axes[2].coordinates.size()) - 1 };
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

int vtkSightlineNetCDFSphericalReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkRectilinearGrid* output = vtkRectilinearGrid::GetData(outInfo);
  Internals& in = *this->Internal;
  if (in.Variables.empty())
  {
    return 0; // RequestInformation reported why
  }
  int extent[6];
  outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), extent);
  for (int axis = 0; axis < 3; ++axis)
  {
    const int last = static_cast<int>(in.Axes[axis].coordinates.size()) - 1;
    extent[2 * axis] = std::max(extent[2 * axis], 0);
    extent[2 * axis + 1] = std::min(extent[2 * axis + 1], last);
    if (extent[2 * axis] > extent[2 * axis + 1])
    {
      output->Initialize(); // an empty piece
      return 1;
    }
  }
  NetCDFFile file;
  std::string error;
  const std::string name = sightline_io::InputName(this->FileName, this->ReadFromInputString);
  if (!file.Open(this->FileName, this->ReadFromInputString, in.InputString, error))
  {
    vtkErrorMacro(<< name << ": " << error);
    return 0;
  }

  output->SetExtent(extent);
  size_t first[3];
  size_t span[3];
  for (int axis = 0; axis < 3; ++axis)
  {
    vtkNew<vtkDoubleArray> values;
    const int from = extent[2 * axis];
    const int to = extent[2 * axis + 1];
    values->SetNumberOfValues(to - from + 1);
    size_t low = std::numeric_limits<size_t>::max();
    size_t high = 0;
    for (int i = from; i <= to; ++i)
    {
      values->SetValue(i - from, in.Axes[axis].coordinates[i]);
      low = std::min(low, in.Axes[axis].fileIndex[i]);
      high = std::max(high, in.Axes[axis].fileIndex[i]);
    }
    first[axis] = low;
    span[axis] = high - low + 1;
    if (axis == 0)
    {
      output->SetXCoordinates(values);
    }
    else if (axis == 1)
    {
      output->SetYCoordinates(values);
    }
    else
    {
      output->SetZCoordinates(values);
    }
  }
  const vtkIdType nx = extent[1] - extent[0] + 1;
  const vtkIdType ny = extent[3] - extent[2] + 1;
  const vtkIdType nz = extent[5] - extent[4] + 1;

  std::vector<double> raw;
  for (std::size_t v = 0; v < in.Variables.size(); ++v)
  {
    const GridVariable& variable = in.Variables[v];
    const std::size_t dimensions = variable.dimensions.size();
    std::vector<size_t> start(dimensions, 0);
    std::vector<size_t> count(dimensions, 1);
    for (int axis = 0; axis < 3; ++axis)
    {
      start[variable.position[axis]] = first[axis];
      count[variable.position[axis]] = span[axis];
    }
    // Strides of the three axes in the hyperslab, stored in the variable's dimension order.
    std::vector<size_t> stride(dimensions, 1);
    for (std::size_t p = dimensions - 1; p > 0; --p)
    {
      stride[p - 1] = stride[p] * count[p];
    }
    raw.assign(stride[0] * count[0], 0.0);
    const int status =
      nc_get_vara_double(file.Id, variable.id, start.data(), count.data(), raw.data());
    if (status != NC_NOERR)
    {
      vtkErrorMacro(<< name << ": cannot read variable '" << Quote(variable.name)
                    << "': " << nc_strerror(status));
      return 0;
    }
    std::vector<double> missing = NumericAttribute(file.Id, variable.id, "_FillValue");
    if (missing.empty() && variable.type == NC_FLOAT)
    {
      missing.push_back(NC_FILL_FLOAT);
    }
    else if (missing.empty() && variable.type == NC_DOUBLE)
    {
      missing.push_back(NC_FILL_DOUBLE);
    }
    for (double m : NumericAttribute(file.Id, variable.id, "missing_value"))
    {
      missing.push_back(m);
    }
    const std::vector<double> scale = NumericAttribute(file.Id, variable.id, "scale_factor");
    const std::vector<double> offset = NumericAttribute(file.Id, variable.id, "add_offset");
    const double a = scale.empty() ? 1.0 : scale[0];
    const double b = offset.empty() ? 0.0 : offset[0];

    vtkSmartPointer<vtkDataArray> array;
    if (variable.type == NC_DOUBLE)
    {
      array = vtkSmartPointer<vtkDoubleArray>::New();
    }
    else
    {
      array = vtkSmartPointer<vtkFloatArray>::New();
    }
    array->SetName(variable.name.c_str());
    array->SetNumberOfTuples(nx * ny * nz);
    const size_t s0 = stride[variable.position[0]];
    const size_t s1 = stride[variable.position[1]];
    const size_t s2 = stride[variable.position[2]];
    const double nan = std::numeric_limits<double>::quiet_NaN();
    vtkIdType id = 0;
    for (int k = extent[4]; k <= extent[5]; ++k)
    {
      const size_t f2 = (in.Axes[2].fileIndex[k] - first[2]) * s2;
      for (int j = extent[2]; j <= extent[3]; ++j)
      {
        const size_t f1 = (in.Axes[1].fileIndex[j] - first[1]) * s1 + f2;
        for (int i = extent[0]; i <= extent[1]; ++i, ++id)
        {
          const double value = raw[(in.Axes[0].fileIndex[i] - first[0]) * s0 + f1];
          const bool isMissing =
            std::find(missing.begin(), missing.end(), value) != missing.end();
          array->SetComponent(id, 0, isMissing ? nan : value * a + b);
        }
      }
    }
    output->GetPointData()->AddArray(array);
    if (static_cast<int>(v) == in.ActiveVariable)
    {
      output->GetPointData()->SetActiveScalars(array->GetName());
    }
  }
  vtkNew<vtkDoubleArray> radius;
  radius->SetName("ReferenceRadius");
  radius->InsertNextValue(this->ReferenceRadius);
  output->GetFieldData()->AddArray(radius);
  return 1;
}

void vtkSightlineNetCDFSphericalReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "VariableName: " << (this->VariableName ? this->VariableName : "(first)")
     << "\n";
  os << indent << "ReferenceRadius: " << this->ReferenceRadius << " km\n";
  os << indent << "VerticalCoordinate: " << this->VerticalCoordinate << "\n";
  os << indent << "ReadFromInputString: " << this->ReadFromInputString << "\n";
}
