// SPDX-License-Identifier: BSD-3-Clause
// EmbreeScene + Renderer against analytic spheres: coverage, depth, distance and shading are all
// predicted per pixel from the reference camera matrix and the long double ray-sphere solution.
#include "KernelTestSupport.h"

#include "sightline/core/Renderer.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace
{
using namespace sightline_test;
using sightline::Camera;
using sightline::CameraParameters;
using sightline::EmbreeScene;
using sightline::Framebuffer;
using sightline::Lighting;
using sightline::Material;
using sightline::Renderer;
using sightline::SphereSet;
using sightline::vec3;
using sightline::vec4;

using sightline::kPi;

struct Sphere
{
  dvec3 center;
  double radius;
};

/// The exact primary ray of pixel (x, y), from the reference matrix: unit direction, starting on
/// the near plane.
struct ReferenceRay
{
  dvec3 origin;
  dvec3 direction;
};

ReferenceRay referenceRay(const View& view, const Matrix4& worldToClip, int x, int y)
{
  const dvec3 nearPoint =
    referenceUnproject(worldToClip, x + 0.5L, y + 0.5L, 0, view.width, view.height);
  const dvec3 farPoint =
    referenceUnproject(worldToClip, x + 0.5L, y + 0.5L, 1, view.width, view.height);
  return { nearPoint, glm::normalize(farPoint - nearPoint) };
}

/// Distance from a sphere's centre to the ray's line, relative to the radius (< 1: the line hits).
double relativeLineDistance(const ReferenceRay& ray, const Sphere& sphere)
{
  const dvec3 f = sphere.center - ray.origin;
  return glm::length(f - glm::dot(f, ray.direction) * ray.direction) / sphere.radius;
}

std::shared_ptr<SphereSet> sphereSet(const std::vector<Sphere>& spheres,
                                     const std::vector<std::uint32_t>& colors = {},
                                     const Material& material = {})
{
  std::vector<vec3> centers;
  std::vector<float> radii;
  for (const Sphere& s : spheres)
  {
    centers.emplace_back(s.center);
    radii.push_back(float(s.radius));
  }
  auto set = std::make_shared<SphereSet>(centers, radii, 1.0f, colors);
  set->material = material;
  return set;
}

/// Material that shows a primitive's colour unlit, so colours identify what was hit.
Material flatMaterial()
{
  Material material;
  material.ambient = 1.0f;
  material.diffuse = 0.0f;
  return material;
}

Framebuffer render(const EmbreeScene& scene, const Camera& camera, const Lighting& lighting,
                   const sightline::RenderOptions& options = {})
{
  Framebuffer framebuffer;
  const sightline::RenderStatistics statistics =
    Renderer().render(scene, camera, lighting, framebuffer, options);
  EXPECT_TRUE(statistics.completed);
  std::size_t hits = 0;
  for (const vec4& color : framebuffer.Color)
    hits += color.a > 0.0f;
  EXPECT_EQ(statistics.hits, hits) << "statistics must count the pixels that were hit";
  return framebuffer;
}

bool isHit(const Framebuffer& framebuffer, std::size_t i)
{
  return framebuffer.Color[i].a > 0.0f;
}

// (a) With a parallel camera a sphere covers a disc of radius R = r / pixel size. Pixel centres
// inside a circle of radius R number pi R^2 up to the pixels the boundary crosses: their squares
// lie between the discs of radius R -+ sqrt(2)/2, so |count - pi R^2| <= pi (sqrt(2) R + 1/2).
// Per pixel, the hit must match the analytic line distance wherever that is not on the edge.
TEST(Renderer, ParallelViewOfASphereCoversItsDisc)
{
  const View view = parallelView(161, 121);
  const Sphere sphere{ { 0.0123, -0.0217, 0.4 }, 1.3 };
  const auto scene = makeScene(sphereSet({ sphere }));
  const Framebuffer framebuffer =
    render(*scene, view.camera(), Lighting::headlight(view.viewDirection()));

  const double pixelSize = 2 * view.parameters.parallelScale / view.height;
  const double radiusInPixels = sphere.radius / pixelSize;
  const double discArea = kPi * radiusInPixels * radiusInPixels;
  const double boundaryTolerance = kPi * (std::sqrt(2.0) * radiusInPixels + 0.5);
  std::size_t hits = 0;
  const Matrix4 worldToClip = view.reference();
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x)
    {
      const bool hit = isHit(framebuffer, framebuffer.index(x, y));
      hits += hit;
      const double distance = relativeLineDistance(referenceRay(view, worldToClip, x, y), sphere);
      if (std::fabs(distance - 1) > 1e-4)
      {
        EXPECT_EQ(hit, distance < 1) << "pixel (" << x << ", " << y << ")";
      }
    }
  EXPECT_NEAR(double(hits), discArea, boundaryTolerance);
}

