// SPDX-License-Identifier: BSD-3-Clause
// Spherical and cylindrical volumes cut into regions, as MPI ranks draw them under ordered
// compositing: each region holds only the cells cellRangeInBox gives for its box, every ray is
// clipped to the region (SphericalVolumeOptions::regionLower/Upper), and the regions' images
// blended front to back in ray order must be the image of the whole grid.
#include "sightline/volumes/SphericalVolume.h"

#include "RegionBlend.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

using namespace sightline;

namespace
{
constexpr double inf = std::numeric_limits<double>::infinity();

// Index of the cell between breakpoints b that holds x, or -1 outside.
int cellOf(const std::vector<double>& b, double x)
{
  if (x < b.front() || x > b.back())
    return -1;
  const auto it = std::upper_bound(b.begin(), b.end(), x);
  return std::min(int(it - b.begin()) - 1, int(b.size()) - 2);
}

// The azimuth cell of phi, trying every turn.
int azimuthCellOf(const std::vector<double>& b, double phi)
{
  for (int turn = -2; turn <= 2; ++turn)
  {
    const int cell = cellOf(b, phi + turn * 2.0 * kPi);
    if (cell >= 0)
      return cell;
  }
  return -1;
}

// A non-uniform full ball from phi = -pi (a seam on -x) and a shell wedge across +x.
std::vector<SphericalGrid> sphericalSections()
{
  return { { { 0.0, 0.15, 0.4, 0.55, 0.8, 1.0 }, { 0.0, 0.3, 0.9, kPi / 2, 2.2, 2.7, kPi },
             { -kPi, -2.5, -1.2, -0.3, 0.4, 1.5, 2.6, kPi } },
    { { 0.3, 0.5, 0.7, 1.0 }, { 0.4, 1.0, 1.6, 2.5 }, { -0.9, -0.2, 0.3, 1.1 } } };
}

template <class Grid>
bool rangeInBox(const Grid& grid, const dvec3& lower, const dvec3& upper, std::array<int, 6>& range)
{
  int first[3], last[3];
  if (!cellRangeInBox(grid, lower, upper, first, last))
    return false;
  range = { first[0], last[0], first[1], last[1], first[2], last[2] };
  return true;
}

// The cells of an inclusive index range of n cells, in order; first > last runs across the
// seam of a full circle (first..n-1, then 0..last).
std::vector<int> cellsOfRun(int first, int last, int n)
{
  std::vector<int> cells;
  for (int k = first; k != last + 1; k = (k + 1) % (n + 1))
    if (k < n)
      cells.push_back(k);
  return cells;
}
bool inRun(int k, int first, int last)
{
  return first <= last ? k >= first && k <= last : k >= first || k <= last;
}

// The breakpoints of a run of cells; across a full circle's seam the angles go on past 2 pi.
std::vector<double> slice(const std::vector<double>& b, int first, int last)
{
  std::vector<double> out;
  for (int k : cellsOfRun(first, last, int(b.size()) - 1))
  {
    const double turn = first > last && k <= last ? 2.0 * kPi : 0.0;
    if (out.empty())
      out.push_back(b[std::size_t(k)] + turn);
    out.push_back(b[std::size_t(k) + 1] + turn);
  }
  return out;
}

// The cells of `range` as a grid of their own, with their values.
SphericalGrid subGrid(const SphericalGrid& grid, const std::array<int, 6>& range)
{
  return { slice(grid.radius, range[0], range[1]), slice(grid.polar, range[2], range[3]),
    slice(grid.azimuth, range[4], range[5]) };
}
CylindricalGrid subGrid(const CylindricalGrid& grid, const std::array<int, 6>& range)
{
  return { slice(grid.radius, range[0], range[1]), slice(grid.azimuth, range[2], range[3]),
    slice(grid.height, range[4], range[5]) };
}
int cellCount(const std::array<int, 6>& range, const std::array<int, 3>& cells)
{
  int count = 1;
  for (int axis = 0; axis < 3; ++axis)
    count *= int(cellsOfRun(range[2 * axis], range[2 * axis + 1], cells[std::size_t(axis)]).size());
  return count;
}
template <class Grid, class T>
std::vector<T> subValues(const Grid& grid, const std::vector<T>& values, const std::array<int, 6>& range,
  const std::array<int, 3>& cells)
{
  std::vector<T> out;
  for (int k : cellsOfRun(range[4], range[5], cells[2]))
    for (int j : cellsOfRun(range[2], range[3], cells[1]))
      for (int i : cellsOfRun(range[0], range[1], cells[0]))
        out.push_back(values[grid.cellIndex(i, j, k)]);
  return out;
}
std::array<int, 3> cellsOf(const SphericalGrid& grid)
{
  return { grid.radialCells(), grid.polarCells(), grid.azimuthalCells() };
}
std::array<int, 3> cellsOf(const CylindricalGrid& grid)
{
  return { grid.radialCells(), grid.azimuthalCells(), grid.heightCells() };
}

// Eight octants around a point off the centre, outer faces infinite.
std::vector<std::array<dvec3, 2>> octants(const dvec3& cut)
{
  std::vector<std::array<dvec3, 2>> regions;
  for (int i = 0; i < 8; ++i)
  {
    dvec3 lower, upper;
    for (int axis = 0; axis < 3; ++axis)
    {
      const bool above = (i >> axis) & 1;
      lower[axis] = above ? cut[axis] : -inf;
      upper[axis] = above ? inf : cut[axis];
    }
    regions.push_back({ lower, upper });
  }
  return regions;
}

// The finite box of a region that the grid can reach (the grid lies within |x| <= reach).
std::array<dvec3, 2> finite(const std::array<dvec3, 2>& region, double reach)
{
  return { glm::max(region[0], dvec3(-reach)), glm::min(region[1], dvec3(reach)) };
}
} // namespace

