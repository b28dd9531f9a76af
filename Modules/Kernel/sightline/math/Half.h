// SPDX-License-Identifier: BSD-3-Clause
// IEEE 754 binary16 ("half", float16) <-> binary32. Every half is exact as a float; a float
// rounds to the nearest half, ties to even, and beyond 65504 becomes infinite. Header-only and
// free of GLM, so that the IO module's TRX float16 members and the kernel's compact tube
// positions share one conversion.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace sightline
{
/// The float a half stands for (a hot path of compact tubes: bit arithmetic, no branches on
/// normal numbers).
inline float halfToFloat(std::uint16_t half)
{
  const std::uint32_t sign = std::uint32_t(half & 0x8000u) << 16;
  const std::uint32_t exponent = (half >> 10) & 0x1Fu;
  std::uint32_t bits = std::uint32_t(half & 0x7FFFu) << 13; // exponent and fraction in place
  float value;
  if (exponent == 31) // infinities and NaNs keep their fraction
    bits |= 0x7F800000u;
  else if (exponent != 0) // rebias 15 -> 127
    bits += std::uint32_t(127 - 15) << 23;
  else
  {
    // Zero and subnormals: fraction * 2^-24, exact in float.
    value = float(half & 0x3FFu) * 5.9604644775390625e-8f;
    std::memcpy(&bits, &value, 4);
  }
  bits |= sign;
  std::memcpy(&value, &bits, 4);
  return value;
}

/// Whether a float is exactly a finite half (bit tests only: the hot path of compact tubes'
/// build).
inline bool halfHolds(float value)
{
  std::uint32_t bits;
  std::memcpy(&bits, &value, 4);
  const std::uint32_t magnitude = bits & 0x7FFFFFFFu;
  if (magnitude == 0)
    return true;
  const int exponent = int(magnitude >> 23) - 127;
  if (exponent > 15)
    return false; // beyond 65504 (or infinite, NaN)
  if (exponent >= -14)
    return (magnitude & 0x1FFFu) == 0; // a normal half keeps 10 of the 23 fraction bits
  if (exponent < -24)
    return false;
  // A subnormal half is a multiple of 2^-24: of 1.f * 2^exponent, -1 - exponent fraction bits
  // lie below it.
  return (magnitude & ((1u << (-1 - exponent)) - 1u)) == 0;
}

/// The half of a float that halfHolds (bit arithmetic; floatToHalf for any float).
inline std::uint16_t halfOfExact(float value)
{
  std::uint32_t bits;
  std::memcpy(&bits, &value, 4);
  const std::uint16_t sign = std::uint16_t((bits >> 16) & 0x8000u);
  const std::uint32_t magnitude = bits & 0x7FFFFFFFu;
  const int exponent = int(magnitude >> 23) - 127;
  if (magnitude == 0)
    return sign;
  if (exponent >= -14)
    return std::uint16_t(sign | std::uint32_t(exponent + 15) << 10 | ((magnitude >> 13) & 0x3FFu));
  return std::uint16_t(sign | std::uint16_t(std::fabs(value) * 16777216.0f)); // units of 2^-24
}

/// The half nearest a float, ties to even; NaN stays NaN, beyond 65504 gives infinity.
inline std::uint16_t floatToHalf(float value)
{
  std::uint32_t bits;
  std::memcpy(&bits, &value, 4);
  const std::uint16_t sign = std::uint16_t((bits >> 16) & 0x8000u);
  const float magnitude = std::fabs(value);
  if (std::isnan(value))
    return std::uint16_t(sign | 0x7E00u);
  if (magnitude >= 65520.0f) // rounds past the largest half, 65504
    return std::uint16_t(sign | 0x7C00u);
  int exponent;
  std::frexp(magnitude, &exponent); // magnitude = f * 2^exponent, f in [0.5, 1)
  // Halves below 2^-14 are subnormal: a fixed step of 2^-24. Otherwise 10 bits after the point.
  const int step = exponent - 1 < -14 ? -24 : exponent - 11;
  // rint rounds half to even in the default rounding mode; scaling by 2^-step is exact.
  const float units = std::rint(std::ldexp(magnitude, -step));
  const float rounded = std::ldexp(units, step);
  if (rounded == 0.0f)
    return sign;
  int e;
  const float f = std::frexp(rounded, &e);
  if (e - 1 < -14)
    return std::uint16_t(sign | std::uint16_t(units));
  const std::uint16_t fraction = std::uint16_t(std::ldexp(f, 11)) & 0x3FFu;
  return std::uint16_t(sign | ((e - 1 + 15) << 10) | fraction);
}
} // namespace sightline
