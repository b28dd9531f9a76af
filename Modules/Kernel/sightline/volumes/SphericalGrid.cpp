// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/volumes/SphericalGrid.h"

#include "sightline/volumes/GridTraversal.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
using traversal::checkBreakpoints;
using traversal::clampAscending;
using traversal::Transition;

void SphericalGrid::validate() const
{
  checkBreakpoints(radius, "SphericalGrid", "radius");
  checkBreakpoints(polar, "SphericalGrid", "polar angle");
  checkBreakpoints(azimuth, "SphericalGrid", "azimuth");
  if (radius.front() < 0.0)
    throw std::invalid_argument("sightline::SphericalGrid: radius breakpoints start below 0 (" +
      std::to_string(radius.front()) + ")");
  if (polar.front() < 0.0 || polar.back() > kPi * (1.0 + 1e-12))
    throw std::invalid_argument("sightline::SphericalGrid: polar angle breakpoints [" +
      std::to_string(polar.front()) + ", " + std::to_string(polar.back()) +
      "] leave [0, pi] (radians, colatitude)");
  if (azimuth.back() - azimuth.front() > kTwoPi * (1.0 + 1e-12))
    throw std::invalid_argument("sightline::SphericalGrid: azimuth breakpoints span " +
      std::to_string(azimuth.back() - azimuth.front()) + " radians, more than 2 pi");
}

bool SphericalGrid::fullCircle() const
{
  return traversal::spansFullCircle(azimuth);
}

SphericalTraversal::SphericalTraversal(SphericalGrid grid)
  : Grid((grid.validate(), std::move(grid)))
  , Azimuth(std::make_shared<traversal::AzimuthSweep>(Grid.azimuth))
{
  for (double r : Grid.radius)
    RadiusSquared.push_back(r * r);
  for (double theta : Grid.polar)
  {
    // Exact at the poles and the equator, where cones degenerate to the axis and a plane.
    const double c = theta == 0.0 ? 1.0 : theta >= kPi ? -1.0 : std::cos(theta);
    PolarCosine.push_back(c);
    SignedCosineSquared.push_back(c * std::abs(c));
  }
}

void SphericalTraversal::traverse(const dvec3& p, const dvec3& d, double tmin, double tmax,
  std::vector<CellSegment>& out) const
{
  out.clear();
  forEachCell(p, d, tmin, tmax, traversal::appendingTo(out));
}