// (b) The centre pixel looks at the sphere's centre: it sees the front point c + r * toEye.
class CentrePixelTest : public ::testing::TestWithParam<bool>
{
};

TEST_P(CentrePixelTest, DepthAndDistanceOfTheFrontPoint)
{
  const bool parallel = GetParam();
  const Sphere sphere{ { 0.5, -0.2, 0.1 }, 0.9 };
  View view = parallel ? parallelView(161, 121) : perspectiveView(161, 121, sphere.center);
  if (parallel) // centre the parallel view on the sphere too
  {
    view.parameters.focalPoint = sphere.center;
    view.parameters.position = sphere.center + dvec3(0, 0, 10);
  }
  const auto scene = makeScene(sphereSet({ sphere }));
  const Framebuffer framebuffer =
    render(*scene, view.camera(), Lighting::headlight(view.viewDirection()));

  const dvec3 toEye = glm::normalize(view.parameters.position - sphere.center);
  const dvec3 frontPoint = sphere.center + sphere.radius * toEye;
  const double expectedDepth =
    double(referenceProject(view.reference(), frontPoint, view.width, view.height).depth);
  // The centre ray runs along the view axis, starting on the near plane.
  const double expectedDistance =
    glm::length(view.parameters.position - frontPoint) - view.parameters.nearClip;

  const std::size_t centre = framebuffer.index(view.width / 2, view.height / 2);
  ASSERT_TRUE(isHit(framebuffer, centre));
  EXPECT_NEAR(framebuffer.Depth[centre], expectedDepth, 1e-6);
  EXPECT_NEAR(framebuffer.Distance[centre], expectedDistance, 1e-5 * expectedDistance);
}

INSTANTIATE_TEST_SUITE_P(Projections, CentrePixelTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& info)
                         { return info.param ? "Parallel" : "Perspective"; });

// (b, c) Every pixel of a lit sphere: depth, distance and Lambert shading under a headlight
// against the analytic hit. Pixels within 1e-3 r of the silhouette are skipped (their normal is
// ill-conditioned); the perspective view is off-centre so that some front-facing points turn away
// from the headlight and must come out black.
class ShadedSphereTest : public ::testing::TestWithParam<bool>
{
};

TEST_P(ShadedSphereTest, EveryPixelMatchesTheAnalyticSphere)
{
  const bool parallel = GetParam();
  View view = parallel ? parallelView(150, 110) : perspectiveView(150, 110, { 0, 0, 0 });
  Sphere sphere{ { 0.3, 0.2, -0.5 }, 1.1 };
  if (!parallel)
  {
    // About 20 degrees off the axis of a wide view: a visible band near the outer silhouette
    // faces away from the headlight.
    view.parameters.viewAngle = 60.0;
    const dvec3 side =
      glm::normalize(glm::cross(dvec3(view.viewDirection()), view.parameters.viewUp));
    sphere = { view.parameters.focalPoint + 4.0 * side, 2.0 };
  }
  Material material; // diffuse 1, ambient 0, no specular
  material.color = vec3(0.8f, 0.5f, 0.2f);
  const auto scene = makeScene(sphereSet({ sphere }, {}, material));
  const vec3 lightDirection = view.viewDirection();
  const Framebuffer framebuffer =
    render(*scene, view.camera(), Lighting::headlight(lightDirection));

  const Matrix4 worldToClip = view.reference();
  int checked = 0, unlit = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x)
    {
      const ReferenceRay ray = referenceRay(view, worldToClip, x, y);
      if (relativeLineDistance(ray, sphere) > 1 - 1e-3)
        continue;
      const std::size_t i = framebuffer.index(x, y);
      const auto t = referenceSphereHit(ray.origin, ray.direction, sphere.center, sphere.radius);
      ASSERT_TRUE(t.has_value());
      ASSERT_TRUE(isHit(framebuffer, i)) << "pixel (" << x << ", " << y << ")";
      const dvec3 point = ray.origin + double(*t) * ray.direction;
      const dvec3 normal = (point - sphere.center) / sphere.radius;
      const double lambert = std::max(0.0, -glm::dot(normal, dvec3(lightDirection)));
      unlit += lambert == 0.0;
      ++checked;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(framebuffer.Color[i][c], lambert * material.color[c], 1e-4)
          << "pixel (" << x << ", " << y << "), channel " << c;
      EXPECT_EQ(framebuffer.Color[i].a, 1.0f);
      EXPECT_NEAR(framebuffer.Depth[i],
                  double(referenceProject(worldToClip, point, view.width, view.height).depth),
                  1e-6);
      EXPECT_NEAR(framebuffer.Distance[i], double(*t), 1e-5 * double(*t));
    }
  EXPECT_GT(checked, 1000);
  if (!parallel)
  {
    EXPECT_GT(unlit, 0) << "the view should include points facing away from the headlight";
  }
}

