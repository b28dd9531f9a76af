// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineGeographicAxes.h"

#include "SightlineReaderInput.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

namespace sightline_io
{
namespace
{
constexpr double Pi = 3.14159265358979323846;

std::string Lower(std::string text)
{
  for (char& c : text)
  {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  const auto first = text.find_first_not_of(" \t");
  const auto last = text.find_last_not_of(" \t");
  return first == std::string::npos ? std::string() : text.substr(first, last - first + 1);
}

bool OneOf(const std::string& text, std::initializer_list<const char*> words)
{
  return std::any_of(words.begin(), words.end(), [&](const char* w) { return text == w; });
}

bool Contains(const std::string& text, const char* word)
{
  return text.find(word) != std::string::npos;
}

std::string Named(const CoordinateAttributes& a)
{
  return "coordinate '" + Quote(a.name) + "'";
}

// Kilometres per unit of a length, or 0 for anything else.
double KilometresPer(const std::string& units)
{
  const std::string u = Lower(units);
  if (OneOf(u, { "km", "kilometer", "kilometers", "kilometre", "kilometres" }))
  {
    return 1.0;
  }
  if (OneOf(u, { "m", "meter", "meters", "metre", "metres" }))
  {
    return 1e-3;
  }
  return 0.0;
}

// Radians per unit of an angle (CF's degrees_east/north and their spellings), or 0.
double RadiansPer(const std::string& units)
{
  const std::string u = Lower(units);
  if (OneOf(u, { "degrees_east", "degree_east", "degrees_e", "degree_e", "degreese", "degreee",
                 "degrees_north", "degree_north", "degrees_n", "degree_n", "degreesn",
                 "degreen", "degrees", "degree", "deg" }))
  {
    return Pi / 180.0;
  }
  if (OneOf(u, { "radians", "radian", "rad" }))
  {
    return 1.0;
  }
  return 0.0;
}

// +1 strictly increasing, -1 strictly decreasing, 0 otherwise (with `error` naming where).
int Monotonic(const std::vector<double>& v, const CoordinateAttributes& a, std::string& error)
{
  if (v.size() < 2)
  {
    error = Named(a) + " has " + std::to_string(v.size()) +
      " node(s); a grid axis needs at least two";
    return 0;
  }
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    if (!std::isfinite(v[i]))
    {
      error = Named(a) + " has a value that is not finite (node " + std::to_string(i) + ")";
      return 0;
    }
  }
  const int direction = v[1] > v[0] ? 1 : -1;
  for (std::size_t i = 0; i + 1 < v.size(); ++i)
  {
    if (!(direction * (v[i + 1] - v[i]) > 0.0))
    {
      std::ostringstream text;
      text << Named(a) << " is not strictly monotonic: node " << i << " is " << v[i]
           << ", node " << i + 1 << " is " << v[i + 1];
      error = text.str();
      return 0;
    }
  }
  return direction;
}

// The axis from converted values that are monotonic in `direction`, increasing; false with
// `error` set when the conversion made neighbours equal (values too close for doubles, e.g.
// depths of 1e-20 km below a radius of 6371 km).
bool Increasing(const std::vector<double>& converted, int direction, SphericalAxis& axis,
  const CoordinateAttributes& a, std::string& error)
{
  const std::size_t n = converted.size();
  axis.coordinates.resize(n);
  axis.fileIndex.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t from = direction > 0 ? i : n - 1 - i;
    axis.coordinates[i] = converted[from];
    axis.fileIndex[i] = from;
    if (i > 0 && !(axis.coordinates[i] > axis.coordinates[i - 1]))
    {
      error = Named(a) + " has neighbouring nodes that coincide on the sphere (node " +
        std::to_string(from) + ")";
      return false;
    }
  }
  return true;
}
} // namespace

AxisRole RoleOf(const CoordinateAttributes& a)
{
  const std::string units = Lower(a.units);
  const std::string standard = Lower(a.standardName);
  const std::string name = Lower(a.name);
  const std::string axis = Lower(a.axis);
  if (Contains(standard, "colatitude") || Contains(name, "colat"))
  {
    return AxisRole::Colatitude;
  }
  if (OneOf(units, { "degrees_east", "degree_east", "degrees_e", "degree_e", "degreese",
                     "degreee" }) ||
    standard == "longitude" || (name.rfind("lon", 0) == 0 && RadiansPer(units) > 0.0))
  {
    return AxisRole::Longitude;
  }
  if (OneOf(units, { "degrees_north", "degree_north", "degrees_n", "degree_n", "degreesn",
                     "degreen" }) ||
    standard == "latitude" || (name.rfind("lat", 0) == 0 && RadiansPer(units) > 0.0))
  {
    return AxisRole::Latitude;
  }
  if (!a.positive.empty() || axis == "z" || KilometresPer(units) > 0.0 ||
    OneOf(standard, { "depth", "altitude", "height", "radius" }) ||
    OneOf(name, { "depth", "radius", "altitude", "height", "elevation" }))
  {
    return AxisRole::Vertical;
  }
  return AxisRole::Other;
}

