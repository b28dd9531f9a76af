// SPDX-License-Identifier: BSD-3-Clause
// Private helper of vtkSightlineNetCDFSphericalReader (not wrapped, not installed): a walk over
// the header of a netCDF classic file (CDF-1, CDF-2 "64-bit offset", CDF-5) that checks every
// count and length fits in the file before the netCDF library reads it. libnetcdf allocates
// what a damaged header claims (a name of 4 GB) before it finds the file too short.
#ifndef SightlineNetCDFClassicHeader_h
#define SightlineNetCDFClassicHeader_h

#include <string>

namespace sightline_io
{
class InputFile;

/// True when `file` is not a classic netCDF file (another format: netCDF's own checks apply)
/// or its header is consistent; false with `error` naming the first part that does not fit.
bool CheckNetCDFClassicHeader(InputFile& file, std::string& error);
} // namespace sightline_io

#endif