TEST(VolumeRegions, CellRangeInBoxHoldsTheCellOfEveryPointInTheBox)
{
  std::mt19937 random(17);
  std::uniform_real_distribution<double> coordinate(-1.1, 1.1), size(0.0, 0.8), unit(0.0, 1.0);
  const CylindricalGrid cylinder{ { 0.0, 0.2, 0.6, 1.0 }, { -kPi, -1.0, 0.5, 2.0, kPi }, { -1.0, -0.2, 0.3, 1.0 } };
  int tight = 0, seamRuns = 0;
  for (int trial = 0; trial < 300; ++trial)
  {
    dvec3 lower(coordinate(random), coordinate(random), coordinate(random));
    dvec3 upper = lower + dvec3(size(random), size(random), size(random));
    if (trial % 10 == 0) // boxes around the z axis, and through the origin
    {
      upper.x = std::abs(upper.x) + 0.01;
      lower.x = -upper.x;
    }
    if (trial % 7 == 3) // boxes with a face on the axis, as a partition's halves have
    {
      lower.x = 0.0;
      upper.x = std::max(upper.x, 0.1);
    }
    if (trial % 11 == 5)
    {
      lower.y = std::min(lower.y, -0.1);
      upper.y = 0.0;
    }
    if (trial % 20 == 0)
    {
      upper.z = std::abs(upper.z) + 0.01;
      lower.z = -0.5 * upper.z;
    }
    // Boxes on -x across y = 0, off the axis: across the ball's seam (at -pi) without holding
    // the axis, so the ball's range must be a run across the seam, not every azimuth.
    const bool acrossSeam = trial % 9 == 4;
    if (acrossSeam)
    {
      upper.x = -0.05 - 0.5 * unit(random);
      lower.x = std::min(lower.x, upper.x - 0.1);
      lower.y = -0.05 - 0.5 * unit(random);
      upper.y = 0.05 + 0.5 * unit(random);
    }
    for (const SphericalGrid& grid : sphericalSections())
    {
      std::array<int, 6> range{};
      const bool any = rangeInBox(grid, lower, upper, range);
      for (int s = 0; s < 400; ++s)
      {
        const dvec3 x = lower + dvec3(unit(random), unit(random), unit(random)) * (upper - lower);
        const double r = glm::length(x);
        const int i = cellOf(grid.radius, r);
        const int j = r > 0.0 ? cellOf(grid.polar, std::acos(std::clamp(x.z / r, -1.0, 1.0))) : 0;
        const int k = azimuthCellOf(grid.azimuth, std::atan2(x.y, x.x));
        if (i < 0 || j < 0 || k < 0)
          continue; // outside the section
        ASSERT_TRUE(any) << "trial " << trial << ": no cells for a box holding cell " << i << " " << j << " " << k;
        EXPECT_TRUE(i >= range[0] && i <= range[1] && j >= range[2] && j <= range[3] && inRun(k, range[4], range[5]))
          << "trial " << trial << ": cell " << i << " " << j << " " << k << " outside the range";
      }
      if (any && cellCount(range, cellsOf(grid)) < int(grid.cellCount()) / 2)
        ++tight;
      seamRuns += any && range[4] > range[5];
      if (acrossSeam && grid.fullCircle() && any)
      {
        EXPECT_GT(range[4], range[5]) << "trial " << trial << ": a box across the seam takes every azimuth";
      }
    }
    std::array<int, 6> range{};
    const bool any = rangeInBox(cylinder, lower, upper, range);
    for (int s = 0; s < 400; ++s)
    {
      const dvec3 x = lower + dvec3(unit(random), unit(random), unit(random)) * (upper - lower);
      const int i = cellOf(cylinder.radius, std::hypot(x.x, x.y));
      const int j = azimuthCellOf(cylinder.azimuth, std::atan2(x.y, x.x));
      const int k = cellOf(cylinder.height, x.z);
      if (i < 0 || j < 0 || k < 0)
        continue;
      ASSERT_TRUE(any) << "trial " << trial << ": no cylindrical cells for a box holding one";
      EXPECT_TRUE(i >= range[0] && i <= range[1] && inRun(j, range[2], range[3]) && k >= range[4] && k <= range[5])
        << "trial " << trial << ": cylindrical cell " << i << " " << j << " " << k << " outside the range";
    }
  }
  // Not every box gets every cell: the ranges are what makes a rank's piece smaller.
  EXPECT_GT(tight, 100);
  std::printf("%d of 600 spherical boxes hold under half the cells, %d take a run across the seam\n", tight, seamRuns);
  // The half x <= 0 of a ball, a face on the axis: only the azimuths in [pi/2, 3pi/2], not the
  // cell that merely touches the face at -pi/2 (the seam of this grid, at -pi, is inside).
  {
    const SphericalGrid ball = sphericalSections()[0];
    std::array<int, 6> range{};
    ASSERT_TRUE(rangeInBox(ball, dvec3(-1.0), dvec3(0.0, 1.0, 1.0), range));
    const SphericalGrid wedge{ ball.radius, ball.polar, { 0.0, 0.5 * kPi, kPi, 1.5 * kPi } };
    ASSERT_TRUE(rangeInBox(wedge, dvec3(0.0, -1.0, -1.0), dvec3(1.0), range));
    EXPECT_EQ(range[4], 0); // x >= 0 holds [0, pi/2]; the cell [pi, 3pi/2] only touches x = 0
    EXPECT_EQ(range[5], 0);
    ASSERT_TRUE(rangeInBox(wedge, dvec3(-1.0), dvec3(0.0, 1.0, 1.0), range));
    EXPECT_EQ(range[4], 1);
    EXPECT_EQ(range[5], 2);
    // The half x <= -0.1 of the ball spans azimuths ~95 to ~265 degrees, across its seam at
    // -pi: the cells [1.5, 2.6], [2.6, pi], [-pi, -2.5], [-2.5, -1.2], as the run 5..1.
    ASSERT_TRUE(rangeInBox(ball, dvec3(-1.0), dvec3(-0.1, 1.0, 1.0), range));
    EXPECT_EQ(range[4], 5);
    EXPECT_EQ(range[5], 1);
    // The same across a wedge's ends: they are not neighbours, so every cell.
    const SphericalGrid open{ ball.radius, ball.polar, { -3.0, -1.2, 0.0, 1.5, 3.0 } };
    ASSERT_TRUE(rangeInBox(open, dvec3(-1.0), dvec3(-0.1, 1.0, 1.0), range));
    EXPECT_EQ(range[4], 0);
    EXPECT_EQ(range[5], 3);
  }
  // A box beyond the outer shell, and a NaN box, meet no cell.
  int first[3], last[3];
  EXPECT_FALSE(cellRangeInBox(sphericalSections()[0], dvec3(1.2), dvec3(2.0), first, last));
  EXPECT_FALSE(cellRangeInBox(sphericalSections()[0], dvec3(std::nan("")), dvec3(2.0), first, last));
}

