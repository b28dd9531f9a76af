// SPDX-License-Identifier: BSD-3-Clause
// The tessellated SH glyph baseline (SHGlyphTessellation) and the triangle mesh it produces
// (TriangleMesh, Embree's built-in triangles): icosphere counts and topology, vertices on the
// exact glyph surface, convergence of a k = 0 glyph to its sphere as the level grows, colours,
// normals (geometric, interpolated, exact), and bad input.
//
// References: the vertex counts 10 * 4^L + 2 are the published icosphere sizes (DIPY's
// create_unit_sphere, FURY); the glyph surface is |p| = |F(p / |p|)| evaluated with the kernel's
// SH basis, whose own tests check it against MRtrix3 and DIPY; the sphere's chord error is the
// distance of each triangle's plane from the centre, computed here in long double.
#include "sightline/core/EmbreeScene.h"
#include "sightline/glyphs/SHGlyphSet.h"
#include "sightline/baselines/SHGlyphTessellation.h"
#include "sightline/spheres/SphereSet.h"
#include "sightline/baselines/TriangleMesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace
{
using sightline::dvec3;
using sightline::EmbreeScene;
using sightline::Icosphere;
using sightline::makeIcosphere;
using sightline::Ray;
using sightline::SHBasis;
using sightline::SHColoring;
using sightline::SHGlyphOptions;
using sightline::SHGlyphSet;
using sightline::SHTessellationInfo;
using sightline::SHTessellationNormals;
using sightline::SHTessellationOptions;
using sightline::tessellateSHGlyphs;
using sightline::TriangleMesh;
using sightline::vec3;

using sightline::kPi;
const double kY00 = 0.5 / std::sqrt(kPi);

SHGlyphOptions canonicalOptions()
{
  SHGlyphOptions options;
  options.convention = { SHBasis::Canonical, false };
  return options;
}

/// Random canonical coefficients of a glyph with a dominant constant term and lobes.
std::vector<float> randomCoefficients(int order, std::mt19937& random, double b0 = 1.0)
{
  std::uniform_real_distribution<double> uniform(-0.6, 0.6);
  std::vector<float> b(sightline::shCoefficientCount(order));
  for (float& c : b)
    c = float(uniform(random) * b0);
  b[0] = float(b0 * 2.0);
  return b;
}

/// A set of glyphs with centres near the origin, so that float vertices keep ~1e-7 accuracy.
SHGlyphSet makeGlyphs(int order, int count, unsigned seed, const SHGlyphOptions& options = canonicalOptions())
{
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> position(-1.5f, 1.5f);
  std::vector<vec3> centers;
  std::vector<float> coefficients;
  for (int i = 0; i < count; ++i)
  {
    centers.emplace_back(position(random), position(random), position(random));
    const std::vector<float> b = randomCoefficients(order, random, 0.4);
    coefficients.insert(coefficients.end(), b.begin(), b.end());
  }
  return SHGlyphSet(centers, coefficients, order, options);
}

double glyphValue(const SHGlyphSet& glyphs, unsigned i, const dvec3& w)
{
  return sightline::evaluateSHSum<double>(glyphs.order(i), glyphs.coefficients(i), w.x, w.y, w.z);
}

//------------------------------------------------------------------------------
TEST(Icosphere, CountsFollowTheSubdivisionFormula)
{
  const std::size_t expectedVertices[] = { 12, 42, 162, 642, 2562, 10242 };
  for (int level = 0; level <= 5; ++level)
  {
    const Icosphere sphere = makeIcosphere(level);
    EXPECT_EQ(sphere.vertices.size(), expectedVertices[level]) << "level " << level;
    EXPECT_EQ(sightline::icosphereVertexCount(level), expectedVertices[level]);
    EXPECT_EQ(sphere.triangles.size(), 3 * sightline::icosphereTriangleCount(level));
    EXPECT_EQ(sightline::icosphereTriangleCount(level), std::size_t(20) << (2 * level));
  }
}

TEST(Icosphere, IsAClosedOutwardOrientedUnitSphere)
{
  for (int level = 0; level <= 4; ++level)
  {
    const Icosphere sphere = makeIcosphere(level);
    for (const dvec3& v : sphere.vertices)
      ASSERT_NEAR(glm::length(v), 1.0, 1e-15);
    // Every directed edge appears once and its reverse once: closed, consistently oriented.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (std::size_t t = 0; t < sphere.triangles.size(); t += 3)
    {
      const std::uint32_t a = sphere.triangles[t], b = sphere.triangles[t + 1], c = sphere.triangles[t + 2];
      ++edges[{ a, b }];
      ++edges[{ b, c }];
      ++edges[{ c, a }];
      const dvec3& A = sphere.vertices[a];
      const dvec3 normal = glm::cross(sphere.vertices[b] - A, sphere.vertices[c] - A);
      EXPECT_GT(glm::dot(normal, A + sphere.vertices[b] + sphere.vertices[c]), 0.0)
        << "triangle " << t / 3 << " of level " << level << " faces inwards";
    }
    for (const auto& [edge, count] : edges)
    {
      ASSERT_EQ(count, 1) << "edge used twice in the same direction";
      ASSERT_EQ(edges.count({ edge.second, edge.first }), 1u) << "boundary edge";
    }
    // Euler: V - E + F = 2 for a sphere.
    const long long V = sphere.vertices.size(), E = edges.size() / 2, F = sphere.triangles.size() / 3;
    EXPECT_EQ(V - E + F, 2);
  }
}

TEST(Icosphere, LevelOutOfRangeThrows)
{
  EXPECT_THROW(makeIcosphere(-1), std::invalid_argument);
  EXPECT_THROW(makeIcosphere(sightline::kMaxIcosphereSubdivisions + 1), std::invalid_argument);
  EXPECT_NO_THROW(makeIcosphere(0));
}

//------------------------------------------------------------------------------
TEST(SHGlyphTessellation, CountsAndLayout)
{
  const SHGlyphSet glyphs = makeGlyphs(4, 7, 11);
  ASSERT_EQ(glyphs.size(), 7u);
  for (int level : { 0, 1, 2, 3 })
  {
    SHTessellationOptions options;
    options.subdivisions = level;
    SHTessellationInfo info;
    const auto mesh = tessellateSHGlyphs(glyphs, options, &info);
    EXPECT_EQ(info.glyphs, 7u);
    EXPECT_EQ(info.verticesPerGlyph, sightline::icosphereVertexCount(level));
    EXPECT_EQ(info.trianglesPerGlyph, sightline::icosphereTriangleCount(level));
    EXPECT_GE(info.seconds, 0.0);
    EXPECT_EQ(mesh->vertexCount(), 7 * info.verticesPerGlyph);
    EXPECT_EQ(mesh->size(), 7 * info.trianglesPerGlyph);
    // Glyph i's triangles use only glyph i's vertices.
    for (std::size_t t = 0; t < mesh->size(); ++t)
      for (std::uint32_t v : mesh->triangle(t))
        ASSERT_EQ(v / info.verticesPerGlyph, t / info.trianglesPerGlyph);
    EXPECT_GT(mesh->memoryBytes(), mesh->vertexCount() * sizeof(vec3));
    EXPECT_TRUE(mesh->hasPrimitiveColors());
  }
}

TEST(SHGlyphTessellation, VerticesLieOnTheExactGlyph)
{
  // Glyphs centred at the origin: the float vertex is the double position rounded relative to
  // its own size, so even vertices close to the centre (near zeros of F) keep their direction.
  for (int order : { 2, 4, 8 })
  {
    std::mt19937 random(100 + order);
    std::vector<float> coefficients;
    for (int i = 0; i < 5; ++i)
    {
      const std::vector<float> b = randomCoefficients(order, random, 0.4);
      coefficients.insert(coefficients.end(), b.begin(), b.end());
    }
    const SHGlyphSet glyphs(std::vector<vec3>(5, vec3(0.0f)), coefficients, order, canonicalOptions());
    SHTessellationOptions options;
    options.subdivisions = 3;
    const auto mesh = tessellateSHGlyphs(glyphs, options);
    const Icosphere sphere = makeIcosphere(3);
    const std::size_t nv = sphere.vertices.size();
    double worst = 0.0, worstDirection = 0.0;
    for (unsigned i = 0; i < glyphs.size(); ++i)
      for (std::size_t v = 0; v < nv; ++v)
      {
        const dvec3 p(mesh->vertex(i * nv + v));
        const double r = glm::length(p);
        ASSERT_GT(r, 0.0);
        const dvec3 w = p / r;
        // |p| == |F(p / |p|)| ...
        worst = std::max(worst, std::abs(r - std::abs(glyphValue(glyphs, i, w))));
        // ... in the direction of the sphere's vertex (|F(v)| v, not the antipode).
        worstDirection = std::max(worstDirection, glm::length(w - sphere.vertices[v]));
      }
    EXPECT_LT(worst, 1e-6) << "order " << order;
    EXPECT_LT(worstDirection, 1e-6) << "order " << order;
  }
}

TEST(SHGlyphTessellation, VerticesAreAtTheRadiusOfTheirDirection)
{
  // Glyphs away from the origin: the vertex is c + |F(v)| v up to float rounding of the sum.
  for (int order : { 4, 8 })
  {
    const SHGlyphSet glyphs = makeGlyphs(order, 5, 200 + order);
    const auto mesh = tessellateSHGlyphs(glyphs, SHTessellationOptions{ 2 });
    const Icosphere sphere = makeIcosphere(2);
    const std::size_t nv = sphere.vertices.size();
    for (unsigned i = 0; i < glyphs.size(); ++i)
    {
      const dvec3 center(glyphs.center(i));
      for (std::size_t v = 0; v < nv; ++v)
      {
        const dvec3 expected = center + std::abs(glyphValue(glyphs, i, sphere.vertices[v])) * sphere.vertices[v];
        ASSERT_LT(glm::length(dvec3(mesh->vertex(i * nv + v)) - expected), 1e-6)
          << "glyph " << i << " vertex " << v << " order " << order;
      }
    }
  }
}

TEST(SHGlyphTessellation, UsesTheSetsCanonicalCoefficients)
{
  // The same glyph given in DIPY's descoteaux07 (legacy) basis: the mesh follows the converted
  // coefficients the exact glyphs use, and a glyph whose top band is zero is tessellated with
  // its trimmed order.
  std::mt19937 random(5);
  std::vector<float> b = randomCoefficients(6, random, 0.5);
  std::fill(b.begin() + sightline::shCoefficientCount(4), b.end(), 0.0f);
  SHGlyphOptions options;
  options.convention = { SHBasis::Descoteaux07, true };
  const SHGlyphSet glyphs({ vec3(0.25f, -0.5f, 0.125f) }, b, 6, options);
  ASSERT_EQ(glyphs.order(0), 4);
  const auto mesh = tessellateSHGlyphs(glyphs, SHTessellationOptions{ 2 });
  for (std::size_t v = 0; v < mesh->vertexCount(); ++v)
  {
    const dvec3 p = dvec3(mesh->vertex(v)) - dvec3(glyphs.center(0));
    EXPECT_NEAR(glm::length(p), std::abs(glyphValue(glyphs, 0, glm::normalize(p))), 1e-6);
  }
}

TEST(SHGlyphTessellation, NegativeLobesAreAbsoluteOrClipped)
{
  // F = Y_2^0 scaled: negative around the equator.
  std::vector<float> b(sightline::shCoefficientCount(2), 0.0f);
  b[sightline::shIndex(2, 0)] = 1.0f;
  const SHGlyphSet glyphs({ vec3(0.0f) }, b, 2, canonicalOptions());
  const Icosphere sphere = makeIcosphere(2);
  for (bool clip : { false, true })
  {
    SHTessellationOptions options;
    options.subdivisions = 2;
    options.clipNegative = clip;
    const auto mesh = tessellateSHGlyphs(glyphs, options);
    int negative = 0;
    for (std::size_t v = 0; v < sphere.vertices.size(); ++v)
    {
      const double value = glyphValue(glyphs, 0, sphere.vertices[v]);
      const double r = glm::length(dvec3(mesh->vertex(v)));
      if (value < 0.0)
      {
        ++negative;
        EXPECT_NEAR(r, clip ? 0.0 : -value, 1e-6);
      }
      else
        EXPECT_NEAR(r, value, 1e-6);
    }
    EXPECT_GT(negative, 10);
  }
}

//------------------------------------------------------------------------------
/// Largest distance between a tessellated sphere of radius R and the exact sphere: the
/// vertices lie on it, so it is R minus the smallest distance of a triangle's plane from the
/// centre (each triangle's foot point lies inside it: the triangles are acute).
long double sphereDeviation(const TriangleMesh& mesh, const dvec3& center, double R)
{
  long double nearest = INFINITY;
  for (std::size_t t = 0; t < mesh.size(); ++t)
  {
    const auto tri = mesh.triangle(t);
    long double p[3][3];
    for (int k = 0; k < 3; ++k)
    {
      const vec3 v = mesh.vertex(tri[k]);
      p[k][0] = (long double)v.x - center.x;
      p[k][1] = (long double)v.y - center.y;
      p[k][2] = (long double)v.z - center.z;
    }
    long double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; ++k)
    {
      e1[k] = p[1][k] - p[0][k];
      e2[k] = p[2][k] - p[0][k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const long double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const long double distance = std::abs(n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2]) / length;
    nearest = std::min(nearest, distance);
  }
  return (long double)R - nearest;
}

TEST(SHGlyphTessellation, ConstantGlyphConvergesToItsSphere)
{
  const double R = 0.75;
  const vec3 center(0.5f, -0.25f, 1.0f);
  const SHGlyphSet glyphs({ center }, { float(R / kY00) }, 0, canonicalOptions());
  ASSERT_EQ(glyphs.order(0), 0);
  long double previous = INFINITY;
  for (int level = 0; level <= 5; ++level)
  {
    SHTessellationOptions options;
    options.subdivisions = level;
    const auto mesh = tessellateSHGlyphs(glyphs, options);
    for (std::size_t v = 0; v < mesh->vertexCount(); ++v)
      ASSERT_NEAR(glm::length(dvec3(mesh->vertex(v)) - dvec3(center)), R, 1e-6);
    const long double deviation = sphereDeviation(*mesh, dvec3(center), R);
    EXPECT_GT(deviation, 0.0L);
    EXPECT_LT(deviation, previous) << "level " << level;
    if (level >= 2)
    {
      // Second order: halving the edge length quarters the chord error.
      EXPECT_NEAR(double(previous / deviation), 4.0, 0.5) << "level " << level;
    }
    previous = deviation;
  }
  EXPECT_LT(previous, 1e-3 * R);
}

TEST(SHGlyphTessellation, TracedMeshApproachesTheExactSphere)
{
  // Rays through Embree's triangles against the analytic sphere the glyph is: the distance to
  // the hit shrinks with the level, and never exceeds the chord error.
  const double R = 0.6;
  const SHGlyphSet glyphs({ vec3(0.0f) }, { float(R / kY00) }, 0, canonicalOptions());
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  std::vector<Ray> rays;
  for (int i = 0; i < 400; ++i)
  {
    dvec3 target(normal(random), normal(random), normal(random));
    target = 0.7 * R * glm::normalize(target);
    dvec3 from(normal(random), normal(random), normal(random));
    from = 3.0 * glm::normalize(from);
    Ray ray;
    ray.origin = vec3(from);
    ray.direction = vec3(glm::normalize(target - from));
    rays.push_back(ray);
  }
  double previous = INFINITY;
  for (int level = 1; level <= 5; ++level)
  {
    auto mesh = tessellateSHGlyphs(glyphs, SHTessellationOptions{ level });
    const double chord = double(sphereDeviation(*mesh, dvec3(0.0), R));
    EmbreeScene scene;
    scene.add(mesh);
    scene.commit();
    double worst = 0.0;
    for (const Ray& ray : rays)
    {
      RTCRayHit rh = sightline::makeRayHit(ray);
      ASSERT_TRUE(scene.intersect(rh));
      const dvec3 hit = dvec3(ray.origin) + double(rh.ray.tfar) * dvec3(ray.direction);
      worst = std::max(worst, R - glm::length(hit));
    }
    EXPECT_LE(worst, chord + 1e-6) << "level " << level;
    EXPECT_LT(worst, previous) << "level " << level;
    previous = worst;
  }
}

//------------------------------------------------------------------------------
TEST(SHGlyphTessellation, ColoursFollowTheGlyphSet)
{
  const SHGlyphSet glyphs = makeGlyphs(4, 2, 21);
  const Icosphere sphere = makeIcosphere(2);
  const auto mesh = tessellateSHGlyphs(glyphs, SHTessellationOptions{ 2 });
  ASSERT_TRUE(mesh->hasPrimitiveColors());
  // Direction colouring |v|: a vertex's colour is the glyph's surface colour there (to 8 bits).
  for (unsigned i = 0; i < 2; ++i)
    for (std::size_t v = 0; v < sphere.vertices.size(); ++v)
    {
      const vec3 expected = glm::abs(vec3(sphere.vertices[v]));
      const std::size_t index = i * sphere.vertices.size() + v;
      // The mesh interpolates vertex colours: at a triangle's corner that is the vertex colour.
      for (std::size_t t = 0; t < mesh->size(); ++t)
      {
        const auto tri = mesh->triangle(t);
        if (tri[0] != index)
          continue;
        const vec3 color = mesh->surfaceColor(unsigned(t), mesh->vertex(index));
        EXPECT_NEAR(color.x, expected.x, 0.5 / 255 + 1e-6);
        EXPECT_NEAR(color.y, expected.y, 0.5 / 255 + 1e-6);
        EXPECT_NEAR(color.z, expected.z, 0.5 / 255 + 1e-6);
        break;
      }
    }

  // Material colouring: no colours of its own, the material is copied.
  SHGlyphOptions options = canonicalOptions();
  options.coloring = SHColoring::Material;
  SHGlyphSet plain = makeGlyphs(2, 1, 4, options);
  plain.material.color = vec3(0.2f, 0.4f, 0.6f);
  const auto plainMesh = tessellateSHGlyphs(plain, SHTessellationOptions{ 1 });
  EXPECT_FALSE(plainMesh->hasPrimitiveColors());
  EXPECT_EQ(plainMesh->material.color, plain.material.color);
}

TEST(SHGlyphTessellation, NormalsFlatMeshAndExact)
{
  const SHGlyphSet glyphs = makeGlyphs(4, 1, 31);
  const dvec3 center(glyphs.center(0));
  SHTessellationOptions options;
  options.subdivisions = 4;
  options.normals = SHTessellationNormals::Flat;
  EXPECT_FALSE(tessellateSHGlyphs(glyphs, options)->hasVertexNormals());

  options.normals = SHTessellationNormals::Exact;
  const auto exact = tessellateSHGlyphs(glyphs, options);
  options.normals = SHTessellationNormals::Mesh;
  const auto averaged = tessellateSHGlyphs(glyphs, options);
  ASSERT_TRUE(exact->hasVertexNormals());
  ASSERT_TRUE(averaged->hasVertexNormals());

  // Trace towards points just inside a triangle next to its first vertex (aiming exactly at a
  // vertex could slip between the triangles around it): the exact mesh reports Eq. 11's
  // normals interpolated there; the averaged one is close to them on this smooth glyph.
  auto hitNormal = [](const std::shared_ptr<TriangleMesh>& mesh, const Ray& ray)
  {
    EmbreeScene scene;
    scene.add(mesh);
    scene.commit();
    RTCRayHit rh = sightline::makeRayHit(ray);
    EXPECT_TRUE(scene.intersect(rh));
    return std::make_pair(glm::normalize(dvec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z)), double(rh.ray.tfar));
  };
  auto exactNormalAt = [&](std::uint32_t v)
  {
    return glm::normalize(sightline::shGlyphNormal(4, glyphs.coefficients(0), dvec3(exact->vertex(v)) - center));
  };
  double worstAngle = 0.0;
  int tested = 0;
  for (std::size_t t = 0; t < exact->size(); t += 61)
  {
    const auto tri = exact->triangle(t);
    const dvec3 q = 0.98 * dvec3(exact->vertex(tri[0])) + 0.01 * dvec3(exact->vertex(tri[1])) +
      0.01 * dvec3(exact->vertex(tri[2]));
    const dvec3 w = glm::normalize(q - center);
    const dvec3 reference = glm::normalize(0.98 * exactNormalAt(tri[0]) + 0.01 * exactNormalAt(tri[1]) +
      0.01 * exactNormalAt(tri[2]));
    if (glm::dot(reference, w) < 0.2)
      continue; // grazing
    Ray ray;
    ray.origin = vec3(q + 2.0 * w);
    ray.direction = vec3(-w);
    const auto [exactNormal, tExact] = hitNormal(exact, ray);
    if (std::abs(tExact - 2.0) > 1e-4)
      continue; // another part of the glyph is in front
    EXPECT_GT(glm::dot(exactNormal, reference), 1.0 - 1e-5) << "triangle " << t;
    const auto [meshNormal, tMesh] = hitNormal(averaged, ray);
    EXPECT_NEAR(tMesh, tExact, 1e-6);
    worstAngle = std::max(worstAngle, std::acos(std::min(1.0, glm::dot(meshNormal, reference))));
    ++tested;
  }
  EXPECT_GT(tested, 20);
  EXPECT_LT(worstAngle * 180.0 / kPi, 5.0);
}