bool SphericalTraversal::crossings(const dvec3& p, const dvec3& d, double tmin, double tmax,
  traversal::Crossings& crossed) const
{
  const double dd = glm::dot(d, d);
  if (!(dd > 0.0) || std::isnan(tmin) || std::isnan(tmax) || !isFinite(vec3(p)) || !isFinite(vec3(d)))
    return false;
  // Only the part inside the outer sphere can hold cells.
  const double tClosest = -glm::dot(p, d) / dd;
  const dvec3 closest = p + tClosest * d;
  const double closestSquared = glm::dot(closest, closest);
  const double outerSquared = RadiusSquared.back();
  if (closestSquared >= outerSquared)
    return false;
  // Half chords as (R - |c|)(R + |c|), not R^2 - |c|^2: accurate to the radius's precision for
  // rays that (nearly) touch a sphere, the same expression sphereChord uses.
  const double closestDistance = std::sqrt(closestSquared);
  auto halfChordOf = [&](double radius)
  { return std::sqrt(std::max(0.0, (radius - closestDistance) * (radius + closestDistance)) / dd); };
  const double halfChord = halfChordOf(Grid.radius.back());
  tmin = std::max(tmin, tClosest - halfChord);
  tmax = std::min(tmax, tClosest + halfChord);
  if (!(tmin < tmax))
    return false;
  const dvec3 start = p + tmin * d, end = p + tmax * d;

  // Per-thread scratch lists: no heap allocation per ray once they have grown.
  traversal::CrossingScratch& scratch = traversal::threadCrossingScratch();
  traversal::TransitionList& polarList = scratch.lists[1];
  // Radius: r^2 falls until tClosest and rises after. Index i is the shell [r_i, r_{i+1}).
  const int radialStart = traversal::radialTransitions(Grid.radius, RadiusSquared, tClosest,
    closestDistance, dd, tmin, tmax, glm::dot(start, start), glm::dot(end, end), scratch.lists[0],
    scratch.halfChords);

  // Polar angle: s = cos theta |cos theta| along the line is ditone; its hinge is where
  // (dz |p|^2 - pz p.d) + t (dz p.d - pz |d|^2) vanishes. Index j is [theta_j, theta_{j+1}),
  // i.e. s in (S_{j+1}, S_j]; -1 above S_0 (theta < theta_0), m - 1 below S_m.
  const int polarCount = int(SignedCosineSquared.size());
  auto polarIndex = [&](const dvec3& x)
  {
    const double r2 = glm::dot(x, x);
    const double s = r2 > 0.0 ? x.z * std::abs(x.z) / r2 : 0.0;
    // Count breakpoints with S_j >= s (S decreasing).
    int lo = 0, hi = polarCount;
    while (lo < hi)
    {
      const int mid = (lo + hi) / 2;
      if (SignedCosineSquared[std::size_t(mid)] >= s)
        lo = mid + 1;
      else
        hi = mid;
    }
    // theta = pi itself (the negative z axis) belongs to the last band when the grid reaches
    // the south pole, as theta = 0 belongs to the first.
    if (lo == polarCount && SignedCosineSquared.back() <= -1.0)
      return polarCount - 2;
    return lo - 1;
  };
  const int polarStart = polarIndex(start);
  {
    const double pd = glm::dot(p, d), pp = glm::dot(p, p);
    const double slope = d.z * pd - p.z * dd;
    const double constant = d.z * pp - p.z * pd;
    const dvec3 pCrossD = glm::cross(p, d);
    const bool throughOrigin = glm::dot(pCrossD, pCrossD) <= 1e-28 * pp * dd;
    double tHinge = throughOrigin ? tClosest : (slope != 0.0 ? -constant / slope : tmax + 1.0);
    const bool hinge = tHinge > tmin && tHinge < tmax;
    const double dzdz = d.z * d.z, pzdz = p.z * d.z, pzpz = p.z * p.z;
    const int first = polarStart, last = polarIndex(end);
    const int middle = hinge ? polarIndex(p + tHinge * d) : last;
    // The t where the line meets the cone of breakpoint j on the side sign(cos theta_j),
    // within [a, b] (the phase): a root of (dz^2 - c^2 |d|^2) t^2 + 2 (pz dz - c^2 p.d) t
    // + (pz^2 - c^2 |p|^2).
    auto coneCrossing = [&](int j, double a, double b)
    {
      if (throughOrigin)
        return tClosest; // every cone meets the line at the origin
      const double c = PolarCosine[std::size_t(j)], c2 = c * c;
      const double qa = dzdz - c2 * dd, qb = 2.0 * (pzdz - c2 * pd), qc = pzpz - c2 * pp;
      double roots[2];
      int count = 0;
      const double scale = std::abs(qa) + std::abs(qb) + std::abs(qc);
      if (std::abs(qa) <= 1e-14 * scale)
      {
        if (qb != 0.0)
          roots[count++] = -qc / qb;
      }
      else
      {
        const double disc = std::max(0.0, qb * qb - 4.0 * qa * qc);
        const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
        roots[count++] = q / qa;
        if (q != 0.0)
          roots[count++] = qc / q;
      }
      // Prefer a root on the cone's own nappe inside the phase; else the nearest to it.
      double best = 0.5 * (a + b), bestScore = 1e300;
      for (int k = 0; k < count; ++k)
      {
        const double t = roots[k];
        const double z = p.z + t * d.z;
        const bool side = c == 0.0 || (z >= 0.0) == (c > 0.0);
        const double outside = t < a ? a - t : t > b ? t - b : 0.0;
        const double score = outside + (side ? 0.0 : 1e200);
        if (score < bestScore)
        {
          bestScore = score;
          best = t;
        }
      }
      return std::min(b, std::max(a, best));
    };
    // Crossings written in place: the cones are independent, so their square roots and
    // divisions overlap.
    polarList.reset(2 * std::size_t(polarCount) + 1);
    auto walk = [&](int from, int to, double a, double b)
    {
      for (int j = from; j < to; ++j) // theta rising: leave band j through theta_{j+1}
        polarList.push({ coneCrossing(j + 1, a, b), j + 1 });
      for (int j = from; j > to; --j) // theta falling: leave band j through theta_j
        polarList.push({ coneCrossing(j, a, b), j - 1 });
    };
    if (hinge)
    {
      walk(first, middle, tmin, tHinge);
      walk(middle, last, tHinge, tmax);
    }
    else
      walk(first, last, tmin, tmax);
    clampAscending(polarList, tmin, tmax);
  }

  // Azimuth: monotone along the line, rising when (p x d).z > 0; a line through the z axis
  // jumps by pi there. Index k is [phi_k, phi_{k+1}); -1 outside a wedge.
  const int azimuthStart = Azimuth->transitions(p, d, tmin, tmax, start, end, scratch.lists[2]);

  // Merge the three ascending lists, emitting the pieces inside the section.
  const int first[3] = { radialStart, polarStart, azimuthStart };
  const int counts[3] = { Grid.radialCells(), Grid.polarCells(), Grid.azimuthalCells() };
  traversal::sealCrossings(first, scratch.lists, counts, tmin, tmax, crossed);
  return true;
}