bool RadialAxis(const std::vector<double>& values, const CoordinateAttributes& a,
  VerticalKind kind, double referenceRadiusKm, SphericalAxis& axis, std::string& error)
{
  if (a.units.empty())
  {
    error = "vertical " + Named(a) + " has no units attribute (m or km)";
    return false;
  }
  const double scale = KilometresPer(a.units);
  if (scale == 0.0)
  {
    error = "vertical " + Named(a) + " has units '" + Quote(a.units) +
      "', not a length (m or km)";
    return false;
  }
  if (kind == VerticalKind::Automatic)
  {
    const std::string names =
      Lower(a.name) + " " + Lower(a.standardName) + " " + Lower(a.longName);
    const std::string positive = Lower(a.positive);
    if (Contains(names, "radius"))
    {
      kind = VerticalKind::Radius;
    }
    else if (positive == "down" || Contains(names, "depth"))
    {
      kind = VerticalKind::Depth;
    }
    else if (positive == "up" || Contains(names, "altitude") || Contains(names, "height"))
    {
      kind = VerticalKind::Altitude;
    }
    else
    {
      error = "cannot tell whether vertical " + Named(a) +
        " is a depth, a radius or an altitude: it has no 'positive' attribute; set "
        "VerticalCoordinate";
      return false;
    }
  }
  const int direction = Monotonic(values, a, error);
  if (direction == 0)
  {
    return false;
  }
  std::vector<double> radius(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    const double km = values[i] * scale;
    radius[i] = kind == VerticalKind::Depth ? referenceRadiusKm - km
      : kind == VerticalKind::Altitude      ? referenceRadiusKm + km
                                            : km;
    if (radius[i] < 0.0)
    {
      std::ostringstream text;
      text << "vertical " << Named(a) << " reaches below the centre: "
           << (kind == VerticalKind::Depth ? "depth " : "value ") << values[i] << " "
           << Quote(a.units) << " is beyond the reference radius " << referenceRadiusKm
           << " km";
      error = text.str();
      return false;
    }
  }
  return Increasing(radius, kind == VerticalKind::Depth ? -direction : direction, axis, a, error);
}

bool PolarAxis(const std::vector<double>& values, const CoordinateAttributes& a, AxisRole role,
  SphericalAxis& axis, std::string& error)
{
  const double scale = RadiansPer(a.units);
  if (scale == 0.0)
  {
    error = Named(a) + (a.units.empty() ? std::string(" has no units attribute (degrees_north)")
                                         : " has units '" + Quote(a.units) + "', not an angle");
    return false;
  }
  const int direction = Monotonic(values, a, error);
  if (direction == 0)
  {
    return false;
  }
  std::vector<double> colatitude(values.size());
  const double slack = 1e-9;
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    const double angle = values[i] * scale;
    colatitude[i] = role == AxisRole::Colatitude ? angle : Pi / 2 - angle;
    if (colatitude[i] < -slack || colatitude[i] > Pi + slack)
    {
      std::ostringstream text;
      text << Named(a) << " has " << values[i] << " " << Quote(a.units) << ", beyond the pole";
      error = text.str();
      return false;
    }
    colatitude[i] = std::min(std::max(colatitude[i], 0.0), Pi);
  }
  return Increasing(
    colatitude, role == AxisRole::Colatitude ? direction : -direction, axis, a, error);
}

bool AzimuthAxis(const std::vector<double>& values, const CoordinateAttributes& a,
  SphericalAxis& axis, std::string& error)
{
  const double scale = RadiansPer(a.units);
  if (scale == 0.0)
  {
    error = Named(a) + (a.units.empty() ? std::string(" has no units attribute (degrees_east)")
                                         : " has units '" + Quote(a.units) + "', not an angle");
    return false;
  }
  const std::size_t n = values.size();
  if (n < 2)
  {
    error = Named(a) + " has " + std::to_string(n) + " node(s); a grid axis needs at least two";
    return false;
  }
  std::vector<double> angle(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!std::isfinite(values[i]))
    {
      error = Named(a) + " has a value that is not finite (node " + std::to_string(i) + ")";
      return false;
    }
    angle[i] = values[i] * scale;
  }
  // Steps taken the short way round: a run crossing the seam (170, 180, -170) steps +10 each.
  const double turn = 2 * Pi;
  const auto shortStep = [&](double from, double to) {
    return std::remainder(to - from, turn);
  };
  const double firstStep = shortStep(angle[0], angle[1]);
  const int direction = firstStep > 0 ? 1 : -1;
  std::vector<double> unwrapped(n);
  unwrapped[0] = angle[0];
  for (std::size_t i = 0; i + 1 < n; ++i)
  {
    const double step = shortStep(angle[i], angle[i + 1]);
    if (!(direction * step > 0.0))
    {
      std::ostringstream text;
      text << Named(a) << " is not strictly monotonic: node " << i << " is " << values[i]
           << ", node " << i + 1 << " is " << values[i + 1];
      error = text.str();
      return false;
    }
    unwrapped[i + 1] = unwrapped[i] + step;
  }
  const double span = std::abs(unwrapped[n - 1] - unwrapped[0]);
  const double tolerance = 1e-9 * turn;
  if (span > turn + tolerance)
  {
    std::ostringstream text;
    text << Named(a) << " goes round more than once (" << span / scale << " " << Quote(a.units)
         << ")";
    error = text.str();
    return false;
  }
  if (!Increasing(unwrapped, direction, axis, a, error))
  {
    return false;
  }
  // A global grid without its closing meridian: the gap to a full turn is about one step.
  const double gap = turn - span;
  const double meanStep = span / double(n - 1);
  if (gap > tolerance && gap < 1.5 * meanStep)
  {
    axis.coordinates.push_back(axis.coordinates.front() + turn);
    axis.fileIndex.push_back(axis.fileIndex.front());
  }
  else if (gap <= tolerance && axis.coordinates.front() + turn > axis.coordinates[n - 2])
  {
    axis.coordinates.back() = axis.coordinates.front() + turn; // exactly closed
  }
  return true;
}
} // namespace sightline_io
