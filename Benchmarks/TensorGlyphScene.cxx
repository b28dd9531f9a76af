// SPDX-License-Identifier: BSD-3-Clause
// The tensor glyph scene (Hlawitschka et al., "higher-order tensor glyphs"): a slice of glyphs
// of orders 4, 8 and 12 seen from above, rendered through the kernel's Renderer with one BVH per
// method:
// - exactly (polynomial root finding, Peters et al. 2023) with a converged reference (double,
//   tolerance 1e-10) and the default;
// - by the paper's fixed-step marching inside the bounding sphere, in units of the glyph's
//   radius: its recommendation (step 0.2, final linear interpolation, a third of the step near
//   the centre), the same without centre steps, with 3 bisection steps instead of the
//   interpolation, and finer steps 0.1 to 0.01;
// - by the paper's rejection and bisection with interval arithmetic and with reduced affine
//   arithmetic.
// Data sets: copper's stiffness tensor (Kittel: C11 168.4, C12 121.4, C44 75.4 GPa) in random
// crystal orientations (order 4), and random tensors of orders 8 and 12, a third of them
// "sharpened" so that their lobes touch the centre (the paper's singular case). The marching
// and subdivision methods get the bounding sphere's box, as in the paper. Errors are computed
// against each data set's reference; "sightline" is the exact method the others are timed
// against. Also measured, single-threaded: the cost of one ray-glyph test (hit and miss) per
// method, written to <output>/tensor-glyphs-intersection.csv.
#include "GlyphSceneSupport.h"
#include "SceneRegistry.h"

#include "sightline/glyphs/SHGlyph.h"
#include "sightline/glyphs/SHGlyphSet.h"
#include "sightline/math/SymmetricTensor.h"
#include "sightline/glyphs/TensorGlyph.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>