TEST(VolumeRegions, SubGridImagesBlendedInVisibilityOrderGiveTheWholeImage)
{
  // Each octant renders only the cells of its box's range, clipped to the octant; blended in
  // ray order the eight images are the whole grid's image: emission-absorption multiplies
  // along a ray, and a cell cut by a face contributes its two parts exactly.
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Two cuts: one whose octants either hold the z axis or stay off the seam (at -pi), one
  // whose octant below x = -0.3 runs across the seam (its cells wrap, first > last).
  for (const dvec3& cut : { dvec3(0.13, -0.21, 0.05), dvec3(-0.3, 0.1, 0.05) })
  {
  const auto regions = octants(cut);
  int seamRuns = 0;
  for (const SphericalGrid& grid : sphericalSections())
  {
    std::vector<TransferSample> cells(grid.cellCount());
    for (TransferSample& cell : cells) // structure in every cell, a few empty ones
    {
      cell.color = vec3(float(unit(random)), float(unit(random)), float(unit(random)));
      cell.extinction = unit(random) < 0.15 ? 0.0 : 3.0 * unit(random);
    }
    const SphericalTraversal whole(grid);
    for (const dvec3& position : { dvec3(2.0, 3.0, 2.5), dvec3(-3.0, -1.0, -2.0), dvec3(cut.x, 0.4, 4.0) })
    {
      CameraParameters parameters;
      parameters.position = position;
      parameters.focalPoint = dvec3(position.x == cut.x ? cut.x : 0.0, 0.0, 0.0);
      parameters.viewAngle = 35.0;
      const Camera camera = Camera::fromParameters(parameters, 49, 48); // odd: a column in x = cut.x
      SphericalVolumeOptions options;
      options.minimumTransmittance = 0.0; // early termination would end the parts at other depths
      Framebuffer wholeImage;
      renderSphericalVolume(whole, cells, camera, wholeImage, options);
      std::vector<Framebuffer> parts(regions.size());
      std::size_t heldCells = 0;
      for (std::size_t r = 0; r < regions.size(); ++r)
      {
        const auto box = finite(regions[r], 1.01);
        std::array<int, 6> range{};
        if (!rangeInBox(grid, box[0], box[1], range))
        {
          parts[r].resize(camera.width(), camera.height());
          continue;
        }
        seamRuns += range[4] > range[5];
        const SphericalTraversal piece(subGrid(grid, range));
        const std::vector<TransferSample> pieceCells = subValues(grid, cells, range, cellsOf(grid));
        heldCells += pieceCells.size();
        options.regionLower = regions[r][0];
        options.regionUpper = regions[r][1];
        renderSphericalVolume(piece, pieceCells, camera, parts[r], options);
      }
      int covered, split;
      sightline_test::expectRegionBlendIsWhole(regions, parts, wholeImage, camera, 2e-5f, 2e-5f, covered, split);
      std::printf("spherical section of %zu cells, camera at (%g, %g, %g): the octants hold %zu cells; %d covered "
                  "pixels, %d with layers in several octants\n",
        grid.cellCount(), position.x, position.y, position.z, heldCells, covered, split);
      EXPECT_GT(covered, 300);
      EXPECT_GT(split, 100);
    }
  }

  // A cylindrical grid the same way, and point data interpolated inside the cells (the sample
  // points of a cut segment move, so the tolerance is the midpoint rule's, 1e-3 at this distance).
  const CylindricalGrid cylinder{ { 0.0, 0.2, 0.6, 1.0 }, { -kPi, -1.0, 0.5, 2.0, kPi }, { -1.0, -0.2, 0.3, 1.0 } };
  std::vector<TransferSample> cells(cylinder.cellCount());
  for (TransferSample& cell : cells)
  {
    cell.color = vec3(float(unit(random)), float(unit(random)), float(unit(random)));
    cell.extinction = 3.0 * unit(random);
  }
  const SphericalGrid ball = sphericalSections()[0];
  std::vector<double> points;
  for (double phi : ball.azimuth)
    for (double theta : ball.polar)
      for (double r : ball.radius)
        points.push_back(r * (1.2 + std::sin(theta) * std::cos(phi)));
  TransferTable transfer;
  transfer.minimum = 0.0;
  transfer.maximum = 2.2;
  transfer.entries = { TransferSample{ vec3(0.1f, 0.2f, 0.9f), 0.0 }, TransferSample{ vec3(1.0f, 0.6f, 0.1f), 4.0 } };
  CameraParameters parameters;
  parameters.position = dvec3(2.5, -3.0, 1.5);
  parameters.focalPoint = dvec3(0.0);
  parameters.viewAngle = 35.0;
  const Camera camera = Camera::fromParameters(parameters, 48, 48);
  SphericalVolumeOptions options;
  options.minimumTransmittance = 0.0;
  Framebuffer wholeCylinder, wholePoints;
  renderCylindricalVolume(CylindricalTraversal(cylinder), cells, camera, wholeCylinder, options);
  renderSphericalVolumePoints(SphericalTraversal(ball), points, transfer, 0.02, camera, wholePoints, options);
  std::vector<Framebuffer> cylinderParts(regions.size()), pointParts(regions.size());
  for (std::size_t r = 0; r < regions.size(); ++r)
  {
    const auto box = finite(regions[r], 1.01);
    options.regionLower = regions[r][0];
    options.regionUpper = regions[r][1];
    std::array<int, 6> range{};
    cylinderParts[r].resize(camera.width(), camera.height());
    pointParts[r].resize(camera.width(), camera.height());
    if (rangeInBox(cylinder, box[0], box[1], range))
      seamRuns += range[2] > range[3];
    if (rangeInBox(cylinder, box[0], box[1], range))
      renderCylindricalVolume(CylindricalTraversal(subGrid(cylinder, range)), subValues(cylinder, cells, range, cellsOf(cylinder)),
        camera, cylinderParts[r], options);
    if (rangeInBox(ball, box[0], box[1], range))
    {
      // Point values of the cells' corners: the range's points.
      std::vector<double> piecePoints;
      const int nr = ball.radialCells() + 1, nt = ball.polarCells() + 1;
      std::vector<int> azimuthPoints = cellsOfRun(range[4], range[5], ball.azimuthalCells());
      azimuthPoints.push_back(azimuthPoints.back() + 1);
      for (int k : azimuthPoints)
        for (int j = range[2]; j <= range[3] + 1; ++j)
          for (int i = range[0]; i <= range[1] + 1; ++i)
            piecePoints.push_back(points[std::size_t(i + nr * (j + nt * k))]);
      renderSphericalVolumePoints(SphericalTraversal(subGrid(ball, range)), piecePoints, transfer, 0.02, camera,
        pointParts[r], options);
    }
  }
  int covered, split;
  sightline_test::expectRegionBlendIsWhole(regions, cylinderParts, wholeCylinder, camera, 2e-5f, 2e-5f, covered, split);
  std::printf("cylindrical: %d covered pixels, %d with layers in several octants\n", covered, split);
  EXPECT_GT(split, 100);
  sightline_test::expectRegionBlendIsWhole(regions, pointParts, wholePoints, camera, 1e-3f, 1e-3f, covered, split);
  std::printf("spherical point data: %d covered pixels, %d with layers in several octants\n", covered, split);
  EXPECT_GT(split, 100);
  std::printf("cut at (%g, %g, %g): %d octant ranges run across the seam\n", cut.x, cut.y, cut.z, seamRuns);
  if (cut.x < 0.0)
  {
    EXPECT_GT(seamRuns, 0);
  }
  }
}
