// SPDX-License-Identifier: BSD-3-Clause
// Far from the origin: the same scene placed 0, 1e2, 1e4 and 1e6 primitive sizes away from the
// world origin, with the camera near it, must show the same hits, depths (relative to the
// primitive size) and colours as at the origin, within tolerances that do not grow with the
// distance. Positions go in as a double origin plus float offsets from it; rays are double.
// Each test also prints what the float pipeline of s15 (float positions, float rays) gives for
// the same scene, to show what the tolerances catch.
#include "sightline/core/Camera.h"
#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Renderer.h"
#include "sightline/glyphs/EllipsoidSet.h"
#include "sightline/glyphs/SHGlyphSet.h"
#include "sightline/spheres/SphereSet.h"
#include "sightline/tubes/TubeSet.h"
#include "sightline/volumes/SphericalVolume.h"

#include "glyphs/SHGlyphTestSupport.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

using namespace sightline;

namespace
{
constexpr double kSizesAway[] = { 0.0, 1e2, 1e4, 1e6 };
constexpr int kImageSize = 72;

/// Where the scene goes: `sizesAway` primitive sizes from the origin, off every axis.
dvec3 placement(double sizesAway, double size)
{
  return sizesAway * size * glm::normalize(dvec3(1.0, 0.6, -0.3));
}

/// How positions reach the kernel: a double origin plus float offsets (what this change adds),
/// or float world positions (all that the float API can take, as in s15).
enum class Positions
{
  DoubleOrigin,
  FloatWorld,
};

std::vector<vec3> inWorld(const std::vector<vec3>& local, const dvec3& origin)
{
  std::vector<vec3> world;
  for (const vec3& p : local)
    world.push_back(vec3(origin + dvec3(p)));
  return world;
}

/// A scene in coordinates local to its origin, and the size its errors are measured in.
struct FarScene
{
  std::string name;
  double size = 1.0;
  std::function<std::shared_ptr<Geometry>(const dvec3& origin, Positions)> build;
  enum class Drawn
  {
    Opaque,
    Translucent, ///< as a translucent union (RenderOptions::translucent)
    Volume,      ///< as a homogeneous volume in front of an opaque backdrop
  } drawn = Drawn::Opaque;
};

CameraParameters cameraNear(const dvec3& origin, double size)
{
  CameraParameters p;
  p.position = origin + size * dvec3(1.2, 1.9, 9.0);
  p.focalPoint = origin + size * dvec3(0.1, -0.05, 0.0);
  p.viewAngle = 30.0;
  p.nearClip = 0.5 * size;
  p.farClip = 60.0 * size;
  return p;
}

Framebuffer renderAt(const FarScene& s, const dvec3& origin, Positions positions)
{
  const CameraParameters parameters = cameraNear(origin, s.size);
  const Camera camera = Camera::fromParameters(parameters, kImageSize, kImageSize);
  // A headlight and a side light whose shadows the primitives cast on each other.
  Lighting lighting =
    Lighting::headlight(vec3(glm::normalize(parameters.focalPoint - parameters.position)));
  lighting.lights.push_back({ glm::normalize(vec3(-1.0f, -0.5f, -0.6f)) });
  std::shared_ptr<Geometry> geometry = s.build(origin, positions);
  EmbreeScene opaque, other;
  RenderOptions options;
  if (s.drawn == FarScene::Drawn::Opaque)
  {
    opaque.add(geometry);
    options.shadows.mode = ShadowMode::Hard;
  }
  else
  {
    other.add(geometry);
    other.commit();
    if (s.drawn == FarScene::Drawn::Translucent)
    {
      geometry->material.opacity = 0.45f;
      options.translucent.scene = &other;
    }
    else
    {
      options.volumes.scene = &other;
      options.volumes.extinction = float(0.8 / s.size);
      const dvec3 backdropCentre(0.0, 0.0, -6.0 * s.size);
      opaque.add(positions == Positions::DoubleOrigin
          ? std::make_shared<SphereSet>(origin, std::vector<vec3>{ vec3(backdropCentre) },
              std::vector<float>{ float(4.0 * s.size) })
          : std::make_shared<SphereSet>(inWorld({ vec3(backdropCentre) }, origin),
              std::vector<float>{ float(4.0 * s.size) }));
    }
  }
  opaque.commit();
  Framebuffer fb;
  Renderer().render(opaque, camera, lighting, fb, options);
  return fb;
}

/// Differences of an image from the one at the origin.
struct ImageDifference
{
  std::size_t hitMismatches = 0;
  std::size_t hits = 0;
  double depth = 0.0; ///< largest |distance - distance at the origin| / size
  double color = 0.0; ///< largest colour or opacity difference
};

ImageDifference compare(const Framebuffer& reference, const Framebuffer& image, double size)
{
  ImageDifference d;
  for (std::size_t i = 0; i < reference.pixelCount(); ++i)
  {
    const bool a = reference.Depth[i] < 1.0f, b = image.Depth[i] < 1.0f;
    d.hits += a;
    if (a != b)
    {
      ++d.hitMismatches;
      continue;
    }
    if (!a)
      continue;
    d.depth = std::max(d.depth, std::abs(double(image.Distance[i]) - reference.Distance[i]) / size);
    for (int c = 0; c < 4; ++c)
      d.color = std::max(d.color, std::abs(double(image.Color[i][c]) - reference.Color[i][c]));
  }
  return d;
}

/// The s15 pipeline for comparison: float world positions and the float rounding of each pixel's
/// ray, traced through the float API (first-hit distance, first union surface, or the length
/// inside the volume; infinity where nothing). Spheres are intersected in double here, so for
/// them this understates s15's error.
std::vector<double> floatPipeline(const FarScene& s, const dvec3& origin)
{
  const Camera camera = Camera::fromParameters(cameraNear(origin, s.size), kImageSize, kImageSize);
  EmbreeScene scene;
  scene.add(s.build(origin, Positions::FloatWorld));
  scene.commit();
  std::vector<double> result(std::size_t(kImageSize) * kImageSize, kInfinity);
  std::vector<InsideInterval> intervals;
  std::vector<UnionSurface> surfaces;
  for (int y = 0; y < kImageSize; ++y)
    for (int x = 0; x < kImageSize; ++x)
    {
      const Ray ray = camera.primaryRay(x + 0.5, y + 0.5);
      double& out = result[std::size_t(y) * kImageSize + std::size_t(x)];
      if (s.drawn == FarScene::Drawn::Opaque)
      {
        RTCRayHit rh = makeRayHit(ray);
        if (scene.intersect(rh))
          out = rh.ray.tfar;
      }
      else if (s.drawn == FarScene::Drawn::Translucent)
      {
        intervals.clear();
        scene.insideIntervals(ray, intervals);
        unionSurfaces(intervals, ray.tnear, ray.tfar, 0.0, surfaces);
        if (!surfaces.empty())
          out = surfaces.front().t;
      }
      else
      {
        float entry = kInfinity;
        const double inside = scene.insideLength(ray, entry);
        if (inside > 0.0)
          out = inside;
      }
    }
  return result;
}

/// Largest |a - b| / size over pixels where both are finite, and the pixels where only one is.
std::pair<double, std::size_t> valueDifference(const std::vector<double>& a, const std::vector<double>& b, double size)
{
  double worst = 0.0;
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    if (std::isfinite(a[i]) != std::isfinite(b[i]))
      ++mismatches;
    else if (std::isfinite(a[i]))
      worst = std::max(worst, std::abs(a[i] - b[i]) / size);
  }
  return { worst, mismatches };
}

