// SPDX-License-Identifier: BSD-3-Clause
// The SH glyph scene (Peters et al. 2023, Fig. 1 and Table 1): one slice of glyphs seen from
// above, rendered through the kernel's Renderer and one Embree BVH per method
// - exactly (Algorithm 1) with a converged reference (double, tolerance 1e-10) and the default;
// - by ray marching with 100 and 200 steps inside the bounding cylinder, with the boxes of the
//   bounding sphere (van Almsick et al.) or with the near-exact boxes ("our AABB");
// - as icosphere meshes deformed by |F| (the DIPY/FURY/MRtrix way) on Embree's triangles;
// - as bare boxes (traversal cost only);
// - exactly with hard shadows, soft shadows and an uncertainty volume, to show what each costs.
// Three data sets per run: synthetic fODF-like glyphs truncated at k = 4 and at k = 8, and
// DIPY's func_coef.nii.gz (MRtrix 0.2 basis, lmax 8) tiled over the slice. Each data set has
// a reference of its own, so this scene computes the image errors itself (the harness compares
// with one reference per run and leaves errors alone when no row is marked as reference);
// methods are named "<data set>:<method>", with no row marked isReference, so the harness's
// "x sightline" column stays empty and the ratio to "<data set>:sightline" is in the notes and
// in the table printed here. All methods of a data set are built first, then their --runs
// frames are timed round robin, so that other processes on shared cores slow them alike.
// --tessellation gives icosphere vertex counts (42,162,642,2562 = levels 1-4 by default).
//
// Also measured, single-threaded: AABB time per glyph and the cost of one ray-glyph test
// (hit and miss) for k = 4 and 8, exact and marching; printed and written to
// <output>/sh-glyphs-intersection.csv.
#include "GlyphSceneSupport.h"
#include "SceneRegistry.h"

#include "sightline/core/Camera.h"
#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Framebuffer.h"
#include "sightline/core/Renderer.h"
#include "sightline/glyphs/SHGlyph.h"
#include "sightline/glyphs/SHGlyphSet.h"
#include "sightline/baselines/SHGlyphTessellation.h"
#include "sightline/core/Shading.h"
#include "sightline/math/SphericalHarmonics.h"
#include "sightline/baselines/TriangleMesh.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>