//------------------------------------------------------------------------------
TEST(TriangleMesh, HitsGeometricNormalColoursAndBounds)
{
  // One triangle in the plane z = 1 and one in z = 2 behind it.
  std::vector<vec3> vertices{ { 0, 0, 1 }, { 1, 0, 1 }, { 0, 1, 1 }, { 0, 0, 2 }, { 2, 0, 2 }, { 0, 2, 2 } };
  auto mesh = std::make_shared<TriangleMesh>(vertices, std::vector<std::uint32_t>{ 0, 1, 2, 3, 4, 5 });
  EXPECT_EQ(mesh->size(), 2u);
  EXPECT_EQ(mesh->vertexCount(), 6u);
  EXPECT_FALSE(mesh->hasPrimitiveColors());
  EXPECT_EQ(mesh->bounds().lower, vec3(0, 0, 1));
  EXPECT_EQ(mesh->bounds().upper, vec3(2, 2, 2));

  mesh->setTriangleColors({ sightline::packRGBA8(255, 0, 0), sightline::packRGBA8(0, 0, 255) });
  EXPECT_TRUE(mesh->hasPrimitiveColors());
  EXPECT_EQ(mesh->primitiveColor(1), vec3(0, 0, 1));
  mesh->setVertexColors({ sightline::packRGBA8(255, 0, 0), sightline::packRGBA8(0, 255, 0),
    sightline::packRGBA8(0, 0, 255), 0, 0, 0 });
  const vec3 mid = mesh->surfaceColor(0, vec3(0.25f, 0.25f, 1.0f));
  EXPECT_NEAR(mid.x, 0.5f, 1e-6);
  EXPECT_NEAR(mid.y, 0.25f, 1e-6);
  EXPECT_NEAR(mid.z, 0.25f, 1e-6);
  const vec3 w = mesh->barycentric(0, vec3(0.25f, 0.5f, 1.3f)); // off the plane: projected
  EXPECT_NEAR(w.x, 0.25f, 1e-6);
  EXPECT_NEAR(w.y, 0.25f, 1e-6);
  EXPECT_NEAR(w.z, 0.5f, 1e-6);

  EmbreeScene scene;
  scene.add(mesh);
  scene.commit();
  Ray ray;
  ray.origin = vec3(0.2f, 0.2f, 0.0f);
  ray.direction = vec3(0, 0, 1);
  RTCRayHit rh = sightline::makeRayHit(ray);
  ASSERT_TRUE(scene.intersect(rh));
  EXPECT_EQ(rh.hit.primID, 0u);
  EXPECT_NEAR(rh.ray.tfar, 1.0f, 1e-6);
  const vec3 n = glm::normalize(vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
  EXPECT_NEAR(std::abs(n.z), 1.0f, 1e-6);
  // Past the first triangle's hypotenuse only the second one is hit.
  ray.origin = vec3(0.8f, 0.8f, 0.0f);
  rh = sightline::makeRayHit(ray);
  ASSERT_TRUE(scene.intersect(rh));
  EXPECT_EQ(rh.hit.primID, 1u);
  EXPECT_NEAR(rh.ray.tfar, 2.0f, 1e-6);
  ray.origin = vec3(1.8f, 1.8f, 0.0f);
  rh = sightline::makeRayHit(ray);
  EXPECT_FALSE(scene.intersect(rh));
  EXPECT_TRUE(scene.occluded([] {
    Ray r;
    r.origin = vec3(0.1f, 0.1f, 0.0f);
    r.direction = vec3(0, 0, 1);
    return r;
  }()));
  EXPECT_GT(scene.bvhBytes(), 0);
}

TEST(TriangleMesh, VertexNormalsAreInterpolated)
{
  std::vector<vec3> vertices{ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } };
  auto mesh = std::make_shared<TriangleMesh>(vertices, std::vector<std::uint32_t>{ 0, 1, 2 });
  mesh->setVertexNormals({ { 0, 0, 1 }, { 1, 0, 1 }, { 0, 1, 1 } });
  EmbreeScene scene;
  scene.add(mesh);
  scene.commit();
  Ray ray;
  ray.origin = vec3(0.25f, 0.5f, 1.0f);
  ray.direction = vec3(0, 0, -1);
  RTCRayHit rh = sightline::makeRayHit(ray);
  ASSERT_TRUE(scene.intersect(rh));
  // Barycentric (0.25, 0.25, 0.5): n = 0.25 (0,0,1) + 0.25 (1,0,1) + 0.5 (0,1,1).
  EXPECT_NEAR(rh.hit.Ng_x, 0.25f, 1e-6);
  EXPECT_NEAR(rh.hit.Ng_y, 0.5f, 1e-6);
  EXPECT_NEAR(rh.hit.Ng_z, 1.0f, 1e-6);
}