/// Renders at every distance and checks the differences from the origin's image; prints what
/// float positions and rays (the s15 pipeline) give next to them.
void expectSameAsAtOrigin(const FarScene& s, double depthTolerance, double colorTolerance)
{
  const Framebuffer atOrigin = renderAt(s, dvec3(0.0), Positions::DoubleOrigin);
  for (double sizesAway : kSizesAway)
  {
    const dvec3 origin = placement(sizesAway, s.size);
    const ImageDifference d = compare(atOrigin, renderAt(s, origin, Positions::DoubleOrigin), s.size);
    EXPECT_GT(d.hits, std::size_t(kImageSize * kImageSize / 10)) << s.name;
    EXPECT_EQ(d.hitMismatches, 0u) << s.name << " at " << sizesAway << " sizes";
    EXPECT_LE(d.depth, depthTolerance) << s.name << " at " << sizesAway << " sizes";
    EXPECT_LE(d.color, colorTolerance) << s.name << " at " << sizesAway << " sizes";
    // Float positions with double rays: what the mappers give until they pass a double origin.
    const ImageDifference floatData = compare(atOrigin, renderAt(s, origin, Positions::FloatWorld), s.size);
    const auto old = valueDifference(floatPipeline(s, dvec3(0.0)), floatPipeline(s, origin), s.size);
    std::printf("%-20s %6.0e sizes | double: %zu of %zu hits differ, depth %.1e, colour %.1e | "
                "float positions: %zu differ, depth %.1e, colour %.1e | float pipeline (s15): "
                "%zu differ, %s %.1e\n",
      s.name.c_str(), sizesAway, d.hitMismatches, d.hits, d.depth, d.color, floatData.hitMismatches,
      floatData.depth, floatData.color, old.second,
      s.drawn == FarScene::Drawn::Volume ? "inside length" : "depth", old.first);
  }
}

