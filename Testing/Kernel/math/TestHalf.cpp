// SPDX-License-Identifier: BSD-3-Clause
// float16 conversion (math/Half.h) against its definition: every half is exact as a float and
// comes back; a float rounds to the nearest half, ties to even; halfHolds says exactly which
// floats are halves, and halfOfExact encodes those as floatToHalf does. The reference for
// rounding is the float arithmetic itself (the two neighbouring halves and their midpoint).
#include "sightline/math/Half.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

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

TEST(Half, ArraysEncodeAsTheirValuesDo)
{
  // halvesOfExact() (the CPU's conversion, eight at a time, where it has one) against
  // halfHolds/halfOfExact value by value: every finite half in one array, then arrays with one
  // value that is not a half, at every position of a block of eight and of the tail.
  std::vector<float> values;
  std::vector<std::uint16_t> expected;
  for (unsigned h = 0; h < 65536; ++h)
  {
    const float f = halfToFloat(std::uint16_t(h));
    if (std::isfinite(f))
    {
      values.push_back(f);
      expected.push_back(std::uint16_t(h));
    }
  }
  std::vector<std::uint16_t> out(values.size());
  ASSERT_TRUE(halvesOfExact(values.data(), values.size(), out.data()));
  EXPECT_EQ(out, expected);
  const float notHalves[] = { std::nextafter(1.0f, 2.0f), 65520.0f, -70000.0f,
    std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
    std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::signaling_NaN(),
    std::numeric_limits<float>::denorm_min(), std::ldexp(1.0f, -25), 1e-30f };
  std::mt19937 rng(5);
  for (float bad : notHalves)
    for (std::size_t at = 0; at < 19; ++at)
    {
      std::vector<float> some(19);
      for (float& v : some)
        v = values[rng() % values.size()];
      some[at] = bad;
      std::vector<std::uint16_t> encoded(some.size());
      EXPECT_FALSE(halvesOfExact(some.data(), some.size(), encoded.data())) << bad << " at " << at;
      some[at] = values[at];
      ASSERT_TRUE(halvesOfExact(some.data(), some.size(), encoded.data()));
      for (std::size_t i = 0; i < some.size(); ++i)
        EXPECT_EQ(encoded[i], halfOfExact(some[i]));
    }
}

TEST(Half, ArraysDecodeAsTheirValuesDo)
{
  // halvesToFloats() against halfToFloat, bit for bit (signalling NaNs keep their bits): all
  // 65536 halves in order, from an odd address; then runs of finite halves with one infinity
  // or NaN at every position of a block of eight and of the tail.
  std::vector<unsigned char> bytes(2 * 65536 + 1);
  for (unsigned h = 0; h < 65536; ++h)
  {
    const std::uint16_t half = std::uint16_t(h);
    std::memcpy(bytes.data() + 1 + 2 * h, &half, 2);
  }
  auto expectSame = [](const unsigned char* halves, std::size_t count)
  {
    std::vector<float> out(count);
    halvesToFloats(halves, count, out.data());
    for (std::size_t i = 0; i < count; ++i)
    {
      std::uint16_t half;
      std::memcpy(&half, halves + 2 * i, 2);
      const float f = halfToFloat(half);
      ASSERT_EQ(std::memcmp(&out[i], &f, 4), 0) << "half " << half << " at " << i;
    }
  };
  expectSame(bytes.data() + 1, 65536);
  std::mt19937 rng(7);
  for (std::uint16_t special : { std::uint16_t(0x7C00), std::uint16_t(0xFC00), std::uint16_t(0x7C01), std::uint16_t(0xFE00) })
    for (std::size_t at = 0; at < 21; ++at)
    {
      std::vector<std::uint16_t> run(21);
      for (std::uint16_t& h : run)
        h = std::uint16_t(rng() % 0x7C00u);
      run[at] = special;
      expectSame(reinterpret_cast<const unsigned char*>(run.data()), run.size());
    }
}