vec4 emissionAbsorption(const SphericalGrid& grid, const std::vector<double>& values,
  const std::function<TransferSample(double)>& transfer, const std::vector<CellSegment>& segments,
  double directionLength, double minimumTransmittance)
{
  if (values.size() != grid.cellCount())
    throw std::invalid_argument("sightline::emissionAbsorption: " + std::to_string(values.size()) +
      " values for " + std::to_string(grid.cellCount()) + " cells");
  TransferSample sample;
  return compositeCells(
    [&](const CellSegment& s) -> const TransferSample&
    {
      sample = transfer(values[grid.cellIndex(s.r, s.theta, s.phi)]);
      return sample;
    },
    segments, directionLength, minimumTransmittance);
}
namespace
{
// The ray's closest approach to the origin: t there, |direction|^2 and the squared distance.
struct ClosestApproach
{
  double t, a, p2;
  ClosestApproach(const dvec3& origin, const dvec3& direction)
  {
    a = glm::dot(direction, direction);
    t = -glm::dot(origin, direction) / a;
    const dvec3 foot = origin + t * direction;
    p2 = glm::dot(foot, foot);
  }
};

void checkNodeCount(const SphericalGrid& grid, const std::vector<double>& nodeValues, const char* who)
{
  const std::size_t expected =
    grid.radius.size() * std::size_t(grid.polarCells()) * std::size_t(grid.azimuthalCells());
  if (nodeValues.size() != expected)
    throw std::invalid_argument(std::string("sightline::") + who + ": " + std::to_string(nodeValues.size()) +
      " node values for " + std::to_string(expected) + " (radius breakpoints x theta cells x phi cells)");
}

// Integral of sqrt(p2 + a u^2) du from 0 to u (an odd function of u).
double radiusAntiderivative(double u, double a, double p2)
{
  const double r = std::sqrt(p2 + a * u * u);
  const double sa = std::sqrt(a);
  if (!(p2 > 0.0))
    return 0.5 * sa * u * std::abs(u);
  const double p = std::sqrt(p2);
  return 0.5 * (u * r + p2 / sa * std::asinh(sa * u / p));
}
} // namespace

namespace
{
// Line integral of node values interpolated linearly in q(r) inside each cell (q = r or r^2):
// f = f0 + slope (q - q0), integrated with the exact integral of q along the segment, given in
// the closest-approach parameter u by `integralOfQ(u0, u1)`. `forEachSegment(add)` calls
// add(r, theta, phi, t0, t1) for each cell of the ray: from a list or from the traversal.
template <class Q, class IntegralOfQ, class ForEachSegment>
double projectLinearIn(const SphericalGrid& grid, const std::vector<double>& nodeValues,
  const ForEachSegment& forEachSegment, const dvec3& origin, const dvec3& direction, const char* who,
  const Q& q, const IntegralOfQ& integralOfQ)
{
  checkNodeCount(grid, nodeValues, who);
  const ClosestApproach c(origin, direction);
  const std::size_t nodes = grid.radius.size(), polarCells = std::size_t(grid.polarCells());
  const double* values = nodeValues.data();
  const double* radius = grid.radius.data();
  double sum = 0.0;
  forEachSegment(
    [&](int r, int theta, int phi, double t0, double t1)
    {
      const std::size_t column = nodes * (std::size_t(theta) + polarCells * std::size_t(phi));
      const double f0 = values[column + r], f1 = values[column + r + 1];
      const double q0 = q(radius[r]), q1 = q(radius[r + 1]);
      const double slope = (f1 - f0) / (q1 - q0);
      const double u0 = t0 - c.t, u1 = t1 - c.t;
      sum += (f0 - slope * q0) * (u1 - u0) + slope * integralOfQ(c, u0, u1);
      return true;
    });
  return sum * std::sqrt(c.a);
}

// The two ways to walk a ray's cells: a list of segments, or the traversal itself.
auto segmentsOf(const std::vector<CellSegment>& segments)
{
  return [&segments](const auto& add)
  {
    for (const CellSegment& s : segments)
      add(s.r, s.theta, s.phi, s.t0, s.t1);
  };
}
auto traversalOf(const SphericalTraversal& traversal, const dvec3& origin, const dvec3& direction, double tmin, double tmax)
{
  return [&traversal, origin, direction, tmin, tmax](const auto& add)
  { traversal.forEachCell(origin, direction, tmin, tmax, add); };
}

// Value x length summed over a ray's cells (yt's ProjectionSampler).
template <class ForEachSegment>
double projectCellConstantOver(const SphericalGrid& grid, const std::vector<double>& values,
  const ForEachSegment& forEachSegment, double directionLength)
{
  if (values.size() != grid.cellCount())
    throw std::invalid_argument("sightline::projectCellConstant: " + std::to_string(values.size()) +
      " values for " + std::to_string(grid.cellCount()) + " cells");
  const double* v = values.data();
  const std::size_t nr = std::size_t(grid.radialCells()), nrTheta = nr * std::size_t(grid.polarCells());
  double sum = 0.0;
  forEachSegment(
    [&](int r, int theta, int phi, double t0, double t1)
    {
      sum += v[std::size_t(r) + nr * std::size_t(theta) + nrTheta * std::size_t(phi)] * (t1 - t0);
      return true;
    });
  return sum * directionLength;
}

const auto kRadius = [](double r) { return r; };
const auto kIntegralOfRadius = [](const ClosestApproach& c, double u0, double u1)
{ return radiusAntiderivative(u1, c.a, c.p2) - radiusAntiderivative(u0, c.a, c.p2); };
const auto kRadiusSquared = [](double r) { return r * r; };
// r^2 = p^2 + a u^2 integrates to p^2 (u1 - u0) + a (u1^3 - u0^3) / 3.
const auto kIntegralOfRadiusSquared = [](const ClosestApproach& c, double u0, double u1)
{ return c.p2 * (u1 - u0) + c.a * (u1 * u1 * u1 - u0 * u0 * u0) / 3.0; };
} // namespace