std::vector<vec3> gridOfCentres(int nx, int ny, int nz, float spacing)
{
  std::vector<vec3> centres;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        centres.push_back(spacing * vec3(i - 0.5f * (nx - 1), j - 0.5f * (ny - 1), -float(k)));
  return centres;
}

FarScene spheres()
{
  FarScene s{ "spheres", 1.0, {} };
  s.build = [](const dvec3& origin, Positions positions) -> std::shared_ptr<Geometry>
  {
    // Overlapping neighbours (spacing below the diameter) give intersection curves too.
    const std::vector<vec3> local = gridOfCentres(3, 3, 2, 1.9f);
    std::vector<float> radii(local.size(), 1.0f);
    radii[4] = 0.6f;
    if (positions == Positions::DoubleOrigin)
      return std::make_shared<SphereSet>(origin, local, radii);
    return std::make_shared<SphereSet>(inWorld(local, origin), radii);
  };
  return s;
}

/// The grid: 2 x 2 glyphs of order `order` with radius 1.1, fibre-like lobes.
FarScene shGlyphs(int order, SHIntersectionMethod method, const std::string& name)
{
  FarScene s{ name, 1.1, {} };
  s.build = [order, method](const dvec3& origin, Positions positions) -> std::shared_ptr<Geometry>
  {
    const std::vector<vec3> local = gridOfCentres(2, 2, 1, 2.4f);
    std::vector<float> coefficients;
    const std::vector<std::vector<dvec3>> fibres = { { dvec3(1, 0.2, 0.1) },
      { dvec3(1, 0, 0), dvec3(0.1, 1, 0.3) }, { dvec3(0.3, 0.2, 1), dvec3(1, -0.5, 0) },
      { dvec3(1, 1, 0), dvec3(-1, 1, 0.2), dvec3(0, 0.1, 1) } };
    SHGlyphOptions options;
    options.convention = SHConvention::fromName("canonical", false);
    options.method = method;
    for (const auto& f : fibres)
    {
      const std::vector<double> b = sightline_test::glyph::fibreLobeCoefficients(order, f, 0.15, 12.0);
      std::vector<float> glyph(b.begin(), b.end());
      const double scale = 1.1 / shMaxAmplitude(order, glyph.data(), options.convention);
      for (float c : glyph)
        coefficients.push_back(float(c * scale));
    }
    if (positions == Positions::DoubleOrigin)
      return std::make_shared<SHGlyphSet>(origin, local, coefficients, order, options);
    return std::make_shared<SHGlyphSet>(inWorld(local, origin), coefficients, order, options);
  };
  return s;
}

