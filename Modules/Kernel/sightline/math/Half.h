// SPDX-License-Identifier: BSD-3-Clause
// IEEE 754 binary16 ("half", float16) <-> binary32. Every half is exact as a float; a float
// rounds to the nearest half, ties to even, and beyond 65504 becomes infinite. Header-only and
// free of GLM, so that the IO module's TRX float16 members and the kernel's compact tube
// positions share one conversion.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#include <immintrin.h>
#define SIGHTLINE_HALF_F16C 1
#endif

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

#ifdef SIGHTLINE_HALF_F16C
namespace detail
{
/// Whether this CPU converts halves itself (F16C, with the AVX state the OS saves): every x86
/// CPU since 2012, tested at run time because builds target the plain x86-64 baseline.
inline bool cpuConvertsHalves()
{
  static const bool converts = []
  {
    unsigned a, b, c, d;
    if (!__get_cpuid(1, &a, &b, &c, &d) || !(c & (1u << 29)) || !(c & (1u << 28)) || !(c & (1u << 27)))
      return false;
    unsigned low, high;
    __asm__("xgetbv" : "=a"(low), "=d"(high) : "c"(0));
    return (low & 6u) == 6u;
  }();
  return converts;
}

/// halvesOfExact() eight values at a time; returns how many it encoded (a multiple of 8), or
/// ~0 where one of them is not a finite half.
__attribute__((target("avx,f16c"))) inline std::size_t halvesOfExactF16C(
  const float* values, std::size_t count, std::uint16_t* out)
{
  // Compared as bits, not as floats: the same answer whatever MXCSR's denormal modes (a float
  // denormal, never a half, then converts to a zero of other bits). 65504, the largest half,
  // is 0x477FE000; above it come infinity and NaN.
  const __m128i magnitude = _mm_set1_epi32(0x7FFFFFFF), largest = _mm_set1_epi32(0x477FE000);
  auto exact = [&](__m128i value, __m128i back)
  {
    return _mm_andnot_si128(_mm_cmpgt_epi32(_mm_and_si128(value, magnitude), largest), _mm_cmpeq_epi32(value, back));
  };
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8)
  {
    const __m256 v = _mm256_loadu_ps(values + i);
    const __m128i h = _mm256_cvtps_ph(v, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    const __m256i bits = _mm256_castps_si256(v), back = _mm256_castps_si256(_mm256_cvtph_ps(h));
    const __m128i both = _mm_and_si128(
      exact(_mm256_castsi256_si128(bits), _mm256_castsi256_si128(back)),
      exact(_mm256_extractf128_si256(bits, 1), _mm256_extractf128_si256(back, 1)));
    if (_mm_movemask_epi8(both) != 0xFFFF)
      return ~std::size_t(0);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), h);
  }
  return i;
}
/// halvesToFloats() eight at a time; returns how many it converted. Blocks holding an infinity
/// or NaN are left to halfToFloat (the CPU quiets signalling NaNs; halfToFloat keeps their bits).
__attribute__((target("avx,f16c"))) inline std::size_t halvesToFloatsF16C(
  const void* halves, std::size_t count, float* out)
{
  const auto* bytes = static_cast<const unsigned char*>(halves);
  const __m128i exponent = _mm_set1_epi16(0x7C00);
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8)
  {
    const __m128i h = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + 2 * i));
    if (_mm_movemask_epi8(_mm_cmpeq_epi16(_mm_and_si128(h, exponent), exponent)) != 0)
      break;
    _mm256_storeu_ps(out + i, _mm256_cvtph_ps(h));
  }
  return i;
}
} // namespace detail
#endif

/// halfToFloat() of `count` halves (native byte order, any alignment) into `out`, with the
/// CPU's conversion instructions where it has them: a whole-brain tractogram's float16
/// positions are 3 * 10^9 halves.
inline void halvesToFloats(const void* halves, std::size_t count, float* out)
{
  const auto* bytes = static_cast<const unsigned char*>(halves);
  std::size_t i = 0;
  while (i < count)
  {
#ifdef SIGHTLINE_HALF_F16C
    if (detail::cpuConvertsHalves())
      i += detail::halvesToFloatsF16C(bytes + 2 * i, count - i, out + i);
#endif
    // A block the CPU left (or the tail, or every value without it): value by value.
    for (const std::size_t end = std::min(count, i + 8); i < end; ++i)
    {
      std::uint16_t half;
      std::memcpy(&half, bytes + 2 * i, 2);
      out[i] = halfToFloat(half);
    }
  }
}

/// halfOfExact() of `count` values into `out`; false (with `out` partly written) where one is not
/// a finite half (halfHolds). With the CPU's conversion instructions where it has them: the
/// streamed build of compact tubes encodes 10^9 positions.
inline bool halvesOfExact(const float* values, std::size_t count, std::uint16_t* out)
{
  std::size_t i = 0;
#ifdef SIGHTLINE_HALF_F16C
  if (detail::cpuConvertsHalves())
  {
    i = detail::halvesOfExactF16C(values, count, out);
    if (i > count)
      return false;
  }
#endif
  for (; i < count; ++i)
  {
    if (!halfHolds(values[i]))
      return false;
    out[i] = halfOfExact(values[i]);
  }
  return true;
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
