// SPDX-License-Identifier: BSD-3-Clause
// float16 conversion (math/Half.h) against its definition: every half is exact as a float and
// comes back; a float rounds to the nearest half, ties to even; halfHolds says exactly which
// floats are halves, and halfOfExact encodes those as floatToHalf does. The reference for
// rounding is the float arithmetic itself (the two neighbouring halves and their midpoint).
#include "sightline/math/Half.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace sightline;

TEST(Half, EveryHalfIsAFloatThatComesBack)
{
  int finite = 0;
  for (unsigned h = 0; h < 65536; ++h)
  {
    const float f = halfToFloat(std::uint16_t(h));
    if (std::isnan(f))
    {
      EXPECT_EQ((h >> 10) & 0x1Fu, 31u) << h;
      EXPECT_TRUE(std::isnan(halfToFloat(floatToHalf(f))));
      continue;
    }
    EXPECT_EQ(floatToHalf(f), h) << h;
    if (!std::isfinite(f))
      continue;
    ++finite;
    EXPECT_TRUE(halfHolds(f)) << h;
    EXPECT_EQ(halfOfExact(f), h) << h;
  }
  EXPECT_EQ(finite, 2 * 31 * 1024); // both signs, 31 exponents (subnormals included)
  EXPECT_EQ(halfToFloat(0x3C00u), 1.0f);
  EXPECT_EQ(halfToFloat(0x7BFFu), 65504.0f);
  EXPECT_EQ(halfToFloat(0x0001u), std::ldexp(1.0f, -24));
  EXPECT_EQ(halfToFloat(0xC000u), -2.0f);
}

TEST(Half, FloatsRoundToTheNearestHalfTiesToEven)
{
  // Between consecutive positive halves a < b: below the midpoint -> a, above -> b, at it the
  // one with an even fraction; and nothing between them is a half.
  for (unsigned h = 0; h < 0x7BFFu; ++h)
  {
    const float a = halfToFloat(std::uint16_t(h)), b = halfToFloat(std::uint16_t(h + 1));
    const float middle = 0.5f * (a + b); // exact: halves have 11 bits
    EXPECT_EQ(floatToHalf(middle), (h % 2 == 0) ? h : h + 1) << h;
    EXPECT_EQ(floatToHalf(std::nextafter(middle, a)), h) << h;
    EXPECT_EQ(floatToHalf(std::nextafter(middle, b)), h + 1) << h;
    EXPECT_FALSE(halfHolds(std::nextafter(a, b))) << h;
    EXPECT_FALSE(halfHolds(-std::nextafter(b, a))) << h;
  }
  EXPECT_EQ(floatToHalf(65519.0f), 0x7BFFu);
  EXPECT_EQ(floatToHalf(65520.0f), 0x7C00u); // rounds past the largest half: infinity
  EXPECT_FALSE(halfHolds(65520.0f));
  EXPECT_FALSE(halfHolds(std::numeric_limits<float>::infinity()));
  EXPECT_FALSE(halfHolds(std::ldexp(1.0f, -25)));
  EXPECT_FALSE(halfHolds(std::numeric_limits<float>::denorm_min()));
}

TEST(Half, HalfHoldsExactlyTheFloatsThatRoundTrip)
{
  std::mt19937 rng(3);
  for (int i = 0; i < 200000; ++i)
  {
    std::uint32_t bits = rng();
    if (i % 2) // many with the low fraction bits clear, where halves are
      bits &= 0xFFFFE000u;
    float f;
    std::memcpy(&f, &bits, 4);
    if (std::isnan(f))
      continue;
    const bool roundTrips = std::isfinite(f) && halfToFloat(floatToHalf(f)) == f;
    ASSERT_EQ(halfHolds(f), roundTrips) << std::hexfloat << f;
    if (roundTrips)
    {
      ASSERT_EQ(halfOfExact(f), floatToHalf(f)) << std::hexfloat << f;
    }
  }
}
