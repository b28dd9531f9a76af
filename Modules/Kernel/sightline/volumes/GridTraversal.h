// SPDX-License-Identifier: BSD-3-Clause
// Pieces shared by the spherical and cylindrical traversals (SphericalGrid.h,
// CylindricalGrid.h): index transitions along a ray for a radius measured from a point or an
// axis (ditone: one hinge at the closest approach), for azimuth half-planes around the z axis
// (monotone), and the linear merge of three sorted transition lists into cell segments.
// Private to the kernel.
#pragma once

#include "sightline/math/Math.h"
#include "sightline/volumes/SphericalGrid.h"

#include <memory>
#include <vector>

namespace sightline
{
namespace traversal
{

/// Throws std::invalid_argument (naming `owner` and `name`) for fewer than 2 breakpoints, NaN
/// or infinite ones, or breakpoints that are not strictly increasing.
void checkBreakpoints(const std::vector<double>& v, const char* owner, const char* name);

/// Whether azimuth breakpoints span the full circle (2 pi to 1e-12).
bool spansFullCircle(const std::vector<double>& azimuth);

/// A per-thread buffer that grows to a grid's bound once: appending checks no capacity and
/// growing never zero-fills (a ray of a small grid costs less than the vector bookkeeping).
template <class T>
class ScratchList
{
public:
  /// Empties the list and makes room for `capacity` elements.
  void reset(std::size_t capacity)
  {
    if (capacity > Capacity)
    {
      Data.reset(new T[capacity]);
      Capacity = capacity;
    }
    Size = 0;
  }
  void push(const T& x) { Data[Size++] = x; }
  T* data() { return Data.get(); }
  T* begin() { return Data.get(); }
  T* end() { return Data.get() + Size; }
  std::size_t size() const { return Size; }

private:
  std::unique_ptr<T[]> Data;
  std::size_t Capacity = 0, Size = 0;
};
using TransitionList = ScratchList<Transition>;

/// A thread's lists for one ray's crossings (one thread-local lookup per ray).
struct CrossingScratch
{
  TransitionList lists[3];
  ScratchList<double> halfChords;
};
CrossingScratch& threadCrossingScratch();

/// Keeps the list's t ascending and inside [tmin, tmax] (rounding near hinges may swap
/// neighbours by an ulp).
void clampAscending(TransitionList& list, double tmin, double tmax);

/// Shells between radii (from the origin or from the z axis). The ray's squared distance is
/// closestDistance^2 + dd (t - tClosest)^2; crossings use (R - c)(R + c) for the half chord.
/// Fills the transitions inside [tmin, tmax] (`out` reset to room for 2 n + 1, the sentinel
/// included) and returns the index at tmin (-1 below the first radius, n - 1 at or beyond the
/// last).
int radialTransitions(const std::vector<double>& radius, const std::vector<double>& radiusSquared,
  double tClosest, double closestDistance, double dd, double tmin, double tmax, double startSquared,
  double endSquared, TransitionList& out, ScratchList<double>& halfChords);

/// Wedges between half-planes through the z axis at the azimuth breakpoints. Points are placed
/// by the sign of (h x point).z against the half-planes h = (cos phi_k, sin phi_k), the same
/// test the crossings solve, so a ray's wedges and crossings agree to the last bit, and no
/// atan2 is taken.
class AzimuthSweep
{
public:
  explicit AzimuthSweep(const std::vector<double>& azimuth);
  bool fullCircle() const { return FullCircle; }
  /// Fills the transitions of the ray (p + t d, t in [tmin, tmax], from `start` to `end`;
  /// `out` reset to room for them and the sentinel) and returns the wedge index at tmin (-1
  /// outside a section's wedges).
  int transitions(const dvec3& p, const dvec3& d, double tmin, double tmax, const dvec3& start,
    const dvec3& end, TransitionList& out) const;

private:
  struct HalfPlane
  {
    double x, y;  ///< cos phi, sin phi
    int wedge;    ///< the wedge it opens (counterclockwise of it); -1 in a section's gap
    bool crossed; ///< a breakpoint (false: added to split a gap wider than pi / 2)
  };
  /// The half-plane opening the wedge that holds (x, y).
  int locate(double x, double y) const;

  std::vector<HalfPlane> HalfPlanes; ///< once around, counterclockwise from phi_0
  std::vector<double> Pseudo;        ///< their diamond angles from phi_0's, for a first guess
  double PseudoStart = 0.0;
  bool FullCircle = false;
};

/// The three ascending transition lists ready to merge (CellCrossings.h): appends the sentinel
/// to each and fills `out` in place.
void sealCrossings(const int first[3], TransitionList lists[3], const int counts[3], double tmin,
  double tmax, Crossings& out);
} // namespace traversal
} // namespace sightline