TEST(TriangleMesh, BadInputThrows)
{
  const std::vector<vec3> vertices{ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } };
  EXPECT_THROW(TriangleMesh(vertices, { 0, 1 }), std::invalid_argument);
  EXPECT_THROW(TriangleMesh(vertices, { 0, 1, 3 }), std::invalid_argument);
  EXPECT_THROW(TriangleMesh({ { 0, 0, 0 }, { NAN, 0, 0 }, { 0, 1, 0 } }, { 0, 1, 2 }), std::invalid_argument);
  TriangleMesh mesh(vertices, { 0, 1, 2 });
  EXPECT_THROW(mesh.setVertexColors({ 0, 0 }), std::invalid_argument);
  EXPECT_THROW(mesh.setTriangleColors({ 0, 0 }), std::invalid_argument);
  EXPECT_THROW(mesh.setVertexNormals({ vec3(0, 0, 1) }), std::invalid_argument);
  EXPECT_NO_THROW(mesh.setVertexNormals({}));
}

TEST(SHGlyphTessellation, LevelOutOfRangeThrows)
{
  const SHGlyphSet glyphs = makeGlyphs(2, 1, 8);
  for (int level : { -1, sightline::kMaxIcosphereSubdivisions + 1, 100 })
  {
    SHTessellationOptions options;
    options.subdivisions = level;
    EXPECT_THROW(tessellateSHGlyphs(glyphs, options), std::invalid_argument) << level;
  }
}
} // namespace
