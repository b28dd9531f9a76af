// SPDX-License-Identifier: BSD-3-Clause
// SphereSet: input validation (drop and report, or throw), bounds and the kept-to-input mapping.
#include "sightline/spheres/SphereSet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace
{
using sightline::SphereSet;
using sightline::vec3;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

bool anyReasonMentions(const sightline::ValidationReport& report, const std::string& text)
{
  for (const std::string& reason : report.reasons)
    if (reason.find(text) != std::string::npos)
      return true;
  return false;
}

TEST(SphereSet, KeepsValidInputUntouched)
{
  const std::vector<vec3> centers{ { 0, 0, 0 }, { 1, 2, 3 }, { -4, 5, -6 } };
  const std::vector<float> radii{ 0.5f, 1.0f, 2.0f };
  const SphereSet spheres(centers, radii);
  EXPECT_TRUE(spheres.report().clean());
  EXPECT_TRUE(spheres.report().reasons.empty());
  ASSERT_EQ(spheres.size(), 3u);
  for (unsigned i = 0; i < 3; ++i)
  {
    EXPECT_EQ(sightline::vec3(spheres.spheres()[i]), centers[i]);
    EXPECT_EQ(spheres.spheres()[i].w, radii[i]);
    EXPECT_EQ(spheres.sourceIndex()[i], i);
  }
  EXPECT_FALSE(spheres.hasPrimitiveColors());
}

TEST(SphereSet, DropsAndReportsInvalidSpheres)
{
  // Indices 1, 3 and 6 have bad centres; 2, 4, 5 and 7 bad radii; 0 and 8 are valid.
  const std::vector<vec3> centers{ { 0, 0, 0 },     { kNaN, 0, 0 }, { 1, 0, 0 },
                                   { 0, kInf, 0 },  { 2, 0, 0 },    { 3, 0, 0 },
                                   { 0, 0, -kInf }, { 4, 0, 0 },    { 5, 0, 0 } };
  const std::vector<float> radii{ 1.0f, 1.0f, -1.0f, 1.0f, 0.0f, kNaN, 1.0f, kInf, 0.25f };
  const std::vector<std::uint32_t> colors{
    sightline::packRGBA8(10, 0, 0), sightline::packRGBA8(11, 0, 0), sightline::packRGBA8(12, 0, 0),
    sightline::packRGBA8(13, 0, 0), sightline::packRGBA8(14, 0, 0), sightline::packRGBA8(15, 0, 0),
    sightline::packRGBA8(16, 0, 0), sightline::packRGBA8(17, 0, 0), sightline::packRGBA8(18, 0, 0)
  };
  const SphereSet spheres(centers, radii, 1.0f, colors);

  EXPECT_EQ(spheres.report().rejected, 7u);
  EXPECT_FALSE(spheres.report().clean());
  EXPECT_EQ(spheres.report().reasons.size(), 2u);
  EXPECT_TRUE(anyReasonMentions(spheres.report(), "point 1")) << "first bad centre";
  EXPECT_TRUE(anyReasonMentions(spheres.report(), "point 2")) << "first bad radius";

  ASSERT_EQ(spheres.size(), 2u);
  EXPECT_EQ(spheres.sourceIndex(), (std::vector<std::uint32_t>{ 0, 8 }));
  EXPECT_EQ(spheres.spheres()[1], sightline::vec4(5, 0, 0, 0.25f));
  // Colours follow their spheres, not their positions in the input.
  ASSERT_TRUE(spheres.hasPrimitiveColors());
  EXPECT_FLOAT_EQ(spheres.primitiveColor(0).r, 10 / 255.0f);
  EXPECT_FLOAT_EQ(spheres.primitiveColor(1).r, 18 / 255.0f);
}

TEST(SphereSet, EachKindOfInvalidInputIsReportedWithItsIndex)
{
  struct Bad
  {
    const char* what;
    vec3 center;
    float radius;
  };
  for (const Bad& bad :
       { Bad{ "NaN centre", { 0, kNaN, 0 }, 1.0f }, Bad{ "infinite centre", { kInf, 0, 0 }, 1.0f },
         Bad{ "negative radius", { 0, 0, 0 }, -2.0f }, Bad{ "zero radius", { 0, 0, 0 }, 0.0f },
         Bad{ "NaN radius", { 0, 0, 0 }, kNaN } })
  {
    const SphereSet spheres({ { 1, 1, 1 }, { 2, 2, 2 }, bad.center }, { 1.0f, 1.0f, bad.radius });
    EXPECT_EQ(spheres.report().rejected, 1u) << bad.what;
    EXPECT_EQ(spheres.size(), 2u) << bad.what;
    ASSERT_EQ(spheres.report().reasons.size(), 1u) << bad.what;
    EXPECT_TRUE(anyReasonMentions(spheres.report(), "point 2"))
      << bad.what << ": " << spheres.report().reasons[0];
  }
}

TEST(SphereSet, SizeMismatchesThrow)
{
  const std::vector<vec3> centers{ { 0, 0, 0 }, { 1, 0, 0 } };
  EXPECT_THROW(SphereSet(centers, { 1.0f }), std::invalid_argument);
  EXPECT_THROW(SphereSet(centers, { 1.0f, 1.0f, 1.0f }), std::invalid_argument);
  EXPECT_THROW(SphereSet(centers, {}, 1.0f, { sightline::packRGBA8(1, 2, 3) }),
               std::invalid_argument);
  EXPECT_NO_THROW(
    SphereSet(centers, {}, 1.0f, { sightline::packRGBA8(1, 2, 3), sightline::packRGBA8(4, 5, 6) }));
}

TEST(SphereSet, InvalidDefaultRadiusThrows)
{
  const std::vector<vec3> centers{ { 0, 0, 0 } };
  for (float radius : { 0.0f, -1.0f, kNaN, kInf })
    EXPECT_THROW(SphereSet(centers, {}, radius), std::invalid_argument) << radius;
  // The default is irrelevant when radii are given.
  EXPECT_NO_THROW(SphereSet(centers, { 1.0f }, kNaN));
}

TEST(SphereSet, DefaultRadiusAppliesToEverySphere)
{
  const SphereSet spheres({ { 0, 0, 0 }, { 1, 1, 1 } }, {}, 0.75f);
  ASSERT_EQ(spheres.size(), 2u);
  EXPECT_EQ(spheres.spheres()[0].w, 0.75f);
  EXPECT_EQ(spheres.spheres()[1].w, 0.75f);
}

TEST(SphereSet, BoundsEncloseEveryKeptSphereTightly)
{
  const SphereSet spheres({ { 0, 0, 0 }, { kNaN, 0, 0 }, { 4, -1, 2 }, { -1, 3, 0.5f } },
                          { 1.0f, 100.0f, 0.5f, 2.0f });
  const sightline::Box3 box = spheres.bounds();
  EXPECT_EQ(box.lower, vec3(-3, -1.5f, -1.5f));
  EXPECT_EQ(box.upper, vec3(4.5f, 5, 2.5f));

  const sightline::Box3 second = spheres.bounds(1); // the input's third sphere
  EXPECT_EQ(second.lower, vec3(3.5f, -1.5f, 1.5f));
  EXPECT_EQ(second.upper, vec3(4.5f, -0.5f, 2.5f));

  EXPECT_TRUE(SphereSet({}, {}).bounds().empty());
}

TEST(SphereSet, PrimitiveColorsUnpackRGBA8)
{
  const SphereSet spheres({ { 0, 0, 0 } }, {}, 1.0f, { sightline::packRGBA8(255, 128, 0, 7) });
  const vec3 color = spheres.primitiveColor(0);
  EXPECT_FLOAT_EQ(color.r, 1.0f);
  EXPECT_FLOAT_EQ(color.g, 128 / 255.0f);
  EXPECT_FLOAT_EQ(color.b, 0.0f);
}
} // namespace
