// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/volumes/CylindricalGrid.h"

#include "sightline/volumes/GridTraversal.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sightline
{
void CylindricalGrid::validate() const
{
  traversal::checkBreakpoints(radius, "CylindricalGrid", "radius");
  traversal::checkBreakpoints(azimuth, "CylindricalGrid", "azimuth");
  traversal::checkBreakpoints(height, "CylindricalGrid", "height");
  if (radius.front() < 0.0)
    throw std::invalid_argument("sightline::CylindricalGrid: radius breakpoints start below 0 (" +
      std::to_string(radius.front()) + ")");
  if (azimuth.back() - azimuth.front() > kTwoPi * (1.0 + 1e-12))
    throw std::invalid_argument("sightline::CylindricalGrid: azimuth breakpoints span " +
      std::to_string(azimuth.back() - azimuth.front()) + " radians, more than 2 pi");
}

bool CylindricalGrid::fullCircle() const
{
  return traversal::spansFullCircle(azimuth);
}

CylindricalTraversal::CylindricalTraversal(CylindricalGrid grid)
  : Grid((grid.validate(), std::move(grid)))
  , Azimuth(std::make_shared<traversal::AzimuthSweep>(Grid.azimuth))
{
  for (double r : Grid.radius)
    RadiusSquared.push_back(r * r);
}

void CylindricalTraversal::traverse(const dvec3& p, const dvec3& d, double tmin, double tmax,
  std::vector<CellSegment>& out) const
{
  out.clear();
  forEachCell(p, d, tmin, tmax, traversal::appendingTo(out));
}

bool CylindricalTraversal::crossings(const dvec3& p, const dvec3& d, double tmin, double tmax,
  traversal::Crossings& crossed) const
{
  using traversal::Transition;
  if (!(glm::dot(d, d) > 0.0) || std::isnan(tmin) || std::isnan(tmax) || !isFinite(vec3(p)) || !isFinite(vec3(d)))
    return false;
  // The slab between the first and last heights.
  const double z0 = Grid.height.front(), z1 = Grid.height.back();
  if (d.z != 0.0)
  {
    const double a = (z0 - p.z) / d.z, b = (z1 - p.z) / d.z;
    tmin = std::max(tmin, std::min(a, b));
    tmax = std::min(tmax, std::max(a, b));
  }
  else if (p.z < z0 || p.z > z1)
    return false;
  // The outer cylinder; rho^2 = c^2 + dxy (t - tClosest)^2 around the closest approach.
  const double dxy = d.x * d.x + d.y * d.y;
  const double outer = Grid.radius.back();
  double tClosest = 0.0, closestDistance = std::sqrt(p.x * p.x + p.y * p.y);
  if (dxy > 0.0)
  {
    tClosest = -(p.x * d.x + p.y * d.y) / dxy;
    closestDistance = std::hypot(p.x + tClosest * d.x, p.y + tClosest * d.y);
    if (closestDistance >= outer)
      return false;
    const double half = std::sqrt((outer - closestDistance) * (outer + closestDistance) / dxy);
    tmin = std::max(tmin, tClosest - half);
    tmax = std::min(tmax, tClosest + half);
  }
  else if (closestDistance >= outer)
    return false;
  if (!(tmin < tmax))
    return false;
  const dvec3 start = p + tmin * d, end = p + tmax * d;

  traversal::CrossingScratch& scratch = traversal::threadCrossingScratch();
  traversal::TransitionList& radial = scratch.lists[0];
  traversal::TransitionList& heights = scratch.lists[1];

  int radialStart;
  if (dxy > 0.0)
    radialStart = traversal::radialTransitions(Grid.radius, RadiusSquared, tClosest, closestDistance, dxy,
      tmin, tmax, start.x * start.x + start.y * start.y, end.x * end.x + end.y * end.y, radial,
      scratch.halfChords);
  else // parallel to the axis: rho is constant
  {
    radial.reset(1);
    radialStart = int(std::upper_bound(RadiusSquared.begin(), RadiusSquared.end(),
                        closestDistance * closestDistance) - RadiusSquared.begin()) - 1;
  }

  // Height: linear in t. A start on a plane belongs to the cell the ray moves into.
  const int nz = Grid.heightCells();
  int heightStart;
  if (d.z >= 0.0)
    heightStart = int(std::upper_bound(Grid.height.begin(), Grid.height.end(), start.z) - Grid.height.begin()) - 1;
  else
    heightStart = int(std::lower_bound(Grid.height.begin(), Grid.height.end(), start.z) - Grid.height.begin()) - 1;
  heightStart = std::clamp(heightStart, 0, nz - 1);
  heights.reset(std::size_t(nz) + 1);
  if (d.z > 0.0)
    for (int k = heightStart + 1; k < nz; ++k)
    {
      const double t = (Grid.height[std::size_t(k)] - p.z) / d.z;
      if (t >= tmax)
        break;
      heights.push({ t, k });
    }
  else if (d.z < 0.0)
    for (int k = heightStart; k >= 1; --k)
    {
      const double t = (Grid.height[std::size_t(k)] - p.z) / d.z;
      if (t >= tmax)
        break;
      heights.push({ t, k - 1 });
    }
  traversal::clampAscending(heights, tmin, tmax);

  const int azimuthStart = Azimuth->transitions(p, d, tmin, tmax, start, end, scratch.lists[2]);

  const int first[3] = { radialStart, heightStart, azimuthStart };
  const int counts[3] = { Grid.radialCells(), nz, Grid.azimuthalCells() };
  traversal::sealCrossings(first, scratch.lists, counts, tmin, tmax, crossed);
  return true;
}

double projectCellConstant(const CylindricalGrid& grid, const std::vector<double>& values,
  const std::vector<CellSegment>& segments, double directionLength)
{
  if (values.size() != grid.cellCount())
    throw std::invalid_argument("sightline::projectCellConstant: " + std::to_string(values.size()) +
      " values for " + std::to_string(grid.cellCount()) + " cylindrical cells");
  double sum = 0.0;
  for (const CellSegment& s : segments)
    sum += values[grid.cellIndex(s.r, s.phi, s.theta)] * (s.t1 - s.t0);
  return sum * directionLength;
}
} // namespace sightline