namespace sightline_benchmark
{
namespace
{
namespace fs = std::filesystem;
using sightline::Box3;
using sightline::dvec3;
using sightline::SHGlyphOptions;
using sightline::SHGlyphSet;
using sightline::vec3;

using sightline::kPi;
/// Glyphs are scaled so that max |F| is this (spacing 1): they never touch (DIPY's odf_slicer
/// normalises each glyph the same way, with 0.5).
constexpr double kGlyphRadius = 0.45;
/// Sharpness of the synthetic fibre lobes: zonal band l is attenuated by exp(-l (l + 1) this).
constexpr double kLobeAttenuation = 0.03;
/// The harness's default --tessellation list is for vtkSphereSource; here it means icosphere
/// levels, and that default is replaced by these.
const std::vector<int> kHarnessDefaultTessellations{ 8, 16, 32 };
const std::vector<int> kDefaultLevels{ 1, 2, 3, 4 };

/// One slice of glyphs, coefficients as the glyph set takes them.
struct Dataset
{
  std::string name; ///< method prefix: k4, k8, dipy
  std::string description;
  int order = 0;
  sightline::SHConvention convention{ sightline::SHBasis::Canonical, false };
  std::vector<vec3> centers;
  std::vector<float> coefficients; ///< shCoefficientCount(order) per glyph, in `convention`
  std::vector<float> scales;       ///< empty or one per glyph
  std::string skipReason;          ///< non-empty: the data could not be loaded
};

/// max |F| of each glyph of canonical coefficients (`stride` per glyph): the kernel's
/// shGlyphMaxRadius, which the VTK mapper's normalisation uses too.
std::vector<double> maxAbsValues(int order, const std::vector<double>& canonical)
{
  const int stride = sightline::shCoefficientCount(order);
  const std::size_t n = canonical.size() / stride;
  std::vector<double> result(n);
  tbb::parallel_for(std::size_t(0), n,
    [&](std::size_t i) { result[i] = sightline::shGlyphMaxRadius(order, canonical.data() + i * stride); });
  return result;
}

/// Glyph centres on a square grid of spacing 1 in the plane z = 0, row by row.
std::vector<vec3> gridCenters(long long count, int& side)
{
  side = int(std::ceil(std::sqrt(double(count)) - 1e-9));
  std::vector<vec3> centers(count);
  for (long long i = 0; i < count; ++i)
    centers[i] = vec3(float(i % side), float(i / side), 0.0f);
  return centers;
}

/// Synthetic fODF-like glyphs: an isotropic part plus 1-3 fibre lobes whose directions follow
/// smooth fields with noise (one bundle everywhere, one crossing through the plane in a disc,
/// one fanning in the upper part). A lobe is a sharp zonal function rotated to the fibre
/// direction u: its band-l coefficients are a_l sqrt(4 pi / (2l + 1)) Y_l0(z) Y_lm(u) =
/// a_l Y_lm(u), a smoothed delta. The same fibres are truncated at k = 4 and at k = 8, and
/// each glyph is scaled to max |F| = kGlyphRadius.
std::pair<Dataset, Dataset> makeSyntheticDatasets(long long count, unsigned seed)
{
  constexpr int kFullOrder = 8;
  const int stride = sightline::shCoefficientCount(kFullOrder);
  int side = 0;
  const std::vector<vec3> centers = gridCenters(count, side);
  std::mt19937 random(seed);
  std::normal_distribution<double> jitter(0.0, 0.12);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  std::vector<double> attenuation(kFullOrder + 1);
  double lobePeak = 0.0; // a lobe's value along its own direction: sum a_l (2l + 1) / (4 pi)
  for (int l = 0; l <= kFullOrder; l += 2)
  {
    attenuation[l] = std::exp(-kLobeAttenuation * l * (l + 1));
    lobePeak += attenuation[l] * (2 * l + 1) / (4.0 * kPi);
  }

  std::vector<double> full(std::size_t(count) * stride, 0.0);
  std::vector<double> basis(stride);
  int lobeHistogram[4] = { 0, 0, 0, 0 };
  for (long long i = 0; i < count; ++i)
  {
    const double X = side > 1 ? double(i % side) / (side - 1) : 0.5;
    const double Y = side > 1 ? double(i / side) / (side - 1) : 0.5;
    struct Fibre
    {
      dvec3 direction;
      double weight;
    };
    std::vector<Fibre> fibres;
    const double a1 = 0.5 + 1.2 * X + 0.4 * std::sin(3.0 * Y);
    fibres.push_back({ { std::cos(a1), std::sin(a1), 0.25 * std::sin(2.0 * kPi * Y) }, 0.6 + 0.4 * uniform(random) });
    if ((X - 0.6) * (X - 0.6) + (Y - 0.4) * (Y - 0.4) < 0.12)
      fibres.push_back({ { 0.3 * std::sin(5.0 * X), 0.3 * std::cos(4.0 * Y), 1.0 }, 0.4 + 0.5 * uniform(random) });
    if (Y > 0.55 + 0.15 * std::sin(6.0 * X))
    {
      const double a3 = 2.2 - 0.8 * Y;
      fibres.push_back({ { std::cos(a3), std::sin(a3), -0.3 }, 0.4 + 0.5 * uniform(random) });
    }
    ++lobeHistogram[fibres.size()];
    double* b = full.data() + i * stride;
    for (Fibre& fibre : fibres)
    {
      dvec3 u = glm::normalize(fibre.direction) + dvec3(jitter(random), jitter(random), jitter(random));
      u = glm::normalize(u);
      sightline::evaluateSH<double>(kFullOrder, u.x, u.y, u.z, basis.data());
      for (int l = 0; l <= kFullOrder; l += 2)
        for (int m = -l; m <= l; ++m)
          b[sightline::shIndex(l, m)] += fibre.weight * attenuation[l] * basis[sightline::shIndex(l, m)];
    }
    // The isotropic part (partial volume of other tissue, a flat response) makes b0 the
    // dominant coefficient: a constant 40-70 % of the strongest lobe's peak at k = 8.
    double strongest = 0.0;
    for (const Fibre& fibre : fibres)
      strongest = std::max(strongest, fibre.weight);
    b[0] += (0.4 + 0.3 * uniform(random)) * strongest * lobePeak * 2.0 * std::sqrt(kPi);
  }

  auto truncated = [&](int order, const std::string& name)
  {
    Dataset dataset;
    dataset.name = name;
    dataset.order = order;
    dataset.centers = centers;
    const int n = sightline::shCoefficientCount(order);
    std::vector<double> canonical(std::size_t(count) * n);
    for (long long i = 0; i < count; ++i)
      std::copy(full.begin() + i * stride, full.begin() + i * stride + n, canonical.begin() + i * n);
    const std::vector<double> largest = maxAbsValues(order, canonical);
    dataset.coefficients.resize(canonical.size());
    for (long long i = 0; i < count; ++i)
      for (int j = 0; j < n; ++j)
        dataset.coefficients[i * n + j] = float(canonical[i * n + j] * kGlyphRadius / largest[i]);
    std::ostringstream description;
    description << "synthetic fODF-like, " << side << "x" << (count + side - 1) / side
                << " slice, k = " << order << ", lobes 1/2/3: " << lobeHistogram[1] << "/"
                << lobeHistogram[2] << "/" << lobeHistogram[3];
    dataset.description = description.str();
    return dataset;
  };
  return { truncated(4, "k4"), truncated(8, "k8") };
}

/// DIPY's func_coef.nii.gz (2x3x4 voxels, lmax 8, MRtrix 0.2's basis: tournier07 legacy, as
/// the kernel's reference tests read it), read by DIPY's own Python with nibabel into a raw
/// float32 file in the output directory, then tiled over the slice.
Dataset makeDipyDataset(const Options& options, long long count)
{
  Dataset dataset;
  dataset.name = "dipy";
  dataset.order = 8;
  dataset.convention = { sightline::SHBasis::Tournier07, true };
  const fs::path directory = fs::path(options.outputDirectory) / "sh-glyphs-data";
  fs::create_directories(directory);
  const fs::path raw = directory / "func_coef.f32";
  const fs::path shapeFile = directory / "func_coef.txt";
  const std::string script =
    "import os, sys, numpy as np, nibabel as nib, dipy.data\n"
    "path = os.path.join(os.path.dirname(dipy.data.__file__), 'files', 'func_coef.nii.gz')\n"
    "a = np.ascontiguousarray(np.asarray(nib.load(path).dataobj, np.float32))\n"
    "a.tofile(sys.argv[1])\n"
    "open(sys.argv[2], 'w').write(' '.join(map(str, a.shape)) + '\\n' + path + '\\n')\n";
  const fs::path scriptPath = directory / "dump_func_coef.py";
  std::ofstream(scriptPath) << script;
  const std::string command = "'" + options.python + "' '" + scriptPath.string() + "' '" +
    raw.string() + "' '" + shapeFile.string() + "'";
  if (std::system(command.c_str()) != 0)
  {
    dataset.skipReason = "could not read DIPY's func_coef.nii.gz with " + options.python +
      " (needs python3-dipy and python3-nibabel)";
    return dataset;
  }
  int nx = 0, ny = 0, nz = 0, nc = 0;
  std::string source;
  {
    std::ifstream shape(shapeFile);
    shape >> nx >> ny >> nz >> nc;
    shape >> std::ws;
    std::getline(shape, source);
  }
  const int stride = sightline::shCoefficientCount(8);
  if (nc != stride || nx < 1 || ny < 1 || nz < 1)
  {
    dataset.skipReason = "func_coef.nii.gz has an unexpected shape";
    return dataset;
  }
  std::vector<float> voxels(std::size_t(nx) * ny * nz * nc);
  std::ifstream(raw, std::ios::binary).read(reinterpret_cast<char*>(voxels.data()),
    std::streamsize(voxels.size() * sizeof(float)));

  int side = 0;
  dataset.centers = gridCenters(count, side);
  dataset.coefficients.resize(std::size_t(count) * stride);
  // Tiles of nx x ny voxels; successive tiles step through z so all voxels appear.
  for (long long i = 0; i < count; ++i)
  {
    const long long gx = i % side, gy = i / side;
    const long long x = gx % nx, y = gy % ny, z = (gx / nx + gy / ny) % nz;
    const float* source = voxels.data() + ((x * ny + y) * nz + z) * nc;
    std::copy(source, source + nc, dataset.coefficients.begin() + i * stride);
  }
  // Scale each glyph to max |F| = kGlyphRadius; the glyph set converts the basis itself.
  const sightline::SHConversion conversion = sightline::SHConversion::toCanonical(dataset.convention, 8);
  std::vector<double> canonical(dataset.coefficients.size());
  for (long long i = 0; i < count; ++i)
    conversion.apply(dataset.coefficients.data() + i * stride, canonical.data() + i * stride);
  const std::vector<double> largest = maxAbsValues(8, canonical);
  dataset.scales.resize(count);
  for (long long i = 0; i < count; ++i)
    dataset.scales[i] = float(kGlyphRadius / largest[i]);
  std::ostringstream description;
  description << "DIPY func_coef.nii.gz (" << nx << "x" << ny << "x" << nz
              << " voxels, tournier07 legacy, lmax 8) tiled over a " << side << "x"
              << (count + side - 1) / side << " slice";
  dataset.description = description.str();
  return dataset;
}

/// The uncertainty glyphs of Section 5: b0 times 1.7, then every coefficient times N(1, 0.05).
Dataset makeUncertainty(const Dataset& mean, unsigned seed)
{
  Dataset dataset = mean;
  dataset.name = mean.name + "-uncertainty";
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(1.0, 0.05);
  const int stride = sightline::shCoefficientCount(mean.order);
  for (std::size_t i = 0; i < dataset.coefficients.size(); ++i)
  {
    const double b0 = i % stride == 0 ? 1.7 : 1.0;
    dataset.coefficients[i] = float(dataset.coefficients[i] * b0 * noise(random));
  }
  return dataset;
}

//------------------------------------------------------------------------------

std::shared_ptr<SHGlyphSet> makeGlyphSet(const Dataset& dataset, SHGlyphOptions options)
{
  options.convention = dataset.convention;
  auto glyphs = std::make_shared<SHGlyphSet>(
    dataset.centers, dataset.coefficients, dataset.order, options, dataset.scales);
  glyphs->material = glyphMaterial();
  if (!glyphs->report().clean())
    throw std::runtime_error(dataset.name + ": glyphs were rejected: " + glyphs->report().reasons.front());
  return glyphs;
}

//------------------------------------------------------------------------------
/// "Boxes only": a user geometry that reports a hit where the ray enters each glyph's box, with
/// the box face as normal. Rendering it costs BVH traversal and shading but no glyph test.
class GlyphBoxes : public sightline::UserGeometry<GlyphBoxes>
{
public:
  explicit GlyphBoxes(const SHGlyphSet& glyphs)
  {
    Boxes.reserve(glyphs.size());
    for (unsigned i = 0; i < glyphs.size(); ++i)
    {
      Boxes.push_back(glyphs.bounds(i));
      AllBounds.extend(Boxes.back());
    }
    material = glyphs.material;
    material.color = vec3(0.7f);
    material.ambientColor = vec3(0.7f);
  }