double projectCellConstant(const SphericalGrid& grid, const std::vector<double>& values,
  const std::vector<CellSegment>& segments, double directionLength)
{
  return projectCellConstantOver(grid, values, segmentsOf(segments), directionLength);
}

double projectCellConstant(const SphericalTraversal& traversal, const std::vector<double>& values,
  const dvec3& origin, const dvec3& direction, double tmin, double tmax)
{
  return projectCellConstantOver(traversal.grid(), values, traversalOf(traversal, origin, direction, tmin, tmax),
    glm::length(direction));
}

double projectLinearInRadius(const SphericalGrid& grid, const std::vector<double>& nodeValues,
  const std::vector<CellSegment>& segments, const dvec3& origin, const dvec3& direction)
{
  return projectLinearIn(grid, nodeValues, segmentsOf(segments), origin, direction, "projectLinearInRadius",
    kRadius, kIntegralOfRadius);
}

double projectLinearInRadiusSquared(const SphericalGrid& grid, const std::vector<double>& nodeValues,
  const std::vector<CellSegment>& segments, const dvec3& origin, const dvec3& direction)
{
  return projectLinearIn(grid, nodeValues, segmentsOf(segments), origin, direction,
    "projectLinearInRadiusSquared", kRadiusSquared, kIntegralOfRadiusSquared);
}

double projectLinearInRadius(const SphericalTraversal& traversal, const std::vector<double>& nodeValues,
  const dvec3& origin, const dvec3& direction, double tmin, double tmax)
{
  return projectLinearIn(traversal.grid(), nodeValues, traversalOf(traversal, origin, direction, tmin, tmax),
    origin, direction, "projectLinearInRadius", kRadius, kIntegralOfRadius);
}

double projectLinearInRadiusSquared(const SphericalTraversal& traversal, const std::vector<double>& nodeValues,
  const dvec3& origin, const dvec3& direction, double tmin, double tmax)
{
  return projectLinearIn(traversal.grid(), nodeValues, traversalOf(traversal, origin, direction, tmin, tmax),
    origin, direction, "projectLinearInRadiusSquared", kRadiusSquared, kIntegralOfRadiusSquared);
}

std::vector<double> sampleRadialNodes(
  const SphericalGrid& grid, const std::function<double(double, double, double)>& field)
{
  grid.validate();
  std::vector<double> values;
  values.reserve(grid.radius.size() * std::size_t(grid.polarCells()) * std::size_t(grid.azimuthalCells()));
  for (int k = 0; k < grid.azimuthalCells(); ++k)
    for (int j = 0; j < grid.polarCells(); ++j)
      for (double r : grid.radius)
        values.push_back(field(r, 0.5 * (grid.polar[j] + grid.polar[j + 1]), 0.5 * (grid.azimuth[k] + grid.azimuth[k + 1])));
  return values;
}

bool sphereChord(const dvec3& origin, const dvec3& direction, double radius, double t0, double t1,
  double& enter, double& leave)
{
  const double a = glm::dot(direction, direction);
  const double closest = -glm::dot(origin, direction) / a;
  const dvec3 foot = origin + closest * direction;
  // (R - |p|)(R + |p|) keeps the half chord accurate for grazing rays.
  const double footDistance = glm::length(foot);
  const double halfSquared = (radius - footDistance) * (radius + footDistance) / a;
  if (!(halfSquared > 0.0))
    return false;
  const double half = std::sqrt(halfSquared);
  enter = std::max(t0, closest - half);
  leave = std::min(t1, closest + half);
  return enter < leave;
}
} // namespace sightline
