// SPDX-License-Identifier: BSD-3-Clause
// The spherical-grid scenes, after the thesis' Chapter 6 (Figures 6.11-6.14): projection
// integrals (value x length summed along each ray, yt's ProjectionSampler) of analytic fields
// sampled on grids of N breakpoints per axis, N = 8..256, each ray's error against the exact
// integral, and the frame time, for the native traversal and for Cartesian resampling.
// - "spherical-step": the thesis' chi_0.5 (2 for r <= 1/2, 1 out to r = 1);
// - "spherical-step-aligned": the same with N cells per axis, so that the step is a breakpoint
//   (the grid's cells hold the field exactly: a layered model on its own grid);
// - "spherical-r2": r^2 inside the unit ball.
// Rays are orthographic and parallel to x, over a W x H pixel grid covering [-1, 1]^2 in
// (y, z): aligned with the Cartesian axes, which favours the Cartesian methods, as the thesis
// does. The spherical grids are uniform with N breakpoints per axis (N - 1 cells), so the step
// at r = 1/2 falls in the middle of a cell, as in the thesis. Methods:
// - analytic (reference): the exact integrals from sphere chords (SphericalFields.h);
// - sightline-spherical: SphericalTraversal + cell-constant projection of cell-midpoint values;
// - sightline-spherical-linear-r2 (r2 scene only): the linear-in-r^2 sampler on radial nodes,
//   exact for this field by construction (shown to say what interpolation buys, not as a fair
//   comparison);
// - cartesian-resampled: the spherical cells resampled to an N^3 image over [-1, 1]^3 (each
//   voxel takes the value of the spherical cell holding its centre, 0 outside the ball, what
//   vtkResampleToImage does with cell data), then an exact voxel traversal (Amanatides-Woo,
//   value x length in each voxel: the same sampler on the Cartesian grid, as many samples as
//   voxels crossed). Resampling is reported as build time, not charged to the frame (thesis
//   6.3);
// - cartesian-exact-samples: the same marcher on an N^3 image of the analytic field sampled at
//   voxel centres: the Cartesian grid at its best, with no resampling loss.
// Run with a small image: sightline-benchmark --scene spherical-step --width 256 --height 256.
#include "SceneRegistry.h"

#include "sightline/volumes/SphericalFields.h"
#include "sightline/volumes/SphericalGrid.h"

#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

namespace sightline_benchmark
{
namespace
{
using sightline::dvec3;
using sightline::SphericalGrid;

using sightline::kPi;

enum class Field
{
  Step,
  RadiusSquared
};

double fieldAt(Field field, double r)
{
  if (field == Field::Step)
    return sightline::RadialStepField::chiHalf()(r);
  return r <= 1.0 ? r * r : 0.0;
}

double exactIntegral(Field field, const dvec3& o, const dvec3& d, double t0, double t1)
{
  if (field == Field::Step)
    return sightline::RadialStepField::chiHalf().rayIntegral(o, d, t0, t1);
  return sightline::RadiusSquaredField{ 1.0 }.rayIntegral(o, d, t0, t1);
}

SphericalGrid uniformGrid(int breakpoints)
{
  SphericalGrid grid;
  for (int i = 0; i < breakpoints; ++i)
  {
    const double s = double(i) / (breakpoints - 1);
    grid.radius.push_back(s);
    grid.polar.push_back(kPi * s);
    grid.azimuth.push_back(2.0 * kPi * s);
  }
  return grid;
}

/// The rays: origin (-2, y, z), direction +x, t in [0, 4], one per pixel centre.
struct RaySet
{
  int width, height;
  dvec3 origin(int x, int y) const
  {
    return dvec3(-2.0, (x + 0.5) / width * 2.0 - 1.0, (y + 0.5) / height * 2.0 - 1.0);
  }
};

/// Integrates every ray with `integrate(origin, direction)` into `out` (row-major), in parallel,
/// in tiles of 16 x 16 rays as a renderer traces them: neighbouring rays read neighbouring cells
/// while they are still cached.
void integrateAll(const RaySet& rays, std::vector<double>& out,
  const std::function<double(const dvec3&, const dvec3&)>& integrate)
{
  out.resize(std::size_t(rays.width) * rays.height);
  tbb::parallel_for(tbb::blocked_range2d<int>(0, rays.height, 16, 0, rays.width, 16),
    [&](const tbb::blocked_range2d<int>& tile)
    {
      for (int y = tile.rows().begin(); y < tile.rows().end(); ++y)
        for (int x = tile.cols().begin(); x < tile.cols().end(); ++x)
          out[std::size_t(y) * rays.width + x] = integrate(rays.origin(x, y), dvec3(1.0, 0.0, 0.0));
    },
    tbb::simple_partitioner());
}

/// An N^3 image over [-1, 1]^3 and an exact voxel traversal of it (Amanatides and Woo 1987):
/// each voxel a ray crosses adds its value times the length inside it.
class CartesianImage
{
public:
  explicit CartesianImage(int n) : N(n), Size(2.0 / n), Values(std::size_t(n) * n * n, 0.0) {}