  std::size_t size() const override { return Boxes.size(); }
  bool hasPrimitiveColors() const override { return false; }
  vec3 primitiveColor(unsigned) const override { return material.color; }
  std::size_t memoryBytes() const override { return Boxes.capacity() * sizeof(Box3); }
  Box3 bounds() const override { return AllBounds; }
  Box3 bounds(unsigned primitive) const { return Boxes[primitive]; }

  bool intersect(unsigned primitive, const sightline::DoubleRay& ray, sightline::SurfaceHit& hit) const
  {
    const Box3& box = Boxes[primitive];
    double tEnter = ray.tnear, tExit = ray.tfar;
    int axis = -1;
    for (int a = 0; a < 3; ++a)
    {
      const double inverse = 1.0 / ray.direction[a];
      double t0 = (box.lower[a] - ray.origin[a]) * inverse;
      double t1 = (box.upper[a] - ray.origin[a]) * inverse;
      if (t0 > t1)
        std::swap(t0, t1);
      if (t0 > tEnter)
      {
        tEnter = t0;
        axis = a;
      }
      tExit = std::min(tExit, t1);
    }
    if (axis < 0 || !(tEnter <= tExit) || !(tEnter > ray.tnear) || !(tEnter < ray.tfar))
      return false;
    hit.t = tEnter;
    hit.normal = vec3(0.0f);
    hit.normal[axis] = 1.0f;
    return true;
  }

private:
  std::vector<Box3> Boxes;
  Box3 AllBounds;
};



//------------------------------------------------------------------------------
/// Single-threaded costs for one order: AABB per glyph, one intersection test (hit, miss).
struct MicroResult
{
  std::string dataset;
  int order = 0;
  double aabbMicroseconds = kNotMeasured;   ///< shGlyphHalfExtents, one thread
  double boundsSetMicroseconds = kNotMeasured; ///< SHGlyphSet::boundsSeconds per glyph (all threads)
  double exactHitNs = kNotMeasured;         ///< intersectSHGlyph<double>, first hit
  double exactMissNs = kNotMeasured;
  double exactSetHitNs = kNotMeasured;      ///< SHGlyphSet::intersect (with the normal)
  double exactSetMissNs = kNotMeasured;
  double march200HitNs = kNotMeasured;      ///< SHGlyphSet::intersect, 200 steps, cylinder
  double march200MissNs = kNotMeasured;
  double march100HitNs = kNotMeasured;
  double march100MissNs = kNotMeasured;
  int hitRays = 0;
  int missRays = 0;