FarScene ellipsoids()
{
  FarScene s{ "ellipsoids", 1.0, {} };
  s.build = [](const dvec3& origin, Positions positions) -> std::shared_ptr<Geometry>
  {
    const std::vector<vec3> local = gridOfCentres(2, 2, 1, 2.2f);
    std::vector<dmat3> axes;
    for (int i = 0; i < 4; ++i)
    {
      const dmat3 rotation = dmat3(glm::rotate(glm::dmat4(1.0), 0.7 * i + 0.3, glm::normalize(dvec3(1, i, 2))));
      axes.push_back(rotation * dmat3(glm::scale(glm::dmat4(1.0), dvec3(1.0, 0.55 + 0.1 * i, 0.3))));
    }
    if (positions == Positions::DoubleOrigin)
      return std::make_shared<EllipsoidSet>(origin, local, axes);
    return std::make_shared<EllipsoidSet>(inWorld(local, origin), axes);
  };
  return s;
}

/// A branching tube: radii 0.25 to 0.5 (size 0.4), links longer and shorter than their radii.
FarScene tubes(FarScene::Drawn drawn, const std::string& name)
{
  FarScene s{ name, 0.4, {} };
  s.drawn = drawn;
  s.build = [](const dvec3& origin, Positions positions) -> std::shared_ptr<Geometry>
  {
    const std::vector<vec3> local = { vec3(-2.5f, -1.0f, 0.0f), vec3(-1.2f, -0.4f, 0.3f),
      vec3(-0.2f, 0.1f, 0.0f), vec3(0.1f, 0.2f, -0.1f), vec3(1.4f, 1.1f, 0.2f), vec3(2.4f, 1.6f, -0.5f),
      vec3(1.3f, -0.9f, 0.4f), vec3(2.5f, -1.5f, 0.0f) };
    const std::vector<float> radii = { 0.3f, 0.45f, 0.5f, 0.42f, 0.3f, 0.25f, 0.35f, 0.28f };
    const std::vector<std::int64_t> predecessors = { -1, 0, 1, 2, 3, 4, 3, 6 };
    if (positions == Positions::DoubleOrigin)
      return std::make_shared<TubeSet>(origin, local, radii, predecessors);
    return std::make_shared<TubeSet>(inWorld(local, origin), radii, predecessors);
  };
  return s;
}
} // namespace

// Tolerances: depths to 1e-6 of the primitive size (the float framebuffer stores distances ~10
// sizes from the camera: 6e-7 of a size per rounding); colours to 1e-5 (float shading of normals
// that agree to ~1e-9). Neither depends on the distance from the origin.
// SH glyph roots are found to defaultGlyphTolerance (1e-6 of the glyph size): rays a hair apart
// may stop anywhere in that bracket, so their depths get ten times that.
constexpr double kDepthTolerance = 1e-6;
constexpr double kGlyphDepthTolerance = 10.0 * defaultGlyphTolerance<double>();
constexpr double kColorTolerance = 1e-5;

TEST(FarFromOrigin, Spheres)
{
  expectSameAsAtOrigin(spheres(), kDepthTolerance, kColorTolerance);
}

TEST(FarFromOrigin, SHGlyphs)
{
  expectSameAsAtOrigin(shGlyphs(8, SHIntersectionMethod::RootFinding, "SH glyphs k=8"),
    kGlyphDepthTolerance, kColorTolerance);
}

TEST(FarFromOrigin, TensorGlyphs)
{
  // The tensor glyph paper's method on an order-4 glyph: a marching baseline, but its frame and
  // ray are the same as the exact method's, so it must not depend on the distance either.
  expectSameAsAtOrigin(shGlyphs(4, SHIntersectionMethod::TensorMarching, "tensor glyphs k=4"),
    kDepthTolerance, kColorTolerance);
}

TEST(FarFromOrigin, Ellipsoids)
{
  expectSameAsAtOrigin(ellipsoids(), kDepthTolerance, kColorTolerance);
}

TEST(FarFromOrigin, OpaqueTubes)
{
  expectSameAsAtOrigin(tubes(FarScene::Drawn::Opaque, "tubes"), kDepthTolerance, kColorTolerance);
}

TEST(FarFromOrigin, TranslucentTubeUnion)
{
  expectSameAsAtOrigin(tubes(FarScene::Drawn::Translucent, "translucent tubes"), kDepthTolerance,
    kColorTolerance);
}