  dvec3 voxelCentre(int i, int j, int k) const
  {
    return dvec3(-1.0 + (i + 0.5) * Size, -1.0 + (j + 0.5) * Size, -1.0 + (k + 0.5) * Size);
  }
  double& at(int i, int j, int k) { return Values[std::size_t(i) + std::size_t(N) * (std::size_t(j) + std::size_t(N) * k)]; }
  double at(int i, int j, int k) const { return Values[std::size_t(i) + std::size_t(N) * (std::size_t(j) + std::size_t(N) * k)]; }

  double project(const dvec3& o, const dvec3& d, double t0, double t1) const
  {
    // Clip to the image's box.
    for (int axis = 0; axis < 3; ++axis)
    {
      if (d[axis] == 0.0)
      {
        if (o[axis] < -1.0 || o[axis] >= 1.0)
          return 0.0;
        continue;
      }
      double a = (-1.0 - o[axis]) / d[axis], b = (1.0 - o[axis]) / d[axis];
      if (a > b)
        std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
    if (!(t0 < t1))
      return 0.0;
    const dvec3 start = o + t0 * d;
    int cell[3], step[3];
    double next[3], delta[3];
    for (int axis = 0; axis < 3; ++axis)
    {
      cell[axis] = std::clamp(int(std::floor((start[axis] + 1.0) / Size)), 0, N - 1);
      if (d[axis] > 0.0)
      {
        step[axis] = 1;
        next[axis] = t0 + (-1.0 + (cell[axis] + 1) * Size - start[axis]) / d[axis];
        delta[axis] = Size / d[axis];
      }
      else if (d[axis] < 0.0)
      {
        step[axis] = -1;
        next[axis] = t0 + (-1.0 + cell[axis] * Size - start[axis]) / d[axis];
        delta[axis] = -Size / d[axis];
      }
      else
      {
        step[axis] = 0;
        next[axis] = delta[axis] = std::numeric_limits<double>::infinity();
      }
    }
    double sum = 0.0, t = t0;
    while (t < t1)
    {
      const int axis = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
      const double leave = std::min(next[axis], t1);
      sum += at(cell[0], cell[1], cell[2]) * (leave - t);
      t = leave;
      cell[axis] += step[axis];
      if (cell[axis] < 0 || cell[axis] >= N)
        break;
      next[axis] += delta[axis];
    }
    return sum * glm::length(d);
  }

  std::size_t bytes() const { return Values.size() * sizeof(double); }

private:
  int N;
  double Size;
  std::vector<double> Values;
};

struct ErrorNorms
{
  double rms = 0.0, max = 0.0, meanExact = 0.0;
};

ErrorNorms errorNorms(const std::vector<double>& ours, const std::vector<double>& exact)
{
  ErrorNorms e;
  for (std::size_t i = 0; i < ours.size(); ++i)
  {
    const double diff = std::abs(ours[i] - exact[i]);
    e.rms += diff * diff;
    e.max = std::max(e.max, diff);
    e.meanExact += exact[i];
  }
  e.rms = std::sqrt(e.rms / ours.size());
  e.meanExact /= ours.size();
  return e;
}

/// A grey image of the integrals (scaled by `scale`), so the harness can write and compare
/// PNGs: white is `scale`.
Image integralImage(const RaySet& rays, const std::vector<double>& values, double scale)
{
  Image image;
  image.width = rays.width;
  image.height = rays.height;
  image.rgb.resize(image.pixelCount() * 3);
  image.depth.assign(image.pixelCount(), 1.0f);
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    const auto grey = std::uint8_t(std::clamp(std::lround(255.0 * values[i] / scale), 0L, 255L));
    std::fill_n(&image.rgb[3 * i], 3, grey);
    if (values[i] != 0.0)
      image.depth[i] = 0.5f;
  }
  return image;
}

/// `aligned`: N cells (N + 1 breakpoints) per axis instead of N breakpoints, so for even N the
/// step at r = 1/2 is a breakpoint: the grid's cells then hold the field exactly, as a
/// simulation's cells hold its data.
std::vector<MethodResult> runSphericalScene(
  Field field, bool aligned, const Options& options, long long count)
{
  const int n = int(count);
  if (n < 2)
    throw std::invalid_argument("spherical scenes need at least 2 breakpoints per axis");
  const RaySet rays{ options.width, options.height };
  const int runs = std::max(1, options.runs);
  std::vector<MethodResult> results;
  auto makeResult = [&](const std::string& method)
  {
    MethodResult r;
    r.method = method;
    r.primitives = count;
    r.width = rays.width;
    r.height = rays.height;
    return r;
  };

  // Exact integrals: the reference.
  std::vector<double> exact;
  MethodResult analytic = makeResult("analytic");
  analytic.isReference = true;
  analytic.frame = timeFrames(runs,
    [&] { integrateAll(rays, exact, [&](const dvec3& o, const dvec3& d) { return exactIntegral(field, o, d, 0.0, 4.0); }); });
  const double scale = *std::max_element(exact.begin(), exact.end());
  analytic.image = integralImage(rays, exact, scale);
  analytic.integralRmsError = analytic.integralMaxError = 0.0;
  analytic.notes = "sphere chords; mean exact integral " + std::to_string(errorNorms(exact, exact).meanExact);
  results.push_back(std::move(analytic));

  auto finish = [&](MethodResult& r, const std::vector<double>& values)
  {
    const ErrorNorms e = errorNorms(values, exact);
    r.integralRmsError = e.rms;
    r.integralMaxError = e.max;
    r.image = integralImage(rays, values, scale);
  };

  // Native spherical traversal.
  const SphericalGrid grid = uniformGrid(aligned ? n + 1 : n);
  const sightline::SphericalTraversal traversal(grid);
  std::vector<double> cells;
  MethodResult spherical = makeResult("sightline-spherical");
  spherical.buildSeconds = timeOnce(
    [&] { cells = sightline::sampleCellMidpoints(grid, [&](double r, double, double) { return fieldAt(field, r); }); });
  spherical.memoryBytes = double(cells.size() * sizeof(double));
  std::vector<double> values;
  spherical.frame = timeFrames(runs,
    [&]
    {
      integrateAll(rays, values,
        [&](const dvec3& o, const dvec3& d)
        {
          return sightline::projectCellConstant(traversal, cells, o, d, 0.0, 4.0);
        });
    });
  finish(spherical, values);
  spherical.notes = std::to_string(grid.cellCount()) + " cells, cell-midpoint values";
  results.push_back(std::move(spherical));

  if (field == Field::RadiusSquared)
  {
    MethodResult linear = makeResult("sightline-spherical-linear-r2");
    std::vector<double> nodes;
    linear.buildSeconds = timeOnce(
      [&] { nodes = sightline::sampleRadialNodes(grid, [&](double r, double, double) { return fieldAt(field, r); }); });
    linear.memoryBytes = double(nodes.size() * sizeof(double));
    linear.frame = timeFrames(runs,
      [&]
      {
        integrateAll(rays, values,
          [&](const dvec3& o, const dvec3& d)
          {
            return sightline::projectLinearInRadiusSquared(traversal, nodes, o, d, 0.0, 4.0);
          });
      });
    finish(linear, values);
    linear.notes = "values at radial nodes, linear in r^2: exact for this field by construction";
    results.push_back(std::move(linear));
  }

  // Cartesian: resampled from the spherical cells, and sampled from the field itself.
  for (const bool fromGrid : { true, false })
  {
    MethodResult cartesian = makeResult(fromGrid ? "cartesian-resampled" : "cartesian-exact-samples");
    const double voxels = double(n) * n * n;
    if (voxels * sizeof(double) > 4.0 * (1ull << 30))
    {
      cartesian.skipped = true;
      cartesian.notes = "N^3 image over 4 GiB";
      results.push_back(std::move(cartesian));
      continue;
    }
    CartesianImage image(n);
    cartesian.buildSeconds = timeOnce(
      [&]
      {
        tbb::parallel_for(0, n,
          [&](int k)
          {
            for (int j = 0; j < n; ++j)
              for (int i = 0; i < n; ++i)
              {
                const dvec3 c = image.voxelCentre(i, j, k);
                const double r = glm::length(c);
                double value = 0.0;
                if (!fromGrid)
                  value = fieldAt(field, r);
                else if (r <= grid.radius.back())
                {
                  // The spherical cell holding the voxel centre.
                  const double theta = r > 0.0 ? std::acos(std::clamp(c.z / r, -1.0, 1.0)) : 0.0;
                  double phi = std::atan2(c.y, c.x);
                  if (phi < 0.0)
                    phi += 2.0 * kPi;
                  auto index = [](const std::vector<double>& b, double v)
                  {
                    const int cellCount = int(b.size()) - 1;
                    return std::clamp(int(std::upper_bound(b.begin(), b.end(), v) - b.begin()) - 1, 0, cellCount - 1);
                  };
                  value = cells[grid.cellIndex(index(grid.radius, r), index(grid.polar, theta), index(grid.azimuth, phi))];
                }
                image.at(i, j, k) = value;
              }
          });
      });
    cartesian.memoryBytes = double(image.bytes());
    cartesian.frame = timeFrames(runs,
      [&] { integrateAll(rays, values, [&](const dvec3& o, const dvec3& d) { return image.project(o, d, 0.0, 4.0); }); });
    finish(cartesian, values);
    std::ostringstream notes;
    notes << n << "^3 voxels" << (fromGrid ? ", resampled from the spherical cells (build = resampling)"
                                           : ", the field sampled at voxel centres");
    cartesian.notes = notes.str();
    results.push_back(std::move(cartesian));
  }
  for (const MethodResult& r : results)
  {
    std::ostringstream line;
    line << "N = " << n << ": " << r.method;
    if (!r.skipped)
      line << ": frame " << r.frame.medianSeconds << " s, integral error RMS " << r.integralRmsError
           << ", max " << r.integralMaxError;
    logProgress(line.str());
  }
  return results;
}

const SceneRegistration stepRegistration{ "spherical-step",
  "projection integrals of the thesis' chi_0.5 on spherical grids of N breakpoints per axis: "
  "native traversal against Cartesian resampling, error against the exact integrals "
  "(use --width 256 --height 256)",
  { 8, 16, 32, 64, 128, 256 },
  [](const Options& options, long long count, MachineDescription&)
  { return runSphericalScene(Field::Step, false, options, count); } };

const SceneRegistration alignedStepRegistration{ "spherical-step-aligned",
  "as spherical-step with N cells per axis, so that the step at r = 1/2 is a grid breakpoint "
  "(the cells hold the field exactly, as a layered model's cells do; use --width 256 --height 256)",
  { 8, 16, 32, 64, 128, 256 },
  [](const Options& options, long long count, MachineDescription&)
  { return runSphericalScene(Field::Step, true, options, count); } };

const SceneRegistration radiusSquaredRegistration{ "spherical-r2",
  "projection integrals of r^2 in the unit ball on spherical grids of N breakpoints per axis: "
  "native traversal against Cartesian resampling, error against the exact integrals "
  "(use --width 256 --height 256)",
  { 8, 16, 32, 64, 128, 256 },
  [](const Options& options, long long count, MachineDescription&)
  { return runSphericalScene(Field::RadiusSquared, false, options, count); } };
} // namespace
} // namespace sightline_benchmark
