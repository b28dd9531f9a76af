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

namespace
{
/// A monotone stand-in for the angle of (x, y) != 0 in [0, 4): one division, no atan2. Only
/// locates a first guess among the half-planes; the sign tests decide.
double diamondAngle(double x, double y)
{
  if (y >= 0.0)
    return x > 0.0 ? y / (x + y) : 1.0 - x / (y - x);
  return x < 0.0 ? 2.0 - y / (-x - y) : 3.0 + x / (x - y);
}
} // namespace

AzimuthSweep::AzimuthSweep(const std::vector<double>& azimuth)
  : FullCircle(spansFullCircle(azimuth))
{
  // The half-planes once around from phi_0 (a full circle's last breakpoint is its first), with
  // extra ones that change no index wherever two are more than pi / 2 apart (the section's gap,
  // coarse wedges): sign tests against neighbouring half-planes then tell where a point lies.
  const int real = FullCircle ? int(azimuth.size()) - 1 : int(azimuth.size());
  const double phi0 = azimuth.front();
  const double d0 = diamondAngle(std::cos(phi0), std::sin(phi0));
  for (int k = 0; k < real; ++k)
  {
    const double next = k + 1 < real ? azimuth[std::size_t(k) + 1] : phi0 + kTwoPi;
    const int pieces = std::max(1, int(std::ceil((next - azimuth[std::size_t(k)]) / (0.5 * kPi))));
    const int wedge = k == int(azimuth.size()) - 1 ? -1 : k; // past a section's last: none
    for (int piece = 0; piece < pieces; ++piece)
    {
      const double phi = azimuth[std::size_t(k)] + (next - azimuth[std::size_t(k)]) * piece / pieces;
      HalfPlane h;
      h.x = std::cos(phi);
      h.y = std::sin(phi);
      h.wedge = wedge;
      h.crossed = piece == 0;
      double pseudo = diamondAngle(h.x, h.y) - d0;
      if (pseudo < 0.0)
        pseudo += 4.0;
      Pseudo.push_back(HalfPlanes.empty() ? 0.0 : std::max(Pseudo.back(), pseudo));
      HalfPlanes.push_back(h);
    }
  }
  PseudoStart = d0;
}

int AzimuthSweep::locate(double x, double y) const
{
  // On the z axis itself the azimuth is 0 by convention.
  if (x == 0.0 && y == 0.0)
    x = 1.0;
  const int n = int(HalfPlanes.size());
  double pseudo = diamondAngle(x, y) - PseudoStart;
  if (pseudo < 0.0)
    pseudo += 4.0;
  int s = std::max(0, int(std::upper_bound(Pseudo.begin(), Pseudo.end(), pseudo) - Pseudo.begin()) - 1);
  // The guess is at most a rounding away: settle it on the sign tests, the crossings' own
  // (a point on a half-plane belongs to the wedge it opens).
  auto side = [&](int k) { return HalfPlanes[std::size_t(k)].x * y - HalfPlanes[std::size_t(k)].y * x; };
  for (int step = 0; step < n; ++step)
  {
    if (side(s) < 0.0)
      s = s == 0 ? n - 1 : s - 1;
    else if (const int next = s + 1 == n ? 0 : s + 1; side(next) >= 0.0)
      s = next;
    else
      break;
  }
  return s;
}

int AzimuthSweep::transitions(const dvec3& p, const dvec3& d, double tmin, double tmax,
  const dvec3& start, const dvec3& end, TransitionList& out) const
{
  const int n = int(HalfPlanes.size());
  out.reset(std::size_t(n) + 1);
  const double turn = p.x * d.y - p.y * d.x; // (p x d).z
  const double dxy = d.x * d.x + d.y * d.y;
  const double scaleXY = std::sqrt((p.x * p.x + p.y * p.y) * dxy);
  const bool throughAxis = dxy > 0.0 && std::abs(turn) <= 1e-14 * scaleXY;
  const double tAxis = dxy > 0.0 ? -(p.x * d.x + p.y * d.y) / dxy : 0.0;
  // A line through the z axis has the azimuth of -d before the axis and of d after it, exactly,
  // whatever rounding leaves of the points next to the axis. A vertical line keeps its azimuth.
  const bool beforeAxis = throughAxis && tAxis > tmin;
  const int slot = throughAxis ? (beforeAxis ? locate(-d.x, -d.y) : locate(d.x, d.y)) : locate(start.x, start.y);
  const int azimuthStart = HalfPlanes[std::size_t(slot)].wedge;
  if (!(dxy > 0.0) || (throughAxis && !(beforeAxis && tAxis < tmax)))
    return azimuthStart;

  // Walk the half-planes in the sweep's direction while the segment's end lies past the next
  // one: the sign of (h x end).z, the crossing's own test (crossAt solves (h x (p + t d)).z =
  // 0). Neighbours are under pi / 2 apart and the sweep is under pi, so the first half-plane
  // the end does not pass ends the walk. A line through the axis jumps by pi there: the end's
  // azimuth is d's.
  const double ex = throughAxis ? d.x : end.x, ey = throughAxis ? d.y : end.y;
  auto side = [&](int k) { return HalfPlanes[std::size_t(k)].x * ey - HalfPlanes[std::size_t(k)].y * ex; };
  auto crossAt = [&](int k)
  {
    const HalfPlane& h = HalfPlanes[std::size_t(k)];
    if (throughAxis)
      return tAxis;
    const double denominator = d.y * h.x - d.x * h.y;
    return denominator != 0.0 ? (p.x * h.y - p.y * h.x) / denominator : tAxis;
  };
  if (throughAxis || turn > 0.0)
  {
    // Rising through a half-plane enters the wedge it opens.
    for (int step = 1, k = slot; step < n; ++step)
    {
      k = k + 1 == n ? 0 : k + 1;
      if (side(k) < 0.0)
        break;
      if (HalfPlanes[std::size_t(k)].crossed)
        out.push({ crossAt(k), HalfPlanes[std::size_t(k)].wedge });
    }
  }
  else
  {
    // Falling through one enters the wedge before it; a start exactly on it leaves at once.
    for (int step = 0, k = slot; step < n; ++step, k = k == 0 ? n - 1 : k - 1)
    {
      if (side(k) >= 0.0)
        break;
      if (HalfPlanes[std::size_t(k)].crossed)
        out.push({ crossAt(k), HalfPlanes[std::size_t(k == 0 ? n - 1 : k - 1)].wedge });
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