  std::string summary() const
  {
    std::ostringstream s;
    s << std::setprecision(3) << "1 thread: AABB " << aabbMicroseconds << " us/glyph; test ns hit/miss: exact "
      << exactHitNs << "/" << exactMissNs << " (with normal " << exactSetHitNs << "/" << exactSetMissNs
      << "), marching-200 " << march200HitNs << "/" << march200MissNs << ", marching-100 "
      << march100HitNs << "/" << march100MissNs;
    return s.str();
  }
};


MicroResult measureMicro(const Dataset& dataset, const SHGlyphSet& exact, unsigned seed)
{
  MicroResult micro;
  micro.dataset = dataset.name;
  micro.order = dataset.order;
  const unsigned n = unsigned(exact.size());
  micro.boundsSetMicroseconds = 1e6 * exact.boundsSeconds() / n;

  // AABBs on this thread only.
  const unsigned aabbGlyphs = std::min(n, 1000u);
  volatile double sink = 0.0;
  micro.aabbMicroseconds = 1e6 * secondsPerCall(aabbGlyphs, [&](std::size_t i)
    {
      const dvec3 h = sightline::shGlyphHalfExtents(exact.order(unsigned(i)), exact.coefficients(unsigned(i)));
      sink = sink + h.x;
    });

  // Rays: hits aim from outside the bounding sphere at a point inside the glyph (half way to
  // the surface in a random direction); misses aim at a random point of the glyph's box and
  // are kept when the exact test finds nothing.
  struct TestRay
  {
    unsigned glyph;
    double origin[3]; ///< relative to the centre
    double direction[3];
  };
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto randomDirection = [&]
  {
    dvec3 d(normal(random), normal(random), normal(random));
    return glm::normalize(d);
  };
  std::vector<TestRay> hits, misses;
  const int wanted = 4000;
  for (int attempt = 0; attempt < 100 * wanted && (int(hits.size()) < wanted || int(misses.size()) < wanted); ++attempt)
  {
    const unsigned g = unsigned(attempt) % n;
    const double* b = exact.coefficients(g);
    const int order = exact.order(g);
    const double R = sightline::shGlyphBoundingRadius(order, b);
    const dvec3 from = 1.5 * R * randomDirection();
    dvec3 target;
    const bool aimInside = attempt % 2 == 0;
    if (aimInside)
    {
      const dvec3 w = randomDirection();
      target = 0.5 * std::abs(sightline::evaluateSHSum<double>(order, b, w.x, w.y, w.z)) * w;
    }
    else
    {
      const Box3 box = exact.bounds(g);
      const dvec3 c(exact.center(g));
      target = dvec3(box.lower) - c +
        dvec3(uniform(random), uniform(random), uniform(random)) * (dvec3(box.upper) - dvec3(box.lower));
    }
    const dvec3 d = glm::normalize(target - from);
    TestRay ray{ g, { from.x, from.y, from.z }, { d.x, d.y, d.z } };
    double t[sightline::kMaxGlyphHits];
    const int count = sightline::intersectSHGlyph<double>(order, b, ray.origin, ray.direction, 0.0,
      1e30, sightline::defaultGlyphTolerance<double>(), t, true);
    if (count > 0 && aimInside && int(hits.size()) < wanted)
      hits.push_back(ray);
    else if (count == 0 && !aimInside && int(misses.size()) < wanted)
      misses.push_back(ray);
  }
  micro.hitRays = int(hits.size());
  micro.missRays = int(misses.size());

  auto rawTest = [&](const std::vector<TestRay>& rays)
  {
    return 1e9 * secondsPerCall(rays.size(), [&](std::size_t i)
      {
        const TestRay& r = rays[i];
        double t[sightline::kMaxGlyphHits];
        const int count = sightline::intersectSHGlyph<double>(exact.order(r.glyph), exact.coefficients(r.glyph),
          r.origin, r.direction, 0.0, 1e30, sightline::defaultGlyphTolerance<double>(), t, true);
        sink = sink + count;
      });
  };
  auto setTest = [&](const SHGlyphSet& glyphs, const std::vector<TestRay>& rays)
  {
    std::vector<sightline::Ray> worldRays(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i)
    {
      const dvec3 c(glyphs.center(rays[i].glyph));
      worldRays[i].origin = vec3(c + dvec3(rays[i].origin[0], rays[i].origin[1], rays[i].origin[2]));
      worldRays[i].direction = vec3(rays[i].direction[0], rays[i].direction[1], rays[i].direction[2]);
    }
    return 1e9 * secondsPerCall(rays.size(), [&](std::size_t i)
      {
        sightline::SurfaceHit hit;
        sink = sink + glyphs.intersect(rays[i].glyph, worldRays[i], hit);
      });
  };
  micro.exactHitNs = rawTest(hits);
  micro.exactMissNs = rawTest(misses);
  micro.exactSetHitNs = setTest(exact, hits);
  micro.exactSetMissNs = setTest(exact, misses);
  for (int steps : { 200, 100 })
  {
    SHGlyphOptions marching;
    marching.method = sightline::SHIntersectionMethod::RayMarching;
    marching.marchingSteps = steps;
    marching.marchingBound = sightline::SHMarchingBound::Cylinder;
    const auto glyphs = makeGlyphSet(dataset, marching);
    (steps == 200 ? micro.march200HitNs : micro.march100HitNs) = setTest(*glyphs, hits);
    (steps == 200 ? micro.march200MissNs : micro.march100MissNs) = setTest(*glyphs, misses);
  }
  return micro;
}

void writeMicroResults(const Options& options, long long count, const std::vector<MicroResult>& results)
{
  const fs::path path = fs::path(options.outputDirectory) / "sh-glyphs-intersection.csv";
  // One file per run, like the harness's CSV: the first count rewrites it, later ones append.
  static bool firstInThisRun = true;
  std::ofstream out(path, firstInThisRun ? std::ios::trunc : std::ios::app);
  if (firstInThisRun)
    out << "dataset,order,glyphs,aabb_us_per_glyph_1thread,set_bounds_us_per_glyph_all_threads,"
           "exact_hit_ns,exact_miss_ns,exact_with_normal_hit_ns,exact_with_normal_miss_ns,"
           "march200_cylinder_hit_ns,march200_cylinder_miss_ns,march100_cylinder_hit_ns,"
           "march100_cylinder_miss_ns,hit_rays,miss_rays\n";
  firstInThisRun = false;
  for (const MicroResult& m : results)
    out << m.dataset << ',' << m.order << ',' << count << ',' << m.aabbMicroseconds << ','
        << m.boundsSetMicroseconds << ',' << m.exactHitNs << ',' << m.exactMissNs << ','
        << m.exactSetHitNs << ',' << m.exactSetMissNs << ',' << m.march200HitNs << ','
        << m.march200MissNs << ',' << m.march100HitNs << ',' << m.march100MissNs << ','
        << m.hitRays << ',' << m.missRays << '\n';

  std::cout << "\nSH glyph costs, single-threaded (" << count << " glyphs per data set; paper: AABB 29 us/glyph for k = 4)\n"
            << std::left << std::setw(8) << "data" << std::right << std::setw(4) << "k" << std::setw(12)
            << "AABB us" << std::setw(14) << "exact hit ns" << std::setw(15) << "exact miss ns"
            << std::setw(13) << "+normal hit" << std::setw(14) << "march200 hit" << std::setw(15)
            << "march200 miss" << std::setw(14) << "march100 hit" << std::setw(15) << "march100 miss" << "\n";
  for (const MicroResult& m : results)
    std::cout << std::left << std::setw(8) << m.dataset << std::right << std::setw(4) << m.order
              << std::setw(12) << fixed(m.aabbMicroseconds, 1) << std::setw(14) << fixed(m.exactHitNs, 0)
              << std::setw(15) << fixed(m.exactMissNs, 0) << std::setw(13) << fixed(m.exactSetHitNs, 0)
              << std::setw(14) << fixed(m.march200HitNs, 0) << std::setw(15) << fixed(m.march200MissNs, 0)
              << std::setw(14) << fixed(m.march100HitNs, 0) << std::setw(15) << fixed(m.march100MissNs, 0)
              << "\n";
  std::cout << "CSV:    " << path.string() << "\n";
}

//------------------------------------------------------------------------------
/// Icosphere levels of the tessellated baselines. The harness's --tessellation takes values
/// >= 3, so this scene reads them as vertices per glyph (12, 42, 162, 642, 2562, 10242, ... =
/// levels 0, 1, 2, ...); the harness's default list (meant for vtkSphereSource) means levels 1-4.
std::vector<int> tessellationLevels(const Options& options)
{
  if (options.tessellations == kHarnessDefaultTessellations)
    return kDefaultLevels;
  std::vector<int> levels;
  for (int vertices : options.tessellations)
  {
    int level = -1;
    for (int l = 0; l <= sightline::kMaxIcosphereSubdivisions; ++l)
      if (sightline::icosphereVertexCount(l) == std::size_t(vertices))
        level = l;
    if (level < 0)
    {
      std::string valid;
      for (int l = 0; l <= sightline::kMaxIcosphereSubdivisions; ++l)
        valid += (l ? ", " : "") + std::to_string(sightline::icosphereVertexCount(l));
      throw std::invalid_argument("sh-glyphs: --tessellation takes icosphere vertex counts (" + valid +
        " for levels 0-" + std::to_string(sightline::kMaxIcosphereSubdivisions) + "), got " +
        std::to_string(vertices));
    }
    levels.push_back(level);
  }
  return levels;
}

/// Every method on one data set; errors against that data set's reference.
std::vector<MethodResult> runDataset(const Options& options, const Dataset& dataset, long long count,
  const MicroResult* micro)
{
  const std::string prefix = dataset.name + ":";
  const View view = makeGlyphView(dataset.centers, kGlyphRadius, options.width, options.height);
  const long long glyphCount = count;
  // Rows in order; a row is either prepared (rendered below) or skipped.
  std::vector<std::unique_ptr<PreparedMethod>> prepared;
  std::vector<MethodResult> skipped;
  std::vector<std::pair<bool, std::size_t>> order; // (is prepared, index)
  auto add = [&](std::unique_ptr<PreparedMethod> method, const std::string& notes)
  {
    method->result.notes = notes;
    order.emplace_back(true, prepared.size());
    prepared.push_back(std::move(method));
  };

  auto glyphNotes = [](const SHGlyphSet& glyphs, const BuiltScene& built)
  {
    std::ostringstream notes;
    notes << "bounds " << fixed(glyphs.boundsSeconds(), 3) << " s, BVH " << fixed(built.scene->buildSeconds(), 3)
          << " s, BVH " << fixed(double(built.scene->bvhBytes()) / glyphs.size(), 0) << " B/glyph";
    return notes.str();
  };

  // An exact (or marching) glyph set in a scene of its own, rendered plainly.
  auto addGlyphs = [&](const std::string& method, SHGlyphOptions glyphOptions, const std::string& what)
  {
    if (method != "reference" && !options.wantsMethod(method))
      return;
    logProgress("sh-glyphs: " + prefix + method);
    std::shared_ptr<SHGlyphSet> glyphs;
    const double construct = timeOnce([&] { glyphs = makeGlyphSet(dataset, glyphOptions); });
    auto built = std::make_shared<const BuiltScene>(glyphs);
    const double build = construct + built->scene->buildSeconds();
    add(prepareMethod(view, prefix + method, built, nullptr, {}, build, glyphCount),
      what + "; " + glyphNotes(*glyphs, *built));
  };

  SHGlyphOptions referenceOptions;
  referenceOptions.precision = sightline::SHPrecision::Double;
  referenceOptions.tolerance = 1e-10;
  addGlyphs("reference", referenceOptions, "reference: exact, double, tolerance 1e-10; " + dataset.description);

  // The default exact method, whose BVH the shadow and volume rows share.
  logProgress("sh-glyphs: " + prefix + "sightline");
  std::shared_ptr<SHGlyphSet> exact;
  const double construct = timeOnce([&] { exact = makeGlyphSet(dataset, SHGlyphOptions{}); });
  auto exactScene = std::make_shared<const BuiltScene>(exact);
  const double exactBuild = construct + exactScene->scene->buildSeconds();
  add(prepareMethod(view, prefix + "sightline", exactScene, nullptr, {}, exactBuild, glyphCount),
    "exact (Algorithm 1), default options (double, tolerance 1e-6); " + glyphNotes(*exact, *exactScene) +
      (micro ? "; " + micro->summary() : std::string()));

  for (int steps : { 100, 200 })
    for (bool tight : { false, true })
    {
      SHGlyphOptions marching;
      marching.method = sightline::SHIntersectionMethod::RayMarching;
      marching.marchingSteps = steps;
      marching.marchingBound = sightline::SHMarchingBound::Cylinder;
      marching.marchingUsesTightBoxes = tight;
      std::ostringstream what;
      what << "ray marching, " << steps << " steps + 10 bisections in the bounding cylinder; "
           << (tight ? "near-exact boxes (\"our AABB\")" : "boxes of the bounding sphere (van Almsick)");
      addGlyphs("march-" + std::to_string(steps) + (tight ? "-aabb" : "-cyl"), marching, what.str());
    }

  // Tessellations of the same glyphs (|F(v)| v on an icosphere, mesh normals, vertex colours).
  for (int level : tessellationLevels(options))
  {
    const std::string method = "tess-L" + std::to_string(level);
    if (!options.wantsMethod(method))
      continue;
    const long long triangles = glyphCount * (long long)sightline::icosphereTriangleCount(level);
    if (triangles > options.maxTriangles)
    {
      MethodResult result;
      result.method = prefix + method;
      result.primitives = glyphCount;
      result.triangles = triangles;
      result.width = view.width;
      result.height = view.height;
      result.skipped = true;
      result.notes = "skipped: " + std::to_string(triangles) + " triangles exceed the budget of " +
        std::to_string(options.maxTriangles) + " (--max-triangles)";
      order.emplace_back(false, skipped.size());
      skipped.push_back(std::move(result));
      continue;
    }
    logProgress("sh-glyphs: " + prefix + method);
    sightline::SHTessellationOptions tessellation;
    tessellation.subdivisions = level;
    tessellation.normals = sightline::SHTessellationNormals::Mesh;
    sightline::SHTessellationInfo info;
    auto built = std::make_shared<const BuiltScene>(sightline::tessellateSHGlyphs(*exact, tessellation, &info));
    const double build = info.seconds + built->scene->buildSeconds();
    std::ostringstream notes;
    notes << "icosphere level " << level << ": " << info.verticesPerGlyph << " vertices, "
          << info.trianglesPerGlyph << " triangles per glyph at |F(v)| v, mesh vertex normals, "
          << "vertex colours; Embree triangles; tessellation " << fixed(info.seconds, 3) << " s, BVH "
          << fixed(built->scene->buildSeconds(), 3) << " s";
    auto tessellated = prepareMethod(view, prefix + method, built, nullptr, {}, build, glyphCount);
    tessellated->result.triangles = triangles;
    add(std::move(tessellated), notes.str());
  }

  if (options.wantsMethod("boxes-only"))
  {
    logProgress("sh-glyphs: " + prefix + "boxes-only");
    auto built = std::make_shared<const BuiltScene>(std::make_shared<GlyphBoxes>(*exact));
    add(prepareMethod(view, prefix + "boxes-only", built, nullptr, {}, built->scene->buildSeconds(), glyphCount),
      "each glyph's near-exact box reported as hit (user geometry): BVH traversal + shading, no "
      "glyph test; a cost floor, not a rendering");
  }

  // Shadows and uncertainty on the default exact glyphs (same BVH, build counted once).
  const std::string byDesign = " (a different image by design: its error measures the effect)";
  sightline::RenderOptions hard;
  hard.shadows.mode = sightline::ShadowMode::Hard;
  if (options.wantsMethod("hard-shadows"))
  {
    logProgress("sh-glyphs: " + prefix + "hard-shadows");
    add(prepareMethod(view, prefix + "hard-shadows", exactScene, nullptr, hard, exactBuild, glyphCount),
      "exact + one shadow ray per pixel" + byDesign);
  }
  sightline::RenderOptions soft;
  soft.shadows.mode = sightline::ShadowMode::Soft;
  soft.shadows.samples = 16;
  if (options.wantsMethod("soft-shadows-16"))
  {
    logProgress("sh-glyphs: " + prefix + "soft-shadows-16");
    add(prepareMethod(view, prefix + "soft-shadows-16", exactScene, nullptr, soft, exactBuild, glyphCount),
      "exact + 16 shadow rays into a light of angular radius 0.15" + byDesign);
  }

  if (options.wantsMethod("uncertainty") || options.wantsMethod("uncertainty-soft-shadows"))
  {
    const Dataset uncertaintyData = makeUncertainty(dataset, options.seed + 17);
    std::shared_ptr<SHGlyphSet> uncertainty;
    const double uncertaintyConstruct =
      timeOnce([&] { uncertainty = makeGlyphSet(uncertaintyData, SHGlyphOptions{}); });
    auto uncertaintyScene = std::make_shared<const BuiltScene>(uncertainty);
    const double volumeBuild = exactBuild + uncertaintyConstruct + uncertaintyScene->scene->buildSeconds();
    std::ostringstream volumeWhat;
    volumeWhat << "exact + uncertainty volume (second glyph set: b0 x 1.7, each coefficient x N(1, 0.05); "
               << "extinction " << kVolumeExtinction << ", emission 0.5; its bounds "
               << fixed(uncertainty->boundsSeconds(), 3) << " s)";
    if (options.wantsMethod("uncertainty"))
    {
      logProgress("sh-glyphs: " + prefix + "uncertainty");
      add(prepareMethod(view, prefix + "uncertainty", exactScene, uncertaintyScene, {}, volumeBuild, glyphCount),
        volumeWhat.str() + byDesign);
    }
    if (options.wantsMethod("uncertainty-soft-shadows"))
    {
      logProgress("sh-glyphs: " + prefix + "uncertainty-soft-shadows");
      add(prepareMethod(view, prefix + "uncertainty-soft-shadows", exactScene, uncertaintyScene, soft,
            volumeBuild, glyphCount),
        volumeWhat.str() + " + soft shadows (16)" + byDesign);
    }
  }

  logProgress("sh-glyphs: " + prefix + std::to_string(options.runs) + " timed frames of " +
    std::to_string(prepared.size()) + " methods, round robin");
  std::vector<PreparedMethod*> timed;
  for (auto& method : prepared)
    timed.push_back(method.get());
  timeRoundRobin(view, options.runs, timed);

  std::vector<MethodResult> results;
  for (const auto& [isPrepared, index] : order)
    results.push_back(isPrepared ? std::move(prepared[index]->result) : std::move(skipped[index]));
  prepared.clear();

  // Errors against this data set's reference (computed here: the harness knows one reference).
  const Image& reference = results.front().image;
  const MethodResult* sightlineRow = nullptr;
  for (const MethodResult& r : results)
    if (r.method == prefix + "sightline")
      sightlineRow = &r;
  const fs::path images = fs::path(options.outputDirectory) / "images";
  fs::create_directories(images);
  for (MethodResult& result : results)
  {
    if (result.skipped)
      continue;
    result.error = compareImages(result.image, reference);
    const double differing = differingPixelPercent(result.image, reference);
    std::ostringstream extra;
    extra << "; pixels differing > " << kPixelThreshold << "/255: " << std::setprecision(3) << differing << " %";
    if (sightlineRow && &result != sightlineRow)
      extra << "; frame time x" << std::setprecision(3)
            << result.frame.medianSeconds / sightlineRow->frame.medianSeconds << " of " << sightlineRow->method;
    result.notes += extra.str();
    if (&result != &results.front())
      writeDifferencePNG(result.image, reference,
        (images / ("sh-glyphs-" + std::to_string(count) + "-" + result.method + "-diff.png")).string());
  }
  return results;
}

std::vector<MethodResult> skippedDataset(const Options& options, const Dataset& dataset, long long count)
{
  std::vector<std::string> methods{ "reference", "sightline", "march-100-cyl", "march-100-aabb",
    "march-200-cyl", "march-200-aabb" };
  for (int level : tessellationLevels(options))
    methods.push_back("tess-L" + std::to_string(level));
  for (const char* m : { "boxes-only", "hard-shadows", "soft-shadows-16", "uncertainty", "uncertainty-soft-shadows" })
    methods.push_back(m);
  std::vector<MethodResult> results;
  for (const std::string& method : methods)
  {
    MethodResult result;
    result.method = dataset.name + ":" + method;
    result.primitives = count;
    result.width = options.width;
    result.height = options.height;
    result.skipped = true;
    result.notes = "skipped: " + dataset.skipReason;
    results.push_back(std::move(result));
  }
  return results;
}

/// Frame time of each method relative to its data set's "sightline", printed after the runs.
void printSummary(const std::vector<MethodResult>& results)
{
  std::cout << "\nSH glyphs: frame time relative to the exact method of the same data set, and errors\n"
            << std::left << std::setw(34) << "method" << std::right << std::setw(11) << "frame s"
            << std::setw(10) << "x exact" << std::setw(10) << "RGB err" << std::setw(10) << "cover %"
            << std::setw(11) << "build s" << std::setw(10) << "B/glyph" << "\n";
  for (const MethodResult& r : results)
  {
    if (r.skipped)
    {
      std::cout << std::left << std::setw(34) << r.method << " skipped\n";
      continue;
    }
    const std::string prefix = r.method.substr(0, r.method.find(':') + 1);
    double exactTime = kNotMeasured;
    for (const MethodResult& s : results)
      if (s.method == prefix + "sightline")
        exactTime = s.frame.medianSeconds;
    std::cout << std::left << std::setw(34) << r.method << std::right << std::setw(11)
              << fixed(r.frame.medianSeconds, 4) << std::setw(10) << fixed(r.frame.medianSeconds / exactTime, 2)
              << std::setw(10) << fixed(r.error.rgbMeanAbsDiff, 3) << std::setw(10)
              << fixed(r.error.coverageDiffPercent, 3) << std::setw(11) << fixed(r.buildSeconds, 3)
              << std::setw(10) << fixed(r.bytesPerPrimitive, 0) << "\n";
  }
}

//------------------------------------------------------------------------------
std::vector<MethodResult> runSHGlyphScene(const Options& options, long long count, MachineDescription&)
{
  logProgress("sh-glyphs: generating " + std::to_string(count) + " glyphs per data set");
  auto [k4, k8] = makeSyntheticDatasets(count, options.seed);
  const Dataset dipy = makeDipyDataset(options, count);

  // Single-threaded costs, on the default exact glyphs of each synthetic order.
  std::vector<MicroResult> micro;
  for (const Dataset* dataset : { &k4, &k8 })
  {
    logProgress("sh-glyphs: single-threaded AABB and intersection costs, " + dataset->name);
    const auto glyphs = makeGlyphSet(*dataset, SHGlyphOptions{});
    micro.push_back(measureMicro(*dataset, *glyphs, options.seed + 3));
  }
  writeMicroResults(options, count, micro);

  std::vector<MethodResult> results;
  const std::pair<const Dataset*, const MicroResult*> runs[] = { { &k4, &micro[0] }, { &k8, &micro[1] },
    { &dipy, nullptr } };
  for (const auto& [dataset, m] : runs)
  {
    std::vector<MethodResult> part = dataset->skipReason.empty() ? runDataset(options, *dataset, count, m)
                                                                 : skippedDataset(options, *dataset, count);
    for (MethodResult& r : part)
      results.push_back(std::move(r));
  }
  printSummary(results);
  return results;
}

const SceneRegistration registration{ "sh-glyphs",
  "a 140x140 slice of SH glyphs (Peters et al. 2023, Fig. 1 / Table 1): exact vs ray marching "
  "(100/200 steps, sphere or near-exact boxes) vs icosphere tessellations vs bare boxes, plus "
  "shadows and uncertainty volumes; synthetic k = 4 and k = 8 and DIPY's func_coef tiled; "
  "--tessellation gives icosphere vertex counts (42,162,642,2562 = levels 1-4, the default)",
  { 19600 }, &runSHGlyphScene };
} // namespace
} // namespace sightline_benchmark