namespace sightline_benchmark
{
namespace
{
namespace fs = std::filesystem;
using sightline::dvec3;
using sightline::SHGlyphOptions;
using sightline::SHGlyphSet;
using sightline::vec3;

/// Glyphs are scaled so that their longest lobe has this radius (spacing 1).
constexpr double kGlyphRadius = 0.45;

struct Dataset
{
  std::string name;
  std::string description;
  int order = 0;
  std::vector<vec3> centers;
  std::vector<float> coefficients; ///< canonical SH, shCoefficientCount(order) per glyph, scaled
};

std::vector<double> copperFull()
{
  double voigt[36] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      voigt[6 * i + j] = i == j ? 168.4 : 121.4;
  voigt[21] = voigt[28] = voigt[35] = 75.4;
  return sightline::stiffnessFromVoigt(voigt);
}

/// Unique components of bias * (x^2 + y^2 + z^2)^(n/2), the isotropic tensor.
std::vector<double> isotropic(int order, double bias)
{
  auto factorial = [](int n) { double f = 1; for (int i = 2; i <= n; ++i) f *= i; return f; };
  std::vector<double> t(sightline::symmetricTensorComponentCount(order), 0.0);
  for (std::size_t i = 0; i < t.size(); ++i)
  {
    const auto e = sightline::symmetricTensorExponents(order, int(i));
    if (e[0] % 2 || e[1] % 2 || e[2] % 2)
      continue;
    t[i] = bias * factorial(order / 2) / (factorial(e[0] / 2) * factorial(e[1] / 2) * factorial(e[2] / 2)) /
      sightline::symmetricTensorMultiplicity(e[0], e[1], e[2]);
  }
  return t;
}

Dataset makeDataset(const std::string& name, int order, long long count, unsigned seed)
{
  Dataset data;
  data.name = name;
  data.order = order;
  const int side = std::max(1, int(std::lround(std::sqrt(double(count)))));
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const sightline::TensorToSH map(order);
  const int n = sightline::symmetricTensorComponentCount(order);
  const std::vector<double> copper = copperFull();
  int touching = 0;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
    {
      std::vector<double> tensor;
      if (order == 4 && name == "cu4")
      {
        // A random rotation (unit quaternion) of the crystal.
        double q[4] = { normal(rng), normal(rng), normal(rng), normal(rng) };
        const double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        for (double& v : q)
          v /= l;
        const double a = q[0], b = q[1], c = q[2], d = q[3];
        const double r[3][3] = { { a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c) },
          { 2 * (b * c + a * d), a * a - b * b + c * c - d * d, 2 * (c * d - a * b) },
          { 2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d } };
        std::vector<double> turned(81, 0.0);
        for (int i = 0; i < 81; ++i)
        {
          const int idx[4] = { i % 3, (i / 3) % 3, (i / 9) % 3, i / 27 };
          double sum = 0.0;
          for (int j = 0; j < 81; ++j)
          {
            const int jdx[4] = { j % 3, (j / 3) % 3, (j / 9) % 3, j / 27 };
            sum += r[idx[0]][jdx[0]] * r[idx[1]][jdx[1]] * r[idx[2]][jdx[2]] * r[idx[3]][jdx[3]] * copper[j];
          }
          turned[i] = sum;
        }
        tensor = sightline::symmetricPartFromFull(4, turned.data());
      }
      else
      {
        // Random tensors; every third is sharpened: part of its isotropic mean removed so that
        // its lobes pinch towards the centre.
        tensor.resize(n);
        for (double& v : tensor)
          v = normal(rng);
        const bool sharpened = (x + y) % 3 == 0;
        touching += sharpened;
        const std::vector<double> iso = isotropic(order, sharpened ? 0.0 : 1.5 * std::abs(normal(rng)));
        for (int i = 0; i < n; ++i)
          tensor[i] += iso[i];
      }
      std::vector<double> sh(n);
      map.apply(tensor.data(), sh.data());
      const double largest = sightline::shGlyphMaxRadius(order, sh.data());
      for (double v : sh)
        data.coefficients.push_back(float(v * kGlyphRadius / largest));
      data.centers.emplace_back(float(x), float(y), 0.0f);
    }
  std::ostringstream what;
  if (name == "cu4")
    what << "copper stiffness (Kittel), " << side * side << " random crystal orientations, order 4";
  else
    what << side * side << " random symmetric tensors of order " << order << ", " << touching
         << " sharpened to touch the centre";
  data.description = what.str();
  return data;
}

std::shared_ptr<SHGlyphSet> makeGlyphs(const Dataset& data, SHGlyphOptions options)
{
  options.convention = sightline::SHConvention{ sightline::SHBasis::Canonical, false };
  auto glyphs = std::make_shared<SHGlyphSet>(data.centers, data.coefficients, data.order, options);
  glyphs->material = glyphMaterial();
  return glyphs;
}

struct Method
{
  std::string name;
  SHGlyphOptions options;
  std::string what;
};

std::vector<Method> methods(const Options& options)
{
  std::vector<Method> list;
  SHGlyphOptions reference;
  reference.precision = sightline::SHPrecision::Double;
  reference.tolerance = 1e-10;
  list.push_back({ "reference", reference, "reference: exact, double, tolerance 1e-10" });
  list.push_back({ "sightline", SHGlyphOptions{}, "exact root finding, default options (tolerance 1e-6)" });
  auto marching = [](double step, bool interpolation, int bisections, bool centre)
  {
    SHGlyphOptions o;
    o.method = sightline::SHIntersectionMethod::TensorMarching;
    o.tensorMarching.stepSize = step;
    o.tensorMarching.linearInterpolation = interpolation;
    o.tensorMarching.bisectionSteps = bisections;
    o.tensorMarching.centreStepFactor = centre ? 1.0 / 3.0 : 1.0;
    return o;
  };
  list.push_back({ "march-0.2-lin", marching(0.2, true, 0, true),
    "the paper's recommendation: step 0.2, linear interpolation, steps of 1/3 near the centre" });
  list.push_back({ "march-0.2-lin-nocentre", marching(0.2, true, 0, false), "step 0.2, linear interpolation" });
  list.push_back({ "march-0.2-bisect3", marching(0.2, false, 3, true), "step 0.2, 3 bisection steps, centre steps" });
  for (double step : { 0.1, 0.05, 0.02, 0.01 })
  {
    std::ostringstream name;
    name << "march-" << step << "-lin";
    list.push_back({ name.str(), marching(step, true, 0, true), "step " + name.str().substr(6, name.str().size() - 10) +
      ", linear interpolation, centre steps" });
  }
  auto subdivision = [](sightline::EnclosureArithmetic arithmetic, double tolerance)
  {
    SHGlyphOptions o;
    o.method = sightline::SHIntersectionMethod::IntervalSubdivision;
    o.subdivision.arithmetic = arithmetic;
    o.subdivision.tolerance = tolerance;
    return o;
  };
  list.push_back({ "ia-1e-3", subdivision(sightline::EnclosureArithmetic::Interval, 1e-3),
    "interval arithmetic, rejection and bisection to 1e-3 radii" });
  list.push_back({ "raa-1e-3", subdivision(sightline::EnclosureArithmetic::ReducedAffine, 1e-3),
    "reduced affine arithmetic to 1e-3 radii" });
  list.push_back({ "raa-1e-4", subdivision(sightline::EnclosureArithmetic::ReducedAffine, 1e-4),
    "reduced affine arithmetic to 1e-4 radii" });
  // The first two (reference and exact) always run.
  list.erase(std::remove_if(list.begin() + 2, list.end(), [&](const Method& m) { return !options.wantsMethod(m.name); }),
    list.end());
  return list;
}

/// Single-threaded ns per ray-glyph test for hits and misses (rays down through the glyph's
/// box footprint, classified by the exact method).
struct MicroRow
{
  std::string dataset;
  int order = 0;
  std::string method;
  double hitNs = kNotMeasured;
  double missNs = kNotMeasured;
};

std::vector<MicroRow> measureMicro(const Dataset& data, const Options& options)
{
  std::vector<MicroRow> rows;
  const auto exact = makeGlyphs(data, SHGlyphOptions{});
  std::mt19937 rng(options.seed + 5);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::vector<std::pair<unsigned, sightline::Ray>> hits, misses;
  for (int i = 0; i < 20000 && (hits.size() < 2000 || misses.size() < 2000); ++i)
  {
    const unsigned g = unsigned(i) % unsigned(exact->size());
    const vec3 h = exact->halfExtents(g);
    sightline::Ray ray;
    ray.origin = exact->center(g) + vec3(uniform(rng) * h.x, uniform(rng) * h.y, 3.0f);
    ray.direction = vec3(0.0f, 0.0f, -1.0f);
    ray.tnear = 0.0f;
    ray.tfar = 1e30f;
    sightline::SurfaceHit hit;
    (exact->intersect(g, ray, hit) ? hits : misses).emplace_back(g, ray);
  }
  // The exact method, the paper's recommended and finest marching and both subdivisions.
  const std::vector<std::string> measured = { "sightline", "march-0.2-lin", "march-0.01-lin", "ia-1e-3", "raa-1e-3" };
  for (const Method& method : methods(options))
  {
    if (std::find(measured.begin(), measured.end(), method.name) == measured.end())
      continue;
    const auto glyphs = makeGlyphs(data, method.options);
    MicroRow row;
    row.dataset = data.name;
    row.order = data.order;
    row.method = method.name;
    for (auto* set : { &hits, &misses })
    {
      const double seconds = secondsPerCall(set->size(), [&](std::size_t i)
        {
          sightline::SurfaceHit hit;
          glyphs->intersect((*set)[i].first, (*set)[i].second, hit);
        });
      (set == &hits ? row.hitNs : row.missNs) = 1e9 * seconds;
    }
    rows.push_back(row);
  }
  return rows;
}

std::vector<MethodResult> runDataset(const Options& options, const Dataset& data, long long count)
{
  const std::string prefix = data.name + ":";
  const View view = makeGlyphView(data.centers, kGlyphRadius, options.width, options.height);
  std::vector<std::unique_ptr<PreparedMethod>> prepared;
  for (const Method& method : methods(options))
  {
    logProgress("tensor-glyphs: " + prefix + method.name);
    std::shared_ptr<SHGlyphSet> glyphs;
    const double construct = timeOnce([&] { glyphs = makeGlyphs(data, method.options); });
    auto built = std::make_shared<const BuiltScene>(glyphs);
    auto m = prepareMethod(view, prefix + method.name, built, nullptr, {}, construct + built->scene->buildSeconds(),
      count);
    m->result.notes = method.what + "; " + data.description + "; bounds " + fixed(glyphs->boundsSeconds(), 3) + " s";
    prepared.push_back(std::move(m));
  }
  logProgress("tensor-glyphs: " + prefix + std::to_string(options.runs) + " timed frames of " +
    std::to_string(prepared.size()) + " methods, round robin");
  std::vector<PreparedMethod*> timed;
  for (auto& m : prepared)
    timed.push_back(m.get());
  timeRoundRobin(view, options.runs, timed);

  std::vector<MethodResult> results;
  for (auto& m : prepared)
    results.push_back(std::move(m->result));
  const Image reference = results.front().image;
  const double exactFrame = results[1].frame.medianSeconds;
  const fs::path images = fs::path(options.outputDirectory) / "images";
  fs::create_directories(images);
  for (MethodResult& r : results)
  {
    r.error = compareImages(r.image, reference);
    std::ostringstream extra;
    extra << "; pixels differing > " << kPixelThreshold << "/255: " << std::setprecision(3)
          << differingPixelPercent(r.image, reference) << " %; frame time x" << r.frame.medianSeconds / exactFrame
          << " of " << prefix << "sightline";
    r.notes += extra.str();
    if (&r != &results.front())
      writeDifferencePNG(r.image, reference, (images / ("tensor-glyphs-" + std::to_string(count) + "-" + r.method + "-diff.png")).string());
  }
  return results;
}

void writeMicro(const Options& options, const std::vector<MicroRow>& rows)
{
  const fs::path path = fs::path(options.outputDirectory) / "tensor-glyphs-intersection.csv";
  fs::create_directories(path.parent_path());
  std::ofstream out(path);
  out << "dataset,order,method,hit_ns,miss_ns\n";
  for (const MicroRow& r : rows)
    out << r.dataset << "," << r.order << "," << r.method << "," << r.hitNs << "," << r.missNs << "\n";
  std::cout << "\nTensor glyphs, one ray-glyph test on one thread (ns, hit / miss):\n";
  for (const MicroRow& r : rows)
    std::cout << "  " << std::left << std::setw(6) << r.dataset << std::setw(24) << r.method << std::right
              << std::setw(9) << fixed(r.hitNs, 0) << " / " << fixed(r.missNs, 0) << "\n";
  logProgress("tensor-glyphs: wrote " + path.string());
}

/// Per data set: the recommended marching against the exact method, and the finest marching
/// step needed to match the exact method's coverage.
void printSummary(const std::vector<MethodResult>& results)
{
  std::cout << "\nTensor glyphs: frame time relative to the exact method of the same data set, and errors\n"
            << std::left << std::setw(34) << "method" << std::right << std::setw(11) << "frame s" << std::setw(10)
            << "x exact" << std::setw(10) << "RGB err" << std::setw(10) << "cover %" << std::setw(12)
            << "depth p99" << "\n";
  for (const MethodResult& r : results)
  {
    const std::string prefix = r.method.substr(0, r.method.find(':') + 1);
    double exactTime = kNotMeasured;
    for (const MethodResult& s : results)
      if (s.method == prefix + "sightline")
        exactTime = s.frame.medianSeconds;
    std::cout << std::left << std::setw(34) << r.method << std::right << std::setw(11) << fixed(r.frame.medianSeconds, 4)
              << std::setw(10) << fixed(r.frame.medianSeconds / exactTime, 2) << std::setw(10)
              << fixed(r.error.rgbMeanAbsDiff, 3) << std::setw(10) << fixed(r.error.coverageDiffPercent, 4)
              << std::setw(12) << std::setprecision(3) << r.error.depthP99AbsDiff << "\n";
  }
}

std::vector<MethodResult> runTensorGlyphScene(const Options& options, long long count, MachineDescription&)
{
  std::vector<MethodResult> results;
  std::vector<MicroRow> micro;
  const Dataset datasets[] = { makeDataset("cu4", 4, count, options.seed),
    makeDataset("hot8", 8, count, options.seed + 1), makeDataset("hot12", 12, count, options.seed + 2) };
  for (const Dataset& data : datasets)
  {
    logProgress("tensor-glyphs: single-threaded ray-glyph costs, " + data.name);
    for (const MicroRow& row : measureMicro(data, options))
      micro.push_back(row);
    for (MethodResult& r : runDataset(options, data, count))
      results.push_back(std::move(r));
  }
  writeMicro(options, micro);
  printSummary(results);
  return results;
}

const SceneRegistration registration{ "tensor-glyphs",
  "a slice of higher-order tensor glyphs (Hlawitschka et al.): exact root finding vs the paper's "
  "fixed-step marching (step 0.2 with linear interpolation and centre steps, and finer steps) "
  "vs interval / reduced affine arithmetic subdivision; copper's stiffness tensor (order 4) and "
  "random tensors of orders 8 and 12, a third touching their centre",
  { 900 }, &runTensorGlyphScene };
} // namespace
} // namespace sightline_benchmark