TEST(FarFromOrigin, SHGlyphVolume)
{
  FarScene s = shGlyphs(4, SHIntersectionMethod::RootFinding, "SH glyph volume k=4");
  s.drawn = FarScene::Drawn::Volume;
  expectSameAsAtOrigin(s, kGlyphDepthTolerance, kColorTolerance);
}

namespace
{
/// A camera near a grid placed at `origin`: the grid's coordinates map to clip space through
/// the grid-to-world translation, as the volume renderers take it.
Camera gridCamera(const dvec3& origin)
{
  CameraParameters p;
  p.position = origin + dvec3(0.3, -0.2, 9.0);
  p.focalPoint = origin;
  p.viewAngle = 30.0;
  p.nearClip = 0.5;
  p.farClip = 60.0;
  const dmat4 gridToWorld = glm::translate(dmat4(1.0), origin);
  return Camera(Camera::worldToClipMatrix(p, 1.0) * gridToWorld, 64, 64);
}

/// Length inside the sphere of `radius` around the grid's centre of the line o + t d (d unit).
double sphereChord(const dvec3& o, const dvec3& d, double radius)
{
  const dvec3 closest = o - glm::dot(o, d) * d;
  const double b2 = glm::dot(closest, closest);
  return b2 < radius * radius ? 2.0 * std::sqrt(radius * radius - b2) : 0.0;
}

/// Length of o + t d (d unit, t >= 0) inside the finite cylinder rho < radius, z0 < z < z1.
double cylinderChord(const dvec3& o, const dvec3& d, double radius, double z0, double z1)
{
  double t0 = 0.0, t1 = 1e300;
  const double a = d.x * d.x + d.y * d.y;
  const double b = o.x * d.x + o.y * d.y;
  // rho^2 = radius^2 along the line, via its closest approach to the axis (no cancellation).
  const double rho2 = o.x * o.x + o.y * o.y - b * b / a;
  if (!(rho2 < radius * radius))
    return 0.0;
  const double half = std::sqrt((radius * radius - rho2) / a);
  t0 = std::max(t0, -b / a - half);
  t1 = std::min(t1, -b / a + half);
  const double za = (z0 - o.z) / d.z, zb = (z1 - o.z) / d.z;
  t0 = std::max(t0, std::min(za, zb));
  t1 = std::min(t1, std::max(za, zb));
  return std::max(0.0, t1 - t0);
}

/// Renders the grid at every distance and compares each pixel's opacity with the closed form
/// along its exact (double) pixel ray and with the image at the origin; prints what the float
/// pixel ray (s15) gives for the closed form.
void expectExactVolume(const char* name, double extinction,
  const std::function<void(const Camera&, Framebuffer&)>& render,
  const std::function<double(const dvec3&, const dvec3&)>& opticalPath)
{
  Framebuffer atOrigin;
  render(gridCamera(dvec3(0.0)), atOrigin);
  for (double sizesAway : kSizesAway)
  {
    const Camera camera = gridCamera(placement(sizesAway, 1.0));
    Framebuffer fb;
    render(camera, fb);
    double worst = 0.0, fromOrigin = 0.0, floatRay = 0.0;
    int inside = 0;
    for (int y = 0; y < camera.height(); ++y)
      for (int x = 0; x < camera.width(); ++x)
      {
        const DoubleRay ray = camera.doublePrimaryRay(x + 0.5, y + 0.5);
        const double path = opticalPath(ray.origin, ray.direction);
        const std::size_t i = fb.index(x, y);
        inside += path > 0.0;
        worst = std::max(worst, std::abs(fb.Color[i].a - (1.0 - std::exp(-extinction * path))));
        fromOrigin = std::max(fromOrigin, double(std::abs(fb.Color[i].a - atOrigin.Color[i].a)));
        const Ray rounded = camera.primaryRay(x + 0.5, y + 0.5);
        if (path > 0.0)
          floatRay = std::max(floatRay,
            std::abs(opticalPath(dvec3(rounded.origin), dvec3(rounded.direction)) - path) / path);
      }
    EXPECT_GT(inside, 64 * 64 / 4) << name;
    EXPECT_LE(worst, 1e-6) << name << " at " << sizesAway << " sizes";
    EXPECT_LE(fromOrigin, 1e-6) << name << " at " << sizesAway << " sizes";
    std::printf("%-20s %6.0e sizes | opacity vs closed form %.1e, vs origin %.1e | float pixel "
                "ray (s15): optical depth off by %.1e relative\n",
      name, sizesAway, worst, fromOrigin, floatRay);
  }
}
} // namespace

