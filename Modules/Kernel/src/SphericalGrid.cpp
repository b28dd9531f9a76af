#include "sightline/SphericalGrid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

void checkBreakpoints(const std::vector<double>& v, const char* name)
{
  if (v.size() < 2)
    throw std::invalid_argument(std::string("sightline::SphericalGrid: ") + name + " needs at least 2 breakpoints, got " +
      std::to_string(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    if (!std::isfinite(v[i]))
      throw std::invalid_argument(std::string("sightline::SphericalGrid: ") + name + " breakpoint " +
        std::to_string(i) + " is not finite");
    if (i > 0 && !(v[i] > v[i - 1]))
      throw std::invalid_argument(std::string("sightline::SphericalGrid: ") + name + " breakpoints are not strictly increasing at " +
        std::to_string(i) + " (" + std::to_string(v[i - 1]) + ", " + std::to_string(v[i]) + ")");
  }
}

/// A transition of one coordinate's index along the ray.
struct Transition
{
  double t;
  int index; ///< the index after the crossing
};

/// Keeps the list's t ascending and inside [tmin, tmax] (rounding near hinges may swap
/// neighbours by an ulp).
void clampAscending(std::vector<Transition>& list, double tmin, double tmax)
{
  double previous = tmin;
  for (Transition& x : list)
  {
    x.t = std::min(tmax, std::max(previous, x.t));
    previous = x.t;
  }
}
} // namespace

void SphericalGrid::validate() const
{
  checkBreakpoints(radius, "radius");
  checkBreakpoints(polar, "polar angle");
  checkBreakpoints(azimuth, "azimuth");
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
  return std::abs((azimuth.back() - azimuth.front()) - kTwoPi) <= 1e-12 * kTwoPi;
}

SphericalTraversal::SphericalTraversal(SphericalGrid grid)
  : Grid(std::move(grid))
{
  Grid.validate();
  for (double r : Grid.radius)
    RadiusSquared.push_back(r * r);
  for (double theta : Grid.polar)
  {
    // Exact at the poles and the equator, where cones degenerate to the axis and a plane.
    const double c = theta == 0.0 ? 1.0 : theta >= kPi ? -1.0 : std::cos(theta);
    PolarCosine.push_back(c);
    SignedCosineSquared.push_back(c * std::abs(c));
  }
  for (double phi : Grid.azimuth)
    HalfPlanes.push_back(dvec3(std::cos(phi), std::sin(phi), phi));
  FullCircle = Grid.fullCircle();
}