INSTANTIATE_TEST_SUITE_P(Projections, ShadedSphereTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& info)
                         { return info.param ? "Parallel" : "Perspective"; });

// From inside a sphere the far side is seen from behind its outward normal: VTK's two-sided
// lighting flips the normal towards the viewer, so the inside is lit with |n.l|.
TEST(Renderer, InsideOfASphereIsLitTwoSided)
{
  View view = parallelView(60, 50);
  view.parameters.farClip = 40.0;
  const Sphere sphere{ { 0.2, -0.1, 0.0 }, 12.0 }; // encloses the camera and its near plane
  Material material;
  material.color = vec3(0.9f, 0.6f, 0.3f);
  const auto scene = makeScene(sphereSet({ sphere }, {}, material));
  const vec3 lightDirection = view.viewDirection();
  const Framebuffer framebuffer =
    render(*scene, view.camera(), Lighting::headlight(lightDirection));

  const Matrix4 worldToClip = view.reference();
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x)
    {
      const ReferenceRay ray = referenceRay(view, worldToClip, x, y);
      const auto t = referenceSphereHit(ray.origin, ray.direction, sphere.center, sphere.radius);
      ASSERT_TRUE(t.has_value());
      const dvec3 normal =
        (ray.origin + double(*t) * ray.direction - sphere.center) / sphere.radius;
      const double lambert = std::fabs(glm::dot(normal, dvec3(lightDirection)));
      const std::size_t i = framebuffer.index(x, y);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(framebuffer.Color[i][c], lambert * material.color[c], 1e-4)
          << "pixel (" << x << ", " << y << "), channel " << c;
      EXPECT_NEAR(framebuffer.Distance[i], double(*t), 1e-5 * double(*t));
    }
}

// (d) Two interpenetrating spheres, in one geometry or in two: per pixel the nearer analytic hit
// decides the colour. Pixels near either silhouette or near the intersection curve are skipped.
class OverlappingSpheresTest : public ::testing::TestWithParam<bool>
{
};

