// SPDX-License-Identifier: BSD-3-Clause
// Ray packets: the renderer traces a tile's primary rays in Embree packets of 4, 8 or 16. Embree
// may regroup a packet's rays before calling the user geometries back, which find each lane's
// double ray by its ray id. Each ray must get exactly the hit it gets on its own, and every
// packet size the same image, for every primitive, near and far from the origin.
#include "sightline/baselines/TriangleMesh.h"
#include "sightline/core/Camera.h"
#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Renderer.h"
#include "sightline/glyphs/EllipsoidSet.h"
#include "sightline/glyphs/SHGlyphSet.h"
#include "sightline/spheres/SphereSet.h"
#include "sightline/tubes/TubeSet.h"

#include "glyphs/SHGlyphTestSupport.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <random>
#include <stdexcept>

using namespace sightline;

namespace
{
constexpr int kPacketSizes[] = { 1, 4, 8, 16 };

void expectSameFramebuffer(const Framebuffer& a, const Framebuffer& b, const std::string& what);

/// Random spheres, a branching tube, ellipsoids and k = 8 SH glyphs, overlapping in a box of
/// about 8 units around `origin` (double), every position a float offset from it.
std::vector<std::shared_ptr<Geometry>> mixedPrimitives(const dvec3& origin)
{
  std::mt19937 random(2718);
  std::uniform_real_distribution<float> position(-4.0f, 4.0f), radius(0.2f, 0.7f);
  std::vector<vec3> centres;
  std::vector<float> radii;
  std::vector<std::uint32_t> colours;
  for (int i = 0; i < 60; ++i)
  {
    centres.emplace_back(position(random), position(random), position(random));
    radii.push_back(radius(random));
    colours.push_back(packRGBA8(std::uint8_t(40 * i), 200, std::uint8_t(255 - 3 * i)));
  }
  std::vector<std::shared_ptr<Geometry>> geometries;
  geometries.push_back(std::make_shared<SphereSet>(origin, centres, radii, 1.0f, colours));

  const std::vector<vec3> tubePoints = { vec3(-3.5f, -1.0f, 0.0f), vec3(-1.2f, -0.4f, 1.3f),
    vec3(-0.2f, 0.1f, 0.0f), vec3(0.1f, 0.2f, -0.1f), vec3(1.4f, 2.1f, 0.2f), vec3(3.4f, 1.6f, -1.5f),
    vec3(1.3f, -1.9f, 0.4f), vec3(3.5f, -2.5f, 0.0f) };
  const std::vector<float> tubeRadii = { 0.3f, 0.45f, 0.5f, 0.42f, 0.3f, 0.25f, 0.35f, 0.28f };
  geometries.push_back(std::make_shared<TubeSet>(origin, tubePoints, tubeRadii,
    std::vector<std::int64_t>{ -1, 0, 1, 2, 3, 4, 3, 6 }));

  std::vector<dmat3> axes;
  for (int i = 0; i < 4; ++i)
  {
    const dmat3 rotation = dmat3(glm::rotate(glm::dmat4(1.0), 0.7 * i + 0.3, glm::normalize(dvec3(1, i, 2))));
    axes.push_back(rotation * dmat3(glm::scale(glm::dmat4(1.0), dvec3(0.9, 0.5 + 0.1 * i, 0.3))));
  }
  geometries.push_back(std::make_shared<EllipsoidSet>(origin,
    std::vector<vec3>{ vec3(-2.0f, 2.5f, 0.5f), vec3(2.5f, -0.5f, 1.5f), vec3(0.0f, -2.8f, -1.0f),
      vec3(-2.5f, -2.5f, 2.0f) },
    axes));

  SHGlyphOptions options;
  options.convention = SHConvention::fromName("canonical", false);
  std::vector<float> coefficients;
  const std::vector<std::vector<dvec3>> fibres = { { dvec3(1, 0.2, 0.1) },
    { dvec3(1, 0, 0), dvec3(0.1, 1, 0.3) }, { dvec3(0.3, 0.2, 1), dvec3(1, -0.5, 0) } };
  for (const auto& f : fibres)
  {
    const std::vector<double> b = sightline_test::glyph::fibreLobeCoefficients(8, f, 0.15, 12.0);
    std::vector<float> glyph(b.begin(), b.end());
    const double scale = 1.0 / shMaxAmplitude(8, glyph.data(), options.convention);
    for (float c : glyph)
      coefficients.push_back(float(c * scale));
  }
  geometries.push_back(std::make_shared<SHGlyphSet>(origin,
    std::vector<vec3>{ vec3(1.0f, 3.0f, -0.5f), vec3(-3.0f, 0.5f, -2.0f), vec3(2.8f, 2.8f, 2.5f) },
    coefficients, 8, options));
  return geometries;
}

/// A camera 14 units from the scene's centre, looking at it obliquely.
CameraParameters cameraAt(const dvec3& origin)
{
  CameraParameters p;
  p.position = origin + dvec3(5.0, 7.0, 11.0);
  p.focalPoint = origin + dvec3(0.2, -0.1, 0.0);
  p.viewAngle = 40.0;
  p.nearClip = 1.0;
  p.farClip = 40.0;
  return p;
}

bool sameBits(float a, float b)
{
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Packets against single rays through EmbreeScene: coherent blocks of pixels with random lanes
// switched off, and incoherent random rays (which Embree regroups), in packets of every count.
// The user geometries' hits must be the same bits; Embree's own triangles (a float geometry with
// packet code of its own) the same triangle at the same t to float rounding.
TEST(RayPackets, EachRayGetsItsSingleRayHit)
{
  for (const double away : { 0.0, 1e4 })
  {
    const dvec3 origin = away * glm::normalize(dvec3(1.0, 0.6, -0.3));
    EmbreeScene scene;
    for (const auto& geometry : mixedPrimitives(origin))
      scene.add(geometry);
    // A float floor behind everything: nearer than a user primitive wherever it is in front.
    const vec3 o(origin);
    scene.add(std::make_shared<TriangleMesh>(
      std::vector<vec3>{ o + vec3(-9, -9, -3), o + vec3(9, -9, -3), o + vec3(9, 9, -3.5f), o + vec3(-9, 9, -3.5f) },
      std::vector<std::uint32_t>{ 0, 1, 2, 0, 2, 3 }));
    scene.commit();
    const unsigned triangles = 4;

    const Camera camera = Camera::fromParameters(cameraAt(origin), 96, 64);
    std::mt19937 random(31);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::size_t compared = 0, hits = 0, byKind[5] = {};
    for (int trial = 0; trial < 1200; ++trial)
    {
      const bool coherent = trial % 3 != 0;
      const int count = 1 + trial % EmbreeScene::kMaxPacket;
      DoubleRay rays[EmbreeScene::kMaxPacket];
      bool active[EmbreeScene::kMaxPacket];
      const int x0 = int(unit(random) * 92), y0 = int(unit(random) * 60);
      for (int i = 0; i < count; ++i)
      {
        active[i] = unit(random) < 0.85;
        if (coherent)
          rays[i] = camera.doublePrimaryRay(x0 + i % 4 + 0.5, y0 + i / 4 + 0.5);
        else
        {
          const dvec3 from = origin + dvec3(12.0 * unit(random) - 6.0, 12.0 * unit(random) - 6.0, 9.0);
          const dvec3 to = origin + dvec3(8.0 * unit(random) - 4.0, 8.0 * unit(random) - 4.0, -4.0 * unit(random));
          rays[i] = DoubleRay(from, glm::normalize(to - from), unit(random) < 0.2 ? 4.0 : 0.0,
            unit(random) < 0.2 ? 11.0 : kInfinity);
        }
      }
      SceneHit packetHits[EmbreeScene::kMaxPacket];
      bool found[EmbreeScene::kMaxPacket];
      scene.intersectPacket(rays, active, count, packetHits, found, coherent);
      for (int i = 0; i < count; ++i)
      {
        if (!active[i])
        {
          EXPECT_FALSE(found[i]) << "an inactive lane must not report a hit";
          continue;
        }
        SceneHit single;
        const bool singleFound = scene.intersect(rays[i], single, coherent);
        ++compared;
        ASSERT_EQ(found[i], singleFound) << "trial " << trial << " lane " << i << " at " << away;
        if (!singleFound)
          continue;
        ++hits;
        ++byKind[single.geomID];
        ASSERT_EQ(packetHits[i].geomID, single.geomID) << "trial " << trial << " lane " << i;
        ASSERT_EQ(packetHits[i].primID, single.primID) << "trial " << trial << " lane " << i;
        if (single.geomID == triangles)
        {
          EXPECT_NEAR(packetHits[i].t, single.t, 1e-6 * single.t) << "trial " << trial << " lane " << i;
          continue;
        }
        EXPECT_EQ(packetHits[i].t, single.t) << "trial " << trial << " lane " << i << " at " << away;
        for (int axis = 0; axis < 3; ++axis)
          EXPECT_TRUE(sameBits(packetHits[i].normal[axis], single.normal[axis]))
            << "trial " << trial << " lane " << i << " axis " << axis;
      }
    }
    EXPECT_GT(compared, std::size_t(8000));
    EXPECT_GT(hits, compared / 3);
    for (unsigned kind = 0; kind < 5; ++kind)
      EXPECT_GT(byKind[kind], std::size_t(100)) << "geometry " << kind << " at " << away;
  }
}

// Dense data seen from far: nearly every pixel of a block hits another sphere, so the renderer
// traces those blocks in narrow packets (rows of 4); the image must not change.
TEST(RayPackets, DenseFarViewRendersTheSameImage)
{
  std::mt19937 random(99);
  std::uniform_real_distribution<float> position(-4.0f, 4.0f);
  std::vector<vec3> centres;
  for (int i = 0; i < 200000; ++i)
    centres.emplace_back(position(random), position(random), position(random));
  EmbreeScene scene;
  scene.add(std::make_shared<SphereSet>(centres, std::vector<float>{}, 0.02f));
  scene.commit();
  const Camera camera = Camera::fromParameters(cameraAt(dvec3(0.0)), 83, 61);
  const Lighting lighting = Lighting::headlight(vec3(0.0f, 0.0f, -1.0f));
  Framebuffer reference;
  RenderOptions options;
  options.packetSize = 1;
  options.primitiveIds = true;
  const std::size_t hits = Renderer().render(scene, camera, lighting, reference, options).hits;
  EXPECT_GT(hits, std::size_t(83 * 61 / 2));
  // How many 4x4 blocks hit more than 12 different spheres (narrow packets follow them).
  std::size_t divergentBlocks = 0;
  for (int y = 0; y + 4 <= 61; y += 4)
    for (int x = 0; x + 4 <= 83; x += 4)
    {
      std::vector<std::uint32_t> seen;
      for (int j = 0; j < 16; ++j)
      {
        const PixelPrimitive& p = reference.Primitives[reference.index(x + j % 4, y + j / 4)];
        if (p.hit() && std::find(seen.begin(), seen.end(), p.primitive) == seen.end())
          seen.push_back(p.primitive);
      }
      divergentBlocks += seen.size() > 12;
    }
  EXPECT_GT(divergentBlocks, std::size_t(50)) << "the scene must exercise narrow packets";
  for (const int packet : { 4, 8, 16 })
  {
    options.packetSize = packet;
    Framebuffer fb;
    EXPECT_EQ(Renderer().render(scene, camera, lighting, fb, options).hits, hits);
    expectSameFramebuffer(reference, fb, "dense far view, packets of " + std::to_string(packet));
  }
}

TEST(RayPackets, IntersectPacketRejectsCountsItCannotTake)
{
  EmbreeScene scene;
  scene.add(std::make_shared<SphereSet>(std::vector<vec3>{ vec3(0.0f) }, std::vector<float>{ 1.0f }));
  scene.commit();
  DoubleRay rays[EmbreeScene::kMaxPacket + 1];
  bool active[EmbreeScene::kMaxPacket + 1] = {};
  SceneHit hits[EmbreeScene::kMaxPacket + 1];
  bool found[EmbreeScene::kMaxPacket + 1];
  EXPECT_THROW(scene.intersectPacket(rays, active, 0, hits, found), std::invalid_argument);
  EXPECT_THROW(scene.intersectPacket(rays, active, EmbreeScene::kMaxPacket + 1, hits, found),
    std::invalid_argument);
  const int native = scene.device().packetSize();
  EXPECT_TRUE(native == 1 || native == 4 || native == 8 || native == 16) << native;
}

/// Everything the renderer writes, bit for bit.
void expectSameFramebuffer(const Framebuffer& a, const Framebuffer& b, const std::string& what)
{
  ASSERT_EQ(a.pixelCount(), b.pixelCount());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.pixelCount(); ++i)
  {
    bool same = sameBits(a.Depth[i], b.Depth[i]) && sameBits(a.Distance[i], b.Distance[i]);
    for (int c = 0; c < 4; ++c)
      same = same && sameBits(a.Color[i][c], b.Color[i][c]);
    if (!a.Primitives.empty())
      same = same && a.Primitives[i].geometry == b.Primitives[i].geometry &&
        a.Primitives[i].primitive == b.Primitives[i].primitive;
    differ += !same;
  }
  EXPECT_EQ(differ, 0u) << what;
}

// The renderer with every packet size: shadows, primitive ids, tiles that packets do not divide
// (and an image size they do not divide), an object-to-world transform, a depth limit from
// "OpenGL", a region, translucent tubes and a glyph volume all take the same path per pixel.
TEST(RayPackets, EveryPacketSizeRendersTheSameImage)
{
  for (const double away : { 0.0, 1e4 })
  {
    const dvec3 origin = away * glm::normalize(dvec3(1.0, 0.6, -0.3));
    const std::vector<std::shared_ptr<Geometry>> primitives = mixedPrimitives(origin);
    EmbreeScene opaque, translucent, volume;
    opaque.add(primitives[0]);
    opaque.add(primitives[2]);
    opaque.add(primitives[3]);
    opaque.commit();
    primitives[1]->material.opacity = 0.5f;
    translucent.add(primitives[1]);
    translucent.commit();
    // The SH glyphs once more, as a homogeneous volume in front of the opaque primitives.
    volume.add(mixedPrimitives(origin)[3]);
    volume.commit();
    const int width = 83, height = 61;
    const dmat4 objectToWorld = glm::rotate(dmat4(1.0), 0.2, dvec3(0.0, 0.0, 1.0));
    const CameraParameters parameters = cameraAt(origin);
    Lighting lighting = Lighting::headlight(vec3(glm::normalize(parameters.focalPoint - parameters.position)));
    lighting.lights.push_back({ glm::normalize(vec3(-1.0f, -0.5f, -0.6f)) });

    struct Variant
    {
      const char* name;
      std::function<void(RenderOptions&, Camera&)> set;
    };
    std::vector<float> depthLimit(std::size_t(width) * height, 1.0f);
    for (std::size_t i = 0; i < depthLimit.size(); ++i)
      if (i % 7 < 3)
        depthLimit[i] = 0.3f + 0.001f * float(i % 500);
    const Variant variants[] = {
      { "shadows, ids, 10-pixel tiles", [](RenderOptions& o, Camera&)
        {
          o.shadows.mode = ShadowMode::Soft;
          o.shadows.samples = 4;
          o.primitiveIds = true;
          o.tileSize = 10;
        } },
      { "translucent tubes, glyph volume, 7-pixel tiles", [&](RenderOptions& o, Camera&)
        {
          o.translucent.scene = &translucent;
          o.volumes.scene = &volume;
          o.volumes.extinction = 0.4f;
          o.tileSize = 7;
        } },
      { "object-to-world, depth limit, region", [&](RenderOptions& o, Camera& camera)
        {
          // The same view of the scene, whose world position the transform moves.
          o.objectToWorld = objectToWorld;
          CameraParameters world = parameters;
          world.position = dvec3(objectToWorld * dvec4(parameters.position, 1.0));
          world.focalPoint = dvec3(objectToWorld * dvec4(parameters.focalPoint, 1.0));
          world.viewUp = glm::dmat3(objectToWorld) * parameters.viewUp;
          camera = Camera(Camera::worldToClipMatrix(world, double(width) / height) * objectToWorld,
            width, height);
          o.depthLimit = &depthLimit;
          o.regionLower = dvec3(objectToWorld * dvec4(origin, 1.0)) + dvec3(-1.5, -kInfinity, -kInfinity);
          o.regionUpper = dvec3(kInfinity, dvec3(objectToWorld * dvec4(origin, 1.0)).y + 2.0, kInfinity);
        } },
    };
    for (const Variant& variant : variants)
    {
      Framebuffer reference;
      std::size_t referenceHits = 0;
      for (const int packet : kPacketSizes)
      {
        RenderOptions options;
        options.packetSize = packet;
        Camera camera = Camera::fromParameters(parameters, width, height);
        variant.set(options, camera);
        Framebuffer fb;
        const RenderStatistics stats = Renderer().render(opaque, camera, lighting, fb, options);
        if (packet == 1)
        {
          reference = fb;
          referenceHits = stats.hits;
          EXPECT_GT(stats.hits, std::size_t(width * height / 16)) << variant.name << " at " << away;
          std::printf("%s at %g: %zu of %d pixels hit\n", variant.name, away, stats.hits, width * height);
          continue;
        }
        EXPECT_EQ(stats.hits, referenceHits) << variant.name << ", packets of " << packet;
        expectSameFramebuffer(reference, fb,
          std::string(variant.name) + ", packets of " + std::to_string(packet) + " at " + std::to_string(away));
      }
    }
  }
  RenderOptions bad;
  bad.packetSize = 3;
  EmbreeScene empty;
  Framebuffer fb;
  EXPECT_THROW(Renderer().render(empty, Camera::fromParameters({}, 8, 8), Lighting{}, fb, bad),
    std::invalid_argument);
}
} // namespace