// Volumes: the renderers trace the grid's own coordinates, so the distance enters only through
// the camera matrix (in double); what float rays cost is at tangents, at any distance.
TEST(FarFromOrigin, SphericalVolume)
{
  const SphericalGrid grid{ { 0.0, 0.6, 1.2, 2.0 }, { 0.0, 0.7, kPi / 2, 2.4, kPi },
    { -kPi, -1.0, 0.5, kPi } };
  const SphericalTraversal traversal(grid);
  // Extinction in the shell 1.2 <= r <= 2 (radial cells 2 and up; r varies fastest in the order).
  const double k = 0.7;
  std::vector<TransferSample> cells(grid.cellCount(), TransferSample{ vec3(0.2f, 0.6f, 1.0f), 0.0 });
  for (std::size_t c = 0; c < cells.size(); ++c)
    cells[c].extinction = c % std::size_t(grid.radialCells()) >= 2 ? k : 0.0;
  expectExactVolume("spherical volume", k,
    [&](const Camera& camera, Framebuffer& fb) { renderSphericalVolume(traversal, cells, camera, fb); },
    [](const dvec3& o, const dvec3& d) { return sphereChord(o, d, 2.0) - sphereChord(o, d, 1.2); });
}

TEST(FarFromOrigin, CylindricalVolume)
{
  const CylindricalGrid grid{ { 0.0, 0.8, 1.5 }, { -kPi, 0.0, 1.5, kPi }, { -1.0, 0.0, 1.2 } };
  const CylindricalTraversal traversal(grid);
  const double k = 0.9;
  const std::vector<TransferSample> cells(grid.cellCount(), TransferSample{ vec3(1.0f, 0.5f, 0.2f), k });
  expectExactVolume("cylindrical volume", k,
    [&](const Camera& camera, Framebuffer& fb) { renderCylindricalVolume(traversal, cells, camera, fb); },
    [](const dvec3& o, const dvec3& d) { return cylinderChord(o, d, 1.5, -1.0, 1.2); });
}

// Beyond what Embree's float rays can hold (|coordinate| > 1.844e18, e.g. a corrupt NIfTI
// affine): a camera that far from a sphere at the origin (a scene Embree holds) gives primary
// rays Embree would reject with an assertion that aborts the process; they are traced as
// disabled rays and miss, in packets and single rays alike.
TEST(FarFromOrigin, BeyondEmbreesRangeMissesInsteadOfAborting)
{
  EmbreeScene scene;
  scene.add(std::make_shared<SphereSet>(std::vector<vec3>{ vec3(0.0f) }, std::vector<float>{ 1.0f }));
  scene.commit();
  for (const double away : { 3e18, 5e19 })
  {
    for (const bool parallel : { false, true })
    {
      CameraParameters parameters;
      parameters.position = dvec3(0.0, away, 0.0);
      parameters.focalPoint = dvec3(0.0);
      parameters.viewUp = dvec3(0.0, 0.0, 1.0);
      parameters.nearClip = 0.01 * away; // rays start 0.99 * away from the origin
      parameters.farClip = 2.0 * away;
      parameters.parallelProjection = parallel;
      parameters.parallelScale = 2.0;
      const Camera camera = Camera::fromParameters(parameters, 32, 24);
      Framebuffer fb;
      Renderer().render(scene, camera, Lighting(), fb, RenderOptions());
      for (std::size_t i = 0; i < fb.pixelCount(); ++i)
      {
        ASSERT_EQ(fb.Color[i].a, 0.0f) << "a ray from " << away << " hit";
      }
      SceneHit hit;
      EXPECT_FALSE(scene.intersect(camera.doublePrimaryRay(16.0, 12.0), hit));
    }
  }
}