TEST_P(OverlappingSpheresTest, NearerSphereWinsEachPixel)
{
  const bool separateGeometries = GetParam();
  const View view = perspectiveView(140, 100, { 0, 0, 0 });
  const std::vector<Sphere> spheres{ { { -0.4, 0.1, 0.2 }, 1.0 }, { { 0.5, -0.1, -0.3 }, 1.2 } };
  const std::vector<std::uint32_t> colors{ sightline::packRGBA8(255, 0, 0),
                                           sightline::packRGBA8(0, 255, 0) };

  auto scene = std::make_unique<EmbreeScene>();
  if (separateGeometries)
  {
    scene->add(sphereSet({ spheres[0] }, { colors[0] }, flatMaterial()));
    scene->add(sphereSet({ spheres[1] }, { colors[1] }, flatMaterial()));
  }
  else
    scene->add(sphereSet(spheres, colors, flatMaterial()));
  scene->commit();
  const Framebuffer framebuffer =
    render(*scene, view.camera(), Lighting::headlight(view.viewDirection()));
  // The same frame with the primitive of each pixel recorded (for picking): identical colours,
  // and the plain frame records none.
  sightline::RenderOptions withIds;
  withIds.primitiveIds = true;
  const Framebuffer identified =
    render(*scene, view.camera(), Lighting::headlight(view.viewDirection()), withIds);
  EXPECT_TRUE(framebuffer.Primitives.empty());
  ASSERT_EQ(identified.Primitives.size(), identified.pixelCount());
  EXPECT_EQ(identified.Color, framebuffer.Color);
  EXPECT_EQ(identified.Depth, framebuffer.Depth);

  const Matrix4 worldToClip = view.reference();
  int winners[2] = { 0, 0 };
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x)
    {
      const ReferenceRay ray = referenceRay(view, worldToClip, x, y);
      std::optional<long double> t[2];
      bool edge = false;
      for (int s = 0; s < 2; ++s)
      {
        edge |= std::fabs(relativeLineDistance(ray, spheres[s]) - 1) < 1e-3;
        t[s] = referenceSphereHit(ray.origin, ray.direction, spheres[s].center, spheres[s].radius);
      }
      if (edge || (t[0] && t[1] && std::fabs(*t[0] - *t[1]) < 1e-4L * *t[0]))
        continue;
      const std::size_t i = framebuffer.index(x, y);
      if (!t[0] && !t[1])
      {
        EXPECT_FALSE(isHit(framebuffer, i)) << "pixel (" << x << ", " << y << ")";
        EXPECT_FALSE(identified.Primitives[i].hit()) << "pixel (" << x << ", " << y << ")";
        continue;
      }
      const int nearer = !t[1] ? 0 : !t[0] ? 1 : (*t[0] < *t[1] ? 0 : 1);
      const sightline::PixelPrimitive expectedPrimitive = separateGeometries
        ? sightline::PixelPrimitive{ std::uint32_t(nearer), 0u }
        : sightline::PixelPrimitive{ 0u, std::uint32_t(nearer) };
      EXPECT_EQ(identified.Primitives[i].geometry, expectedPrimitive.geometry)
        << "pixel (" << x << ", " << y << ")";
      EXPECT_EQ(identified.Primitives[i].primitive, expectedPrimitive.primitive)
        << "pixel (" << x << ", " << y << ")";
      ++winners[nearer];
      const vec4 expected = nearer == 0 ? vec4(1, 0, 0, 1) : vec4(0, 1, 0, 1);
      EXPECT_EQ(framebuffer.Color[i], expected) << "pixel (" << x << ", " << y << ")";
    }
  EXPECT_GT(winners[0], 100);
  EXPECT_GT(winners[1], 100);
}

INSTANTIATE_TEST_SUITE_P(Layouts, OverlappingSpheresTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& info)
                         { return info.param ? "TwoGeometries" : "OneGeometry"; });

// (e) Nothing to trace: the framebuffer is sized to the camera and cleared, even if it held an
// earlier image.
TEST(Renderer, EmptySceneRendersNothing)
{
  const View view = parallelView(40, 30);
  EmbreeScene empty;
  empty.commit();
  EmbreeScene allRejected; // a geometry whose every sphere was invalid
  allRejected.add(std::make_shared<SphereSet>(std::vector<vec3>{ vec3(0.0f), vec3(1.0f) },
                                              std::vector<float>{ -1.0f, 0.0f }));
  allRejected.commit();
  for (const EmbreeScene* scene : { &empty, &allRejected })
  {
    Framebuffer framebuffer(3, 3);
    std::fill(framebuffer.Color.begin(), framebuffer.Color.end(), vec4(1.0f));
    std::fill(framebuffer.Depth.begin(), framebuffer.Depth.end(), 0.5f);
    const auto statistics = Renderer().render(
      *scene, view.camera(), Lighting::headlight(view.viewDirection()), framebuffer);
    EXPECT_EQ(statistics.hits, 0u);
    EXPECT_TRUE(statistics.completed);
    ASSERT_EQ(framebuffer.width(), 40);
    ASSERT_EQ(framebuffer.height(), 30);
    for (std::size_t i = 0; i < framebuffer.pixelCount(); ++i)
    {
      EXPECT_EQ(framebuffer.Color[i], vec4(0.0f));
      EXPECT_EQ(framebuffer.Depth[i], 1.0f);
      EXPECT_TRUE(std::isinf(framebuffer.Distance[i]));
    }
  }
}

// (f) A sphere filling the whole view, so every rendered pixel is a hit.
struct FilledView
{
  View view = parallelView(64, 200);
  std::unique_ptr<EmbreeScene> scene = makeScene(sphereSet({ { { 0, 0, -5 }, 4.0 } }));
};

