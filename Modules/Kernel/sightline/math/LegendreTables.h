// SPDX-License-Identifier: BSD-3-Clause
// Recurrence constants of the canonical SH basis, shared by the general evaluation
// (SphericalHarmonics.cpp) and the glyph kernel's batched sums (SHGlyph.cpp), so both compute
// the same values (internal header).
#pragma once

#include "sightline/math/Math.h"
#include "sightline/math/SphericalHarmonics.h"

#include <cmath>

namespace sightline
{
namespace detail
{
constexpr int kTableSize = kMaxSHOrder + 1;

/// Recurrence constants for S_l^m = c_m N_lm d^m/dz^m P_l(z), c_0 = 1, c_m = sqrt(2):
///   S_m^m = start[m],  S_{m+1}^m = sqrt(2m+3) z S_m^m,  S_l^m = a z S_{l-1}^m - b S_{l-2}^m,
/// and dS_l^m/dz = up[l][m] S_l^{m+1}. Computed once in double.
struct LegendreTables
{
  double start[kTableSize];
  double a[kTableSize][kTableSize];
  double b[kTableSize][kTableSize];
  double up[kTableSize][kTableSize];

  LegendreTables()
  {
    for (int m = 0; m < kTableSize; ++m)
    {
      // N_mm (2m-1)!! = sqrt((2m+1)/(4 pi) / (2m)!) (2m-1)!!, built as a running product so
      // that no factorial overflows: (2m-1)!!^2 / (2m)! = prod_{i=1..m} (2i-1)/(2i).
      double ratio = 1.0;
      for (int i = 1; i <= m; ++i)
        ratio *= double(2 * i - 1) / double(2 * i);
      start[m] = std::sqrt((2 * m + 1) / (4.0 * kPi) * ratio) * (m == 0 ? 1.0 : std::sqrt(2.0));
      for (int l = 0; l < kTableSize; ++l)
      {
        a[l][m] = b[l][m] = up[l][m] = 0.0;
        if (l > m)
        {
          const double lm = double(l - m) * double(l + m);
          a[l][m] = std::sqrt(double(2 * l + 1) * double(2 * l - 1) / lm);
          if (l > m + 1)
            b[l][m] = std::sqrt(
              double(2 * l + 1) * double(l + m - 1) * double(l - m - 1) / (double(2 * l - 3) * lm));
        }
        if (l > m)
          up[l][m] = std::sqrt(double(l + m + 1) * double(l - m)) / (m == 0 ? std::sqrt(2.0) : 1.0);
      }
    }
  }
};

inline const LegendreTables& legendreTables()
{
  static const LegendreTables instance;
  return instance;
}
} // namespace detail
} // namespace sightline
