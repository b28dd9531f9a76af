// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/volumes/GridTraversal.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace sightline
{
namespace traversal
{
void checkBreakpoints(const std::vector<double>& v, const char* owner, const char* name)
{
  const std::string who = std::string("sightline::") + owner + ": ";
  if (v.size() < 2)
    throw std::invalid_argument(who + name + " needs at least 2 breakpoints, got " + std::to_string(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    if (!std::isfinite(v[i]))
      throw std::invalid_argument(who + name + " breakpoint " + std::to_string(i) + " is not finite");
    if (i > 0 && !(v[i] > v[i - 1]))
      throw std::invalid_argument(who + name + " breakpoints are not strictly increasing at " +
        std::to_string(i) + " (" + std::to_string(v[i - 1]) + ", " + std::to_string(v[i]) + ")");
  }
}

bool spansFullCircle(const std::vector<double>& azimuth)
{
  return std::abs((azimuth.back() - azimuth.front()) - kTwoPi) <= 1e-12 * kTwoPi;
}

CrossingScratch& threadCrossingScratch()
{
  thread_local CrossingScratch scratch;
  return scratch;
}

void clampAscending(TransitionList& list, double tmin, double tmax)
{
  double previous = tmin;
  for (Transition& x : list)
  {
    x.t = std::min(tmax, std::max(previous, x.t));
    previous = x.t;
  }
}

int radialTransitions(const std::vector<double>& radius, const std::vector<double>& radiusSquared,
  double tClosest, double closestDistance, double dd, double tmin, double tmax, double startSquared,
  double endSquared, TransitionList& out, ScratchList<double>& halfChords)
{
  out.reset(2 * radius.size() + 1);
  auto index = [&](double r2)
  { return int(std::upper_bound(radiusSquared.begin(), radiusSquared.end(), r2) - radiusSquared.begin()) - 1; };
  const int first = index(startSquared);
  const int last = index(endSquared);
  // The lowest shell: at the hinge when it lies inside [tmin, tmax], else at whichever end is
  // nearer to it (a ray ending before its closest approach only falls).
  const int lowest = tClosest <= tmin ? first : tClosest >= tmax ? last : index(closestDistance * closestDistance);
  // The ray falls through r_first .. r_{lowest+1} and rises through r_{lowest+1} .. r_last:
  // each sphere's half chord once, for both crossings, in a loop without dependencies.
  const int top = std::max(first, last);
  if (top > lowest)
  {
    halfChords.reset(std::size_t(top - lowest));
    double* half = halfChords.data() - (lowest + 1); // half[i] for radius i
    const double* r = radius.data();
    for (int i = lowest + 1; i <= top; ++i)
      half[i] = std::sqrt(std::max(0.0, (r[i] - closestDistance) * (r[i] + closestDistance)) / dd);
    for (int i = first; i > lowest; --i) // falling: leave shell i through r_i
      out.push({ tClosest - half[i], i - 1 });
    for (int i = lowest + 1; i <= last; ++i) // rising: leave shell i - 1 through r_i
      out.push({ tClosest + half[i], i });
  }
  clampAscending(out, tmin, tmax);
  return first;
}

AzimuthSweep::AzimuthSweep(const std::vector<double>& azimuth)
  : Azimuth(azimuth)
  , FullCircle(spansFullCircle(azimuth))
{
  for (double phi : Azimuth)
    HalfPlanes.push_back(dvec3(std::cos(phi), std::sin(phi), phi));
  // phi_k + (lap - 1) 2 pi for laps 0, 1, 2 (a full circle's last breakpoint is its first).
  const int perLap = FullCircle ? int(Azimuth.size()) - 1 : int(Azimuth.size());
  for (int lap = 0; lap < 3; ++lap)
    for (int k = 0; k < perLap; ++k)
      Laps.push_back(Azimuth[std::size_t(k)] + (lap - 1) * kTwoPi);
}

int AzimuthSweep::transitions(const dvec3& p, const dvec3& d, double tmin, double tmax,
  const dvec3& start, const dvec3& end, TransitionList& out) const
{
  const int azimuthCount = int(HalfPlanes.size());
  out.reset(3 * std::size_t(azimuthCount) + 1); // the walk covers at most three laps
  const double phi0 = HalfPlanes.front().z;
  auto unwrap = [&](const dvec3& x)
  {
    // phi0 + ((phi - phi0) mod 2 pi), in [phi0, phi0 + 2 pi). When phi is within a turn of
    // phi0 (always, for grids whose azimuths start in (-pi, pi)) two exact subtractions give
    // fmod's bits; otherwise fmod.
    const double a = std::atan2(x.y, x.x) - phi0;
    if (!(std::abs(a) < kTwoPi))
      return phi0 + std::fmod(std::fmod(a, kTwoPi) + kTwoPi, kTwoPi);
    double b = a + kTwoPi;
    if (b >= kTwoPi)
      b -= kTwoPi;
    if (b >= kTwoPi)
      b -= kTwoPi;
    return phi0 + b;
  };
  const double turn = p.x * d.y - p.y * d.x; // (p x d).z
  const double dxy = d.x * d.x + d.y * d.y;
  const double scaleXY = std::sqrt((p.x * p.x + p.y * p.y) * dxy);
  const bool throughAxis = dxy > 0.0 && std::abs(turn) <= 1e-14 * scaleXY;
  const double tAxis = dxy > 0.0 ? -(p.x * d.x + p.y * d.y) / dxy : 0.0;
  // A line through the z axis has azimuth atan2(-d) before the axis and atan2(d) after it,
  // exactly, whatever rounding leaves of the points next to the axis. A vertical line keeps
  // its azimuth (0 by convention on the axis itself).
  const double phiStart = throughAxis ? (tAxis > tmin ? unwrap(-d) : unwrap(d)) : unwrap(start);
  // The wedge: Azimuth[k] <= phiStart < Azimuth[k + 1] (the last breakpoint of a full circle is
  // its first).
  int azimuthStart = int(std::upper_bound(Azimuth.begin(), Azimuth.end(), phiStart) - Azimuth.begin()) - 1;
  if (azimuthStart >= azimuthCount - 1)
    azimuthStart = FullCircle ? azimuthCount - 2 : -1;
  if (!(dxy > 0.0))
    return azimuthStart;

  // The half-planes' angles over three laps (Laps) form one increasing sequence; the start
  // lies in the middle lap, and the first of them past it follows its wedge's. Walk from there
  // in the sweep's direction while the segment's end lies past the next half-plane: the sign of
  // (h x end).z, h = (cos phi_k, sin phi_k), which is the crossing's own test (crossAt solves
  // (h x (p + t d)).z = 0), with no atan2 for the end. The sweep is under pi, so only
  // half-planes less than pi from the start can be reached (beyond, the sign test would read
  // the opposite half-plane).
  const int perLap = FullCircle ? azimuthCount - 1 : azimuthCount;
  const int firstPast = perLap + (azimuthStart >= 0 ? azimuthStart + 1 : perLap);
  auto crossAt = [&](int k)
  {
    const dvec3& h = HalfPlanes[std::size_t(k)];
    if (throughAxis)
      return tAxis;
    const double denominator = d.y * h.x - d.x * h.y;
    return denominator != 0.0 ? (p.x * h.y - p.y * h.x) / denominator : tAxis;
  };
  auto side = [&](int k) // > 0 where the end lies counterclockwise of half-plane k
  {
    const dvec3& h = HalfPlanes[std::size_t(k)];
    return h.x * end.y - h.y * end.x;
  };
  const double* laps = Laps.data();
  if (throughAxis)
  {
    // The jump by pi, taken as a rise, when the axis lies inside the segment.
    const double phiEnd = tAxis > tmin && tAxis < tmax ? phiStart + kPi : phiStart;
    for (int v = firstPast; v < 3 * perLap && laps[v] <= phiEnd; ++v)
    {
      const int k = v % perLap;
      out.push({ tAxis, k == azimuthCount - 1 ? -1 : k });
    }
  }
  else if (turn > 0.0)
  {
    // Rising through phi_k enters wedge k (none past a section's last breakpoint).
    for (int v = firstPast; v < 3 * perLap && laps[v] - phiStart < kPi; ++v)
    {
      const int k = v % perLap;
      if (side(k) < 0.0)
        break;
      out.push({ crossAt(k), k == azimuthCount - 1 ? -1 : k });
    }
  }
  else
  {
    // Falling through phi_k enters wedge k - 1; a start exactly on phi_k leaves through it.
    for (int v = firstPast - 1; v >= 0 && phiStart - laps[v] < kPi; --v)
    {
      const int k = v % perLap;
      if (side(k) >= 0.0)
        break;
      out.push({ crossAt(k), k == 0 ? (FullCircle ? azimuthCount - 2 : -1) : k - 1 });
    }
  }
  clampAscending(out, tmin, tmax);
  return azimuthStart;
}

void sealCrossings(const int first[3], TransitionList lists[3], const int counts[3], double tmin,
  double tmax, Crossings& c)
{
  for (int list = 0; list < 3; ++list)
  {
    lists[list].push({ std::numeric_limits<double>::infinity(), 0 });
    c.lists[list] = lists[list].data();
    c.first[list] = first[list];
    c.counts[list] = counts[list];
  }
  c.tmin = tmin;
  c.tmax = tmax;
}
} // namespace traversal
} // namespace sightline
