// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/core/SurfaceUnion.h"

#include <algorithm>

namespace sightline
{
void unionSurfaces(std::vector<InsideInterval>& intervals, double tnear, double tfar, double gap,
  std::vector<UnionSurface>& out)
{
  out.clear();
  // A total order: the surfaces, and which part each comes from where intervals tie, do not
  // depend on the order Embree visited the primitives (ray by ray or in packets).
  std::sort(intervals.begin(), intervals.end(), [](const InsideInterval& a, const InsideInterval& b)
    {
      if (a.t0 != b.t0)
        return a.t0 < b.t0;
      if (a.t1 != b.t1)
        return a.t1 < b.t1;
      if (a.geometry != b.geometry)
        return a.geometry < b.geometry;
      if (a.part != b.part)
        return a.part < b.part;
      return a.primitive < b.primitive;
    });
  std::size_t i = 0;
  while (i < intervals.size() && intervals[i].t0 < tfar)
  {
    // One connected piece of the union: [entry, exit], extended while the next interval
    // starts before the current exit.
    const InsideInterval& first = intervals[i];
    double exit = first.t1;
    std::uint32_t exitPart = first.part, exitGeometry = first.geometry;
    for (++i; i < intervals.size() && intervals[i].t0 <= exit + gap; ++i)
      if (intervals[i].t1 > exit)
      {
        exit = intervals[i].t1;
        exitPart = intervals[i].part;
        exitGeometry = intervals[i].geometry;
      }
    if (first.t0 > tnear)
      out.push_back({ first.t0, true, first.part, first.geometry });
    if (exit > tnear && exit < tfar)
      out.push_back({ exit, false, exitPart, exitGeometry });
  }
}
} // namespace sightline
