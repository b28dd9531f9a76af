// SPDX-License-Identifier: BSD-3-Clause
// Private helper of vtkSightlineNetCDFSphericalReader (not wrapped, not installed): what the
// axes of a CF geographic grid (longitude, latitude, a vertical coordinate) mean, and their
// nodes as the spherical volume mapper's increasing radius, colatitude and azimuth, each node
// remembering which index of the file's axis it came from. No netCDF here: the rules are
// testable on plain values.
#ifndef SightlineGeographicAxes_h
#define SightlineGeographicAxes_h

#include <cstddef>
#include <string>
#include <vector>

namespace sightline_io
{
/// The attributes of a CF coordinate variable that say what it is.
struct CoordinateAttributes
{
  std::string name;
  std::string units;
  std::string standardName;
  std::string longName;
  std::string positive;
  std::string axis;
};

enum class AxisRole
{
  Other,      ///< not a geographic axis (e.g. time)
  Longitude,  ///< degrees_east
  Latitude,   ///< degrees_north
  Colatitude, ///< degrees from the north pole
  Vertical    ///< depth, radius or altitude
};

enum class VerticalKind
{
  Automatic = 0, ///< from the attributes: `positive`, the standard or variable name
  Depth,         ///< below the reference radius, positive down
  Radius,        ///< from the centre
  Altitude       ///< above the reference radius, positive up
};

/// What a coordinate variable is, by CF's rules (units first, then standard_name, axis and
/// the variable's name).
AxisRole RoleOf(const CoordinateAttributes& attributes);

/// An output axis: strictly increasing coordinates, and for each the index of the file's
/// value it came from.
struct SphericalAxis
{
  std::vector<double> coordinates;
  std::vector<std::size_t> fileIndex;
};

/// Radius in the reference radius' unit (km by default) from a vertical coordinate. False with
/// `error` set for missing or non-length units, an ambiguous kind, values that are not finite
/// or not strictly monotonic, fewer than two nodes, or a radius below zero.
bool RadialAxis(const std::vector<double>& values, const CoordinateAttributes& attributes,
  VerticalKind kind, double referenceRadiusKm, SphericalAxis& axis, std::string& error);

/// Colatitude in radians from latitude (or colatitude) in degrees or radians.
bool PolarAxis(const std::vector<double>& values, const CoordinateAttributes& attributes,
  AxisRole role, SphericalAxis& axis, std::string& error);

/// Azimuth in radians from longitude: [-180, 180) and [0, 360) alike; a run that crosses the
/// seam (e.g. 170, 180, -170) is unwrapped, and a global grid without its closing meridian
/// gets it (the first node again, 360 degrees on), so that its last cells close the sphere.
bool AzimuthAxis(const std::vector<double>& values, const CoordinateAttributes& attributes,
  SphericalAxis& axis, std::string& error);
} // namespace sightline_io

#endif