TEST(Renderer, ProgressRisesToOne)
{
  const FilledView filled;
  std::vector<double> fractions;
  sightline::RenderOptions options;
  options.progress = [&](double fraction)
  {
    fractions.push_back(fraction);
    return true;
  };
  Framebuffer framebuffer;
  const auto statistics =
    Renderer().render(*filled.scene, filled.view.camera(),
                      Lighting::headlight(filled.view.viewDirection()), framebuffer, options);
  EXPECT_TRUE(statistics.completed);
  EXPECT_EQ(statistics.hits, framebuffer.pixelCount());
  ASSERT_GE(fractions.size(), 2u) << "a 200-row image should report progress more than once";
  for (std::size_t i = 1; i < fractions.size(); ++i)
    EXPECT_GT(fractions[i], fractions[i - 1]);
  EXPECT_GT(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
}

TEST(Renderer, ProgressReturningFalseStopsEarly)
{
  const FilledView filled;
  int calls = 0;
  sightline::RenderOptions options;
  options.progress = [&](double)
  {
    ++calls;
    return false;
  };
  Framebuffer framebuffer;
  const auto statistics =
    Renderer().render(*filled.scene, filled.view.camera(),
                      Lighting::headlight(filled.view.viewDirection()), framebuffer, options);
  EXPECT_FALSE(statistics.completed);
  EXPECT_EQ(calls, 1);
  // Whole rows were rendered before the stop, the rest stayed cleared.
  std::size_t renderedRows = 0;
  for (int y = 0; y < framebuffer.height(); ++y)
  {
    std::size_t rowHits = 0;
    for (int x = 0; x < framebuffer.width(); ++x)
      rowHits += isHit(framebuffer, framebuffer.index(x, y));
    EXPECT_TRUE(rowHits == 0 || rowHits == std::size_t(framebuffer.width())) << "row " << y;
    for (int x = 0; rowHits == 0 && x < framebuffer.width(); ++x)
      EXPECT_EQ(framebuffer.Depth[framebuffer.index(x, y)], 1.0f);
    renderedRows += rowHits != 0;
  }
  EXPECT_GT(renderedRows, 0u);
  EXPECT_LT(renderedRows, std::size_t(framebuffer.height()));
  EXPECT_EQ(statistics.hits, renderedRows * framebuffer.width());
}

// (g) A sphere given in object coordinates with an actor transform (translation + uniform scale,
// then also a rotation) must look exactly like the transformed sphere given in world coordinates.
// Specular and a second light make the shading depend on the normal and the view vector in world
// space; only the rotation makes a missing normal transform visible.
class ObjectToWorldTest : public ::testing::TestWithParam<bool>
{
};

TEST_P(ObjectToWorldTest, MatchesTheTransformedSphere)
{
  const bool rotate = GetParam();
  const View view = perspectiveView(120, 90, { 1, -1, 0.5 });
  const double scale = 1.8;
  const dvec3 translation(1.5, -2.0, 0.7);
  sightline::dmat4 objectToWorld =
    glm::scale(glm::translate(sightline::dmat4(1.0), translation), dvec3(scale));
  if (rotate)
    objectToWorld = glm::rotate(objectToWorld, 1.1, glm::normalize(dvec3(1, 2, -0.5)));
  const Sphere objectSphere{ { 0.3, -0.2, 0.5 }, 0.7 };
  const Sphere worldSphere{ dvec3(objectToWorld * glm::dvec4(objectSphere.center, 1.0)),
                            scale * objectSphere.radius };

  Material material;
  material.color = vec3(0.3f, 0.6f, 0.9f);
  material.ambient = 0.1f;
  material.diffuse = 0.7f;
  material.specular = 0.5f;
  material.specularPower = 20.0f;
  Lighting lighting = Lighting::headlight(view.viewDirection());
  lighting.lights.push_back(
    { glm::normalize(vec3(-1.0f, -0.5f, -0.2f)), vec3(1.0f, 0.9f, 0.8f), 0.6f });

  const auto objectScene = makeScene(sphereSet({ objectSphere }, {}, material));
  const auto worldScene = makeScene(sphereSet({ worldSphere }, {}, material));
  sightline::RenderOptions options;
  options.objectToWorld = objectToWorld;
  const Framebuffer transformed = render(
    *objectScene, Camera(view.camera().worldToClip() * objectToWorld, view.width, view.height),
    lighting, options);
  const Framebuffer direct = render(*worldScene, view.camera(), lighting);

  std::size_t differing = 0, compared = 0;
  for (std::size_t i = 0; i < direct.pixelCount(); ++i)
  {
    const bool hitBoth = isHit(direct, i) && isHit(transformed, i);
    if (isHit(direct, i) != isHit(transformed, i) ||
        (hitBoth && glm::length(direct.Color[i] - transformed.Color[i]) > 1e-5f))
    {
      ++differing;
      continue;
    }
    if (!hitBoth)
      continue;
    ++compared;
    EXPECT_NEAR(direct.Depth[i], transformed.Depth[i], 1e-6) << "pixel " << i;
    // Distances are world distances whatever the scene's own units.
    EXPECT_NEAR(direct.Distance[i], transformed.Distance[i], 1e-4f * direct.Distance[i])
      << "pixel " << i;
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_LE(differing, 8u) << "only silhouette pixels may differ";
}

INSTANTIATE_TEST_SUITE_P(Transforms, ObjectToWorldTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& info)
                         { return info.param ? "RotateTranslateScale" : "TranslateScale"; });

// (h) Scene bookkeeping, and the BVH's answers against brute force over every sphere.
TEST(EmbreeScene, BuildStatisticsAndBounds)
{
  std::mt19937 random(2718);
  std::uniform_real_distribution<float> position(-20.0f, 20.0f), radius(0.1f, 1.5f);
  std::vector<vec3> centers;
  std::vector<float> radii;
  for (int i = 0; i < 400; ++i)
  {
    centers.emplace_back(position(random), position(random), position(random));
    radii.push_back(radius(random));
  }
  auto spheres = std::make_shared<SphereSet>(centers, radii);
  EmbreeScene scene;
  EXPECT_TRUE(scene.empty());
  EXPECT_EQ(scene.add(spheres), 0u);
  scene.commit();
  EXPECT_FALSE(scene.empty());
  EXPECT_GT(scene.bvhBytes(), 0);
  EXPECT_GE(scene.buildSeconds(), 0.0);
  EXPECT_GE(scene.geometryBytes(), 400 * sizeof(sightline::vec4));

  const sightline::Box3 expected = spheres->bounds();
  const sightline::Box3 bounds = scene.bounds();
  for (int axis = 0; axis < 3; ++axis)
  {
    EXPECT_LE(bounds.lower[axis], expected.lower[axis]);
    EXPECT_GE(bounds.upper[axis], expected.upper[axis]);
    EXPECT_NEAR(bounds.lower[axis], expected.lower[axis], 1e-4);
    EXPECT_NEAR(bounds.upper[axis], expected.upper[axis], 1e-4);
  }
  EXPECT_THROW(scene.add(spheres), std::logic_error) << "adding after commit";
  EmbreeScene other;
  EXPECT_THROW(other.add(nullptr), std::invalid_argument);
}

TEST(EmbreeScene, IntersectFindsTheNearestSphereAndOccludedAgrees)
{
  std::mt19937 random(161803);
  std::uniform_real_distribution<float> position(-10.0f, 10.0f), radius(0.2f, 1.0f),
    unit(0.0f, 1.0f);
  std::vector<vec3> centers;
  std::vector<float> radii;
  for (int i = 0; i < 300; ++i)
  {
    centers.emplace_back(position(random), position(random), position(random));
    radii.push_back(radius(random));
  }
  const auto spheres = std::make_shared<SphereSet>(centers, radii);
  const auto scene = makeScene(spheres);

  int hits = 0, misses = 0;
  for (int i = 0; i < 3000; ++i)
  {
    sightline::Ray ray;
    ray.origin = vec3(position(random), position(random), position(random)) * 1.5f;
    ray.direction = glm::normalize(vec3(position(random), position(random), position(random)));
    ray.tnear = unit(random) < 0.3f ? 5.0f * unit(random) : 0.0f;
    ray.tfar = unit(random) < 0.3f ? ray.tnear + 20.0f * unit(random) : sightline::kInfinity;

    // Brute force with the per-primitive test the BVH calls.
    std::optional<std::pair<float, unsigned>> nearest;
    for (unsigned s = 0; s < spheres->size(); ++s)
    {
      sightline::SurfaceHit hit;
      if (spheres->intersect(s, ray, hit) && (!nearest || hit.t < nearest->first))
        nearest = std::make_pair(hit.t, s);
    }
    RTCRayHit rayhit = sightline::makeRayHit(ray);
    const bool found = scene->intersect(rayhit);
    ASSERT_EQ(found, nearest.has_value()) << "ray " << i;
    EXPECT_EQ(scene->occluded(ray), found) << "ray " << i;
    if (!found)
    {
      ++misses;
      continue;
    }
    ++hits;
    EXPECT_EQ(rayhit.ray.tfar, nearest->first) << "ray " << i;
    EXPECT_EQ(rayhit.hit.primID, nearest->second) << "ray " << i;
    EXPECT_EQ(rayhit.hit.geomID, 0u);
  }
  EXPECT_GT(hits, 300);
  EXPECT_GT(misses, 300);
}
} // namespace