void SphericalTraversal::traverse(const dvec3& p, const dvec3& d, double tmin, double tmax,
  std::vector<CellSegment>& out) const
{
  out.clear();
  const double dd = glm::dot(d, d);
  if (!(dd > 0.0) || std::isnan(tmin) || std::isnan(tmax) || !isFinite(vec3(p)) || !isFinite(vec3(d)))
    return;
  // Only the part inside the outer sphere can hold cells.
  const double tClosest = -glm::dot(p, d) / dd;
  const dvec3 closest = p + tClosest * d;
  const double closestSquared = glm::dot(closest, closest);
  const double outerSquared = RadiusSquared.back();
  if (closestSquared >= outerSquared)
    return;
  // Half chords as (R - |c|)(R + |c|), not R^2 - |c|^2: accurate to the radius's precision for
  // rays that (nearly) touch a sphere, the same expression sphereChord uses.
  const double closestDistance = std::sqrt(closestSquared);
  auto halfChordOf = [&](double radius)
  { return std::sqrt(std::max(0.0, (radius - closestDistance) * (radius + closestDistance)) / dd); };
  const double halfChord = halfChordOf(Grid.radius.back());
  tmin = std::max(tmin, tClosest - halfChord);
  tmax = std::min(tmax, tClosest + halfChord);
  if (!(tmin < tmax))
    return;
  const dvec3 start = p + tmin * d, end = p + tmax * d;

  // Radius: r^2 falls until tClosest and rises after. Index i is the shell [r_i, r_{i+1});
  // -1 below r_0, n - 1 at or beyond the outer sphere.
  auto radialIndex = [&](double r2)
  { return int(std::upper_bound(RadiusSquared.begin(), RadiusSquared.end(), r2) - RadiusSquared.begin()) - 1; };
  // Per-thread scratch lists: no heap allocation per ray once they have grown.
  thread_local std::vector<Transition> radial, polarList, azimuthList;
  thread_local std::vector<std::pair<double, int>> crossings; // (unwrapped angle, breakpoint)
  radial.clear();
  polarList.clear();
  azimuthList.clear();
  {
    const int first = radialIndex(glm::dot(start, start));
    const int last = radialIndex(glm::dot(end, end));
    // The lowest shell: at the hinge when it lies inside [tmin, tmax], else at whichever end is
    // nearer to it (a ray ending before its closest approach only falls).
    const int lowest = tClosest <= tmin ? first : tClosest >= tmax ? last : radialIndex(closestSquared);
    for (int i = first; i > lowest; --i) // falling: leave shell i through r_i
      radial.push_back({ tClosest - halfChordOf(Grid.radius[std::size_t(i)]), i - 1 });
    for (int i = lowest; i < last; ++i) // rising: leave shell i through r_{i+1}
      radial.push_back({ tClosest + halfChordOf(Grid.radius[std::size_t(i + 1)]), i + 1 });
    clampAscending(radial, tmin, tmax);
  }

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
  {
    const double pd = glm::dot(p, d), pp = glm::dot(p, p);
    const double slope = d.z * pd - p.z * dd;
    const double constant = d.z * pp - p.z * pd;
    const dvec3 pCrossD = glm::cross(p, d);
    const bool throughOrigin = glm::dot(pCrossD, pCrossD) <= 1e-28 * pp * dd;
    double tHinge = throughOrigin ? tClosest : (slope != 0.0 ? -constant / slope : tmax + 1.0);
    const bool hinge = tHinge > tmin && tHinge < tmax;
    const int first = polarIndex(start), last = polarIndex(end);
    const int middle = hinge ? polarIndex(p + tHinge * d) : last;
    // The t where the line meets the cone of breakpoint j on the side sign(cos theta_j),
    // within [a, b] (the phase): a root of (dz^2 - c^2 |d|^2) t^2 + 2 (pz dz - c^2 p.d) t
    // + (pz^2 - c^2 |p|^2).
    auto coneCrossing = [&](int j, double a, double b)
    {
      if (throughOrigin)
        return tClosest; // every cone meets the line at the origin
      const double c = PolarCosine[std::size_t(j)], c2 = c * c;
      const double qa = d.z * d.z - c2 * dd, qb = 2.0 * (p.z * d.z - c2 * pd), qc = p.z * p.z - c2 * pp;
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
    auto walk = [&](int from, int to, double a, double b)
    {
      for (int j = from; j < to; ++j) // theta rising: leave band j through theta_{j+1}
        polarList.push_back({ coneCrossing(j + 1, a, b), j + 1 });
      for (int j = from; j > to; --j) // theta falling: leave band j through theta_j
        polarList.push_back({ coneCrossing(j, a, b), j - 1 });
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
  const int azimuthCount = int(HalfPlanes.size());
  const double phi0 = HalfPlanes.front().z;
  auto unwrap = [&](const dvec3& x)
  {
    double phi = std::atan2(x.y, x.x);
    phi = phi0 + std::fmod(std::fmod(phi - phi0, kTwoPi) + kTwoPi, kTwoPi); // in [phi0, phi0 + 2 pi)
    return phi;
  };
  auto azimuthIndex = [&](double phi)
  {
    const int k = int(std::upper_bound(Grid.azimuth.begin(), Grid.azimuth.end(), phi) - Grid.azimuth.begin()) - 1;
    if (k >= azimuthCount - 1)
      return FullCircle ? azimuthCount - 2 : -1;
    return k;
  };
  int azimuthStart = 0;
  {
    const double turn = p.x * d.y - p.y * d.x; // (p x d).z
    const double dxy = d.x * d.x + d.y * d.y;
    const double scaleXY = std::sqrt((p.x * p.x + p.y * p.y) * dxy);
    const bool throughAxis = dxy > 0.0 && std::abs(turn) <= 1e-14 * scaleXY;
    const double tAxis = dxy > 0.0 ? -(p.x * d.x + p.y * d.y) / dxy : 0.0;
    // A line through the z axis has azimuth atan2(-d) before the axis and atan2(d) after it,
    // exactly, whatever rounding leaves of the points next to the axis. A vertical line keeps
    // its azimuth (0 by convention on the axis itself).
    double phiStart;
    if (throughAxis)
      phiStart = tAxis > tmin ? unwrap(-d) : unwrap(d);
    else
      phiStart = unwrap(start);
    azimuthStart = azimuthIndex(phiStart);
    if (dxy > 0.0)
    {
      double phiEnd;
      bool rising;
      if (throughAxis)
      {
        rising = true; // the jump by pi, taken as a rise
        phiEnd = tAxis > tmin && tAxis < tmax ? phiStart + kPi : phiStart;
      }
      else
      {
        rising = turn > 0.0;
        double phiEndRaw = unwrap(end);
        // The sweep is under pi: unwrap the end next to the start, in the sweep's direction.
        if (rising && phiEndRaw < phiStart)
          phiEndRaw += kTwoPi;
        if (!rising && phiEndRaw > phiStart)
          phiEndRaw -= kTwoPi;
        phiEnd = phiEndRaw;
      }
      // Boundaries strictly between the two azimuths, in sweep order, as unwrapped angles.
      int index = azimuthStart;
      crossings.clear();
      // The half-planes' angles over three laps, phi_k + lap 2 pi (the full circle's last
      // breakpoint is its first), form one increasing sequence: binary search for the first
      // one past the start, then walk in the sweep's direction to the end.
      const int perLap = FullCircle ? azimuthCount - 1 : azimuthCount;
      auto angleOf = [&](int v) { return Grid.azimuth[std::size_t(v % perLap)] + (v / perLap - 1) * kTwoPi; };
      int lo = 0, hi = 3 * perLap; // first v with angle > phiStart
      while (lo < hi)
      {
        const int mid = (lo + hi) / 2;
        if (angleOf(mid) > phiStart)
          hi = mid;
        else
          lo = mid + 1;
      }
      // A start exactly on phi_k counts as wedge k: rising it stays, falling it leaves.
      if (rising)
        for (int v = lo; v < 3 * perLap && angleOf(v) <= phiEnd; ++v)
          crossings.push_back({ angleOf(v), v % perLap });
      else
        for (int v = lo - 1; v >= 0 && angleOf(v) >= phiEnd; --v)
          crossings.push_back({ angleOf(v), v % perLap });
      for (const auto& crossing : crossings)
      {
        const int k = crossing.second;
        const dvec3& h = HalfPlanes[std::size_t(k)];
        double t = tAxis;
        if (!throughAxis)
        {
          const double denominator = d.y * h.x - d.x * h.y;
          t = denominator != 0.0 ? (p.x * h.y - p.y * h.x) / denominator : tAxis;
        }
        // Rising through phi_k enters wedge k; falling through it enters wedge k - 1.
        if (rising)
          index = (k == azimuthCount - 1) ? -1 : k;
        else
          index = k == 0 ? (FullCircle ? azimuthCount - 2 : -1) : k - 1;
        azimuthList.push_back({ t, index });
      }
      clampAscending(azimuthList, tmin, tmax);
    }
  }

  // Merge the three ascending lists, emitting the pieces inside the section.
  int ir = radialIndex(glm::dot(start, start)), it = polarIndex(start), ip = azimuthStart;
  const int nr = Grid.radialCells(), nt = Grid.polarCells();
  std::size_t a = 0, b = 0, c = 0;
  double t0 = tmin;
  auto emit = [&](double t1)
  {
    if (t1 > t0 && ir >= 0 && ir < nr && it >= 0 && it < nt && ip >= 0)
      out.push_back({ ir, it, ip, t0, t1 });
    t0 = std::max(t0, t1);
  };
  while (a < radial.size() || b < polarList.size() || c < azimuthList.size())
  {
    const double ta = a < radial.size() ? radial[a].t : 1e300;
    const double tb = b < polarList.size() ? polarList[b].t : 1e300;
    const double tc = c < azimuthList.size() ? azimuthList[c].t : 1e300;
    if (ta <= tb && ta <= tc)
    {
      emit(ta);
      ir = radial[a++].index;
    }
    else if (tb <= tc)
    {
      emit(tb);
      it = polarList[b++].index;
    }
    else
    {
      emit(tc);
      ip = azimuthList[c++].index;
    }
  }
  emit(tmax);
}

double projectCellConstant(const SphericalGrid& grid, const std::vector<double>& values,
  const std::vector<CellSegment>& segments, double directionLength)
{
  if (values.size() != grid.cellCount())
    throw std::invalid_argument("sightline::projectCellConstant: " + std::to_string(values.size()) +
      " values for " + std::to_string(grid.cellCount()) + " cells");
  double sum = 0.0;
  for (const CellSegment& s : segments)
    sum += values[grid.cellIndex(s.r, s.theta, s.phi)] * (s.t1 - s.t0);
  return sum * directionLength;
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

double projectLinearInRadius(const SphericalGrid& grid, const std::vector<double>& nodeValues,
  const std::vector<CellSegment>& segments, const dvec3& origin, const dvec3& direction)
{
  checkNodeCount(grid, nodeValues, "projectLinearInRadius");
  const ClosestApproach c(origin, direction);
  const std::size_t nodes = grid.radius.size();
  double sum = 0.0;
  for (const CellSegment& s : segments)
  {
    const std::size_t column = nodes * (std::size_t(s.theta) + std::size_t(grid.polarCells()) * std::size_t(s.phi));
    const double f0 = nodeValues[column + s.r], f1 = nodeValues[column + s.r + 1];
    const double r0 = grid.radius[s.r], r1 = grid.radius[s.r + 1];
    const double slope = (f1 - f0) / (r1 - r0);
    const double u0 = s.t0 - c.t, u1 = s.t1 - c.t;
    const double integralOfR = radiusAntiderivative(u1, c.a, c.p2) - radiusAntiderivative(u0, c.a, c.p2);
    sum += (f0 - slope * r0) * (u1 - u0) + slope * integralOfR;
  }
  return sum * std::sqrt(c.a);
}

double projectLinearInRadiusSquared(const SphericalGrid& grid, const std::vector<double>& nodeValues,
  const std::vector<CellSegment>& segments, const dvec3& origin, const dvec3& direction)
{
  checkNodeCount(grid, nodeValues, "projectLinearInRadiusSquared");
  const ClosestApproach c(origin, direction);
  const std::size_t nodes = grid.radius.size();
  double sum = 0.0;
  for (const CellSegment& s : segments)
  {
    const std::size_t column = nodes * (std::size_t(s.theta) + std::size_t(grid.polarCells()) * std::size_t(s.phi));
    const double f0 = nodeValues[column + s.r], f1 = nodeValues[column + s.r + 1];
    const double q0 = grid.radius[s.r] * grid.radius[s.r], q1 = grid.radius[s.r + 1] * grid.radius[s.r + 1];
    const double slope = (f1 - f0) / (q1 - q0);
    const double u0 = s.t0 - c.t, u1 = s.t1 - c.t;
    // r^2 = p^2 + a u^2 integrates to p^2 (u1 - u0) + a (u1^3 - u0^3) / 3.
    const double integralOfR2 = c.p2 * (u1 - u0) + c.a * (u1 * u1 * u1 - u0 * u0 * u0) / 3.0;
    sum += (f0 - slope * q0) * (u1 - u0) + slope * integralOfR2;
  }
  return sum * std::sqrt(c.a);
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

} // namespace sightline
