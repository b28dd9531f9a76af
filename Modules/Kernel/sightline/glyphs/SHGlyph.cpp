// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/glyphs/SHGlyph.h"

#include "sightline/math/PolynomialRoots.h"

#include "sightline/math/LegendreTables.h"
#include "sightline/math/SphereSampling.h"

#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace sightline
{
namespace
{
// An AVX2 clone beside the portable one, chosen when the library loads (an ELF ifunc), where
// the compiler and platform offer it: x86-64 Linux with GCC or Clang; elsewhere the portable
// code alone. Helpers meant to run at the clone's width are forced inline into it.
// Not with Clang 19 (Debian 13's): it leaves the template instantiations that only the clones
// use (the tables' constructors, std::call_once's helpers) undefined, and the kernel does not
// link. Clang 14 and GCC 12 and 14 are fine.
#if defined(__x86_64__) && defined(__ELF__) && (defined(__GNUC__) || defined(__clang__)) && \
  !(defined(__clang__) && __clang_major__ >= 19)
#define SIGHTLINE_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#define SIGHTLINE_INLINE_INTO_CLONES __attribute__((always_inline)) inline
#else
#define SIGHTLINE_AVX2_CLONES
#define SIGHTLINE_INLINE_INTO_CLONES inline
#endif

constexpr long double kPiLong = kPiOf<long double>;
constexpr int kOrderSlots = kMaxGlyphOrder / 2 + 1;

/// Per-order constants of Algorithm 1, computed once in long double.
template <class T>
struct RayTables
{
  int order = 0;
  T u[kMaxGlyphOrder + 1]; ///< sample points (u_l, v_l) on the unit half circle
  T v[kMaxGlyphOrder + 1];
  T inverseVandermonde[kMaxGlyphOrder + 1][kMaxGlyphOrder + 1];
  /// max over the unit circle of |u^i v^(k-i)| = sqrt(i^i (k-i)^(k-i) / k^k) (Appendix B; the
  /// factorials in Section 3.5's version of this formula would give a bound that is too small).
  T circleBound[kMaxGlyphOrder + 1];
  T binomial[kMaxGlyphOrder + 2]; ///< C(k+1, j)
  /// max over the unit circle of |u^i v^(k+1-i)|: bounds g(u, v) v, whose maximum is the
  /// largest distance of the glyph's cross-section from the ray's line through the centre.
  T sineBound[kMaxGlyphOrder + 1];
  /// The cross-section's height test: q(theta) = g(cos, sin) sin, a trigonometric polynomial of
  /// degree k + 1, sampled at M = heightSamples = 4 (k + 1) angles theta_j = (j + 1/2) pi / M
  /// of [0, pi) (|q| has period pi): heightBasis[i][j] = cos^i sin^(k+1-i) at theta_j, zero
  /// past M.
  static constexpr int kMaxHeightSamples = 4 * (kMaxGlyphOrder + 1);
  int heightSamples = 0;
  T heightBasis[kMaxGlyphOrder + 2][kMaxHeightSamples];
  /// max |q| <= heightFactor * max_j |q(theta_j)| (see intersectOrder).
  T heightFactor = T(1);
  /// Between neighbouring samples |q| exceeds the larger of their values by at most
  /// heightCurvature * max |q| (|q''| <= m^2 max |q|, half spacing pi / (2 M)).
  T heightCurvature = T(0);
  T heightCotangent[kMaxHeightSamples]; ///< cot theta_j
  /// The entry certificate's finer samples: each interval [theta_j, theta_(j+1)] cut in
  /// kEntryCuts pieces, fineBasis[i][(kEntryCuts - 1) j + s - 1] at theta_j + s pi / (kEntryCuts M).
  static constexpr int kEntryCuts = 4;
  static constexpr int kMaxFineSamples = (kEntryCuts - 1) * kMaxHeightSamples;
  T fineBasis[kMaxGlyphOrder + 2][kMaxFineSamples];
  T fineCotangent[kMaxFineSamples];
  /// q' and q'' at the middle of each piece: the basis functions' derivatives in theta,
  /// [i][kEntryCuts j + p] for piece p of [theta_j, theta_(j+1)] (per order: K + 1 rows).
  std::vector<T> pieceFirst, pieceSecond;
  int pieceStride = 0;
  /// The basis at a piece's quarter points, [i][3 (kEntryCuts j + p) + s] at theta_j + (p + (s +
  /// 1) / 4) pi / (kEntryCuts M): a piece that may reach eo but ends outside is checked on its
  /// quarters (a sixteenth of its curvature margin) before the certificate gives up.
  std::vector<T> pieceQuarters;
  /// On a piece of width delta, |q'(theta)| >= |q'(mid)| - (delta / 2) |q''(mid)| - delta^2 /
  /// 8 max|q'''|, and |q'''| <= m^3 max|q| (Bernstein): pieceHalfWidth = delta / 2,
  /// pieceCubic = delta^2 m^3 / 8 (with a relative margin against rounding).
  T pieceHalfWidth = T(0);
  T pieceCubic = T(0);

  explicit RayTables(int k) : order(k)
  {
    const int n = k + 1;
    long double V[kMaxGlyphOrder + 1][2 * (kMaxGlyphOrder + 1)];
    for (int l = 0; l < n; ++l)
    {
      const long double angle = l * kPiLong / n;
      const long double ul = std::cos(angle), vl = std::sin(angle);
      u[l] = T(ul);
      v[l] = T(vl);
      for (int i = 0; i < n; ++i)
      {
        V[l][i] = std::pow(ul, i) * std::pow(vl, k - i);
        V[l][n + i] = l == i ? 1.0L : 0.0L;
      }
    }
    // Gauss-Jordan with partial pivoting on [V | I].
    for (int col = 0; col < n; ++col)
    {
      int pivot = col;
      for (int r = col + 1; r < n; ++r)
        if (std::abs(V[r][col]) > std::abs(V[pivot][col]))
          pivot = r;
      for (int c = 0; c < 2 * n; ++c)
        std::swap(V[col][c], V[pivot][c]);
      const long double inv = 1.0L / V[col][col];
      for (int c = 0; c < 2 * n; ++c)
        V[col][c] *= inv;
      for (int r = 0; r < n; ++r)
        if (r != col && V[r][col] != 0.0L)
        {
          const long double factor = V[r][col];
          for (int c = 0; c < 2 * n; ++c)
            V[r][c] -= factor * V[col][c];
        }
    }
    for (int i = 0; i < n; ++i)
      for (int l = 0; l < n; ++l)
        inverseVandermonde[i][l] = T(V[i][n + l]);
    for (int i = 0; i < n; ++i)
    {
      const long double a = i == 0 ? 1.0L : std::pow((long double)i, i);
      const long double b = k - i == 0 ? 1.0L : std::pow((long double)(k - i), k - i);
      circleBound[i] = k == 0 ? T(1) : T(std::sqrt(a * b / std::pow((long double)k, k)));
    }
    for (int i = 0; i < n; ++i)
    {
      const long double a = i == 0 ? 1.0L : std::pow((long double)i, i);
      const long double b = std::pow((long double)(n - i), n - i);
      sineBound[i] = T(std::sqrt(a * b / std::pow((long double)n, n)) * (1.0L + 1e-6L));
    }
    // Bernstein's inequality for a trigonometric polynomial of degree m = k + 1 gives
    // |q''| <= m^2 max|q|; at the maximum q' = 0 and the nearest sample is within pi / (2 M):
    // |q(theta_j)| >= max|q| (1 - m^2 pi^2 / (8 M^2)). M = 4 m: a factor of 1.084.
    heightSamples = 4 * (k + 1);
    for (int j = 0; j < kMaxHeightSamples; ++j)
    {
      const long double angle = (j + 0.5L) * kPiLong / heightSamples;
      const bool used = j < heightSamples;
      for (int i = 0; i <= k + 1; ++i)
        heightBasis[i][j] = used ? T(std::pow(std::cos(angle), i) * std::pow(std::sin(angle), k + 1 - i)) : T(0);
      heightCotangent[j] = used ? T(std::cos(angle) / std::sin(angle)) : T(0);
    }
    // Powers by repeated products (std::pow in long double for every entry of every order
    // took 70 ms at the first glyph test); c^i and s^i for i <= k + 3.
    const auto powers = [k](long double x, long double* out)
    {
      out[0] = 1.0L;
      for (int i = 1; i <= k + 3; ++i)
        out[i] = out[i - 1] * x;
    };
    long double cosPower[kMaxGlyphOrder + 4], sinPower[kMaxGlyphOrder + 4];
    for (int j = 0; j < kMaxHeightSamples; ++j)
      for (int cut = 1; cut < kEntryCuts; ++cut)
      {
        const int slot = (kEntryCuts - 1) * j + cut - 1;
        const long double angle = (j + 0.5L + (long double)cut / kEntryCuts) * kPiLong / heightSamples;
        const bool used = j + 1 < heightSamples;
        powers(std::cos(angle), cosPower);
        powers(std::sin(angle), sinPower);
        for (int i = 0; i <= k + 1; ++i)
          fineBasis[i][slot] = used ? T(cosPower[i] * sinPower[k + 1 - i]) : T(0);
        fineCotangent[slot] = used ? T(std::cos(angle) / std::sin(angle)) : T(0);
      }
    const long double m = k + 1;
    {
      const long double delta = kPiLong / (kEntryCuts * heightSamples);
      pieceHalfWidth = T(delta / 2 * (1.0L + 1e-6L));
      pieceCubic = T(delta * delta * m * m * m / 8 * (1.0L + 1e-6L));
      pieceStride = kEntryCuts * heightSamples;
      pieceFirst.assign(std::size_t(k + 1) * pieceStride, T(0));
      pieceSecond.assign(std::size_t(k + 1) * pieceStride, T(0));
      // d/dtheta of c^i s^n (n = m - i) and the second derivative, with c = cos, s = sin.
      const auto term = [&](long double factor, int a, int b)
      { return factor == 0.0L ? 0.0L : factor * cosPower[a] * sinPower[b]; };
      for (int slot = 0; slot < pieceStride; ++slot)
      {
        const long double angle = (0.5L + (slot + 0.5L) / kEntryCuts) * kPiLong / heightSamples;
        powers(std::cos(angle), cosPower);
        powers(std::sin(angle), sinPower);
        for (int i = 0; i <= k; ++i)
        {
          const int n = k + 1 - i;
          pieceFirst[std::size_t(i) * pieceStride + slot] = T(term(-i, i - 1, n + 1) + term(n, i + 1, n - 1));
          pieceSecond[std::size_t(i) * pieceStride + slot] = T(term(i * (i - 1.0L), i - 2, n + 2) -
            term(i * (n + 1.0L) + n * (i + 1.0L), i, n) + term(n * (n - 1.0L), i + 2, n - 2));
        }
      }
      pieceQuarters.assign(std::size_t(k + 1) * 3 * pieceStride, T(0));
      for (int slot = 0; slot < pieceStride; ++slot)
        for (int quarter = 0; quarter < 3; ++quarter)
        {
          const long double angle = (0.5L + (slot + (quarter + 1) / 4.0L) / kEntryCuts) * kPiLong / heightSamples;
          powers(std::cos(angle), cosPower);
          powers(std::sin(angle), sinPower);
          for (int i = 0; i <= k; ++i)
            pieceQuarters[(std::size_t(i) * pieceStride + slot) * 3 + quarter] = T(cosPower[i] * sinPower[k + 1 - i]);
        }
    }
    const long double curvature = m * m * kPiLong * kPiLong / (8.0L * heightSamples * heightSamples);
    heightCurvature = T(curvature);
    heightFactor = T(1.0L / (1.0L - curvature));
    long double c = 1.0L;
    for (int j = 0; j <= k + 1; ++j)
    {
      binomial[j] = T(c);
      c = c * (k + 1 - j) / (j + 1);
    }
  }
};

template <class T>
const RayTables<T>& rayTables(int order)
{
  // Built per order at its first use: a scene of one order pays for its tables only.
  // Once built, one atomic load per call (this runs for every ray-glyph test).
  static std::atomic<const RayTables<T>*> ready[kOrderSlots];
  if (const RayTables<T>* tables = ready[order / 2].load(std::memory_order_acquire))
    return *tables;
  static std::unique_ptr<RayTables<T>> tables[kOrderSlots];
  static std::once_flag flags[kOrderSlots];
  std::call_once(flags[order / 2], [order]
  {
    tables[order / 2] = std::make_unique<RayTables<T>>(order);
    ready[order / 2].store(tables[order / 2].get(), std::memory_order_release);
  });
  return *tables[order / 2];
}

/// The canonical basis's recurrence constants (detail::LegendreTables) in the arithmetic T of
/// the batch below, so it reproduces evaluateSHSum.
template <class T>
struct BatchLegendre
{
  T start[kMaxGlyphOrder + 1];
  T first[kMaxGlyphOrder + 1]; ///< sqrt(2m + 3): S_{m+1}^m = first[m] z S_m^m
  T a[kMaxGlyphOrder + 1][kMaxGlyphOrder + 1];
  T b[kMaxGlyphOrder + 1][kMaxGlyphOrder + 1];
  BatchLegendre()
  {
    const detail::LegendreTables& t = detail::legendreTables();
    for (int m = 0; m <= kMaxGlyphOrder; ++m)
    {
      start[m] = T(t.start[m]);
      first[m] = T(std::sqrt(double(2 * m + 3)));
      for (int l = 0; l <= kMaxGlyphOrder; ++l)
      {
        a[l][m] = T(t.a[l][m]);
        b[l][m] = T(t.b[l][m]);
      }
    }
  }
};

template <class T>
const BatchLegendre<T>& batchLegendre()
{
  static const BatchLegendre<T> instance;
  return instance;
}

/// Directions of the batch below: K + 1 rounded up to whole 32-byte vectors of T.
template <int K, class T>
constexpr int kBatchLanes = (K + 1 + 32 / int(sizeof(T)) - 1) / (32 / int(sizeof(T))) * (32 / int(sizeof(T)));

/// evaluateSHSum at the K + 1 directions (x[l], y[l], z[l]) at once: the recurrences are the
/// same for every direction, so they run on vectors of directions (GCC vector extensions: two
/// SSE2 registers each in the portable clone, one AVX2 register in the other); constants and
/// coefficients are loaded once per ray instead of once per direction. The arrays hold
/// kBatchLanes<K, T> entries (the padding lanes are ignored). Each direction's sum keeps the
/// order of evaluateSHSum's.
template <int K, class T>
SIGHTLINE_INLINE_INTO_CLONES void evaluateSHSumBatch(const T* coefficients, const T* x, const T* y, const T* z, T* sum)
{
  typedef T Vector __attribute__((vector_size(32)));
  constexpr int lanes = 32 / int(sizeof(T));
  constexpr int n = kBatchLanes<K, T> / lanes;
  const BatchLegendre<T>& t = batchLegendre<T>();
  Vector X[n], Y[n], Z[n], A[n], B[n], total[n];
  for (int v = 0; v < n; ++v)
  {
    std::memcpy(&X[v], x + v * lanes, sizeof(Vector));
    std::memcpy(&Y[v], y + v * lanes, sizeof(Vector));
    std::memcpy(&Z[v], z + v * lanes, sizeof(Vector));
    A[v] = Vector{} + T(1);
    B[v] = Vector{};
    total[v] = Vector{};
  }
  for (int m = 0; m <= K; ++m)
  {
    if (m > 0)
      for (int v = 0; v < n; ++v)
      {
        const Vector nextA = X[v] * A[v] - Y[v] * B[v];
        B[v] = X[v] * B[v] + Y[v] * A[v];
        A[v] = nextA;
      }
    const bool even = m % 2 == 0;
    const T cA0 = even ? coefficients[shIndex(m, m)] : T(0);
    const T cB0 = even && m > 0 ? coefficients[shIndex(m, -m)] : T(0);
    Vector previous[n], current[n], weightA[n], weightB[n];
    for (int v = 0; v < n; ++v)
    {
      previous[v] = Vector{} + t.start[m];
      current[v] = previous[v];
      weightA[v] = cA0 * current[v];
      weightB[v] = cB0 * current[v];
    }
    if (m + 1 <= K)
    {
      for (int v = 0; v < n; ++v)
        current[v] = t.first[m] * Z[v] * previous[v];
      if (!even)
      {
        const T cA = coefficients[shIndex(m + 1, m)];
        const T cB = coefficients[shIndex(m + 1, -m)];
        for (int v = 0; v < n; ++v)
        {
          weightA[v] += cA * current[v];
          weightB[v] += cB * current[v];
        }
      }
    }
    for (int l = m + 2; l <= K; ++l)
    {
      const T al = t.a[l][m], bl = t.b[l][m];
      for (int v = 0; v < n; ++v)
      {
        const Vector next = al * Z[v] * current[v] - bl * previous[v];
        previous[v] = current[v];
        current[v] = next;
      }
      if (l % 2 == 0)
      {
        const T cA = coefficients[shIndex(l, m)];
        const T cB = m == 0 ? T(0) : coefficients[shIndex(l, -m)];
        for (int v = 0; v < n; ++v)
        {
          weightA[v] += cA * current[v];
          weightB[v] += cB * current[v];
        }
      }
    }
    for (int v = 0; v < n; ++v)
      total[v] += weightA[v] * A[v] + weightB[v] * B[v];
  }
  for (int v = 0; v < n; ++v)
    std::memcpy(sum + v * lanes, &total[v], sizeof(Vector));
}

/// E(w) = |h(w)| - (w^2 + eps^2)^((K+1)/2), with E'(w) in `derivative`. Along the ray
/// E = r^(K+1) (|q| / eo - 1) (r = sqrt(w^2 + eps^2), the distance from the centre): E has the
/// sign of P = h^2 - r^(2K+2) = E (|h| + r^(K+1)), without P's degree 2K + 2 or its squared
/// coefficients.
template <int K, class T>
SIGHTLINE_INLINE_INTO_CLONES T entryFunction(const T* h, T eps2, T x, T& derivative)
{
  T value = h[K], slope = T(0);
  for (int i = K - 1; i >= 0; --i)
  {
    slope = slope * x + value;
    value = value * x + h[i];
  }
  const T r2 = x * x + eps2;
  T rK = T(1); // r^K, K even
  for (int i = 0; i < K / 2; ++i)
    rK *= r2;
  const T r = std::sqrt(r2);
  derivative = (value < T(0) ? -slope : slope) - T(K + 1) * x * rK / r;
  return std::abs(value) - rK * r;
}

/// The root of E in [a, b], E(a) < 0 < E(b), E changing sign once there (the entry certificate
/// proves it), from the guess x: Newton steps that would leave the bracket become bisections,
/// as in detail::monotonicRootFrom.
template <int K, class T>
SIGHTLINE_INLINE_INTO_CLONES T entryRootOnPiece(const T* h, T eps2, T a, T b, T x, T tolerance, int maxIterations)
{
  if (!(x > a && x < b))
    x = T(0.5) * (a + b);
  for (int iteration = 0; iteration < maxIterations; ++iteration)
  {
    T slope;
    const T value = entryFunction<K>(h, eps2, x, slope);
    if (value == T(0))
      return x;
    if (value < T(0))
      a = x;
    else
      b = x;
    const T next = x - value / slope;
    if (next > a && next < b) // false for a zero slope and NaN too
    {
      if (std::abs(next - x) <= tolerance)
        return next;
      x = next;
    }
    else
      x = T(0.5) * (a + b);
    if (b - a <= tolerance)
      return x;
  }
  return x;
}

template <int K, class T>
SIGHTLINE_INLINE_INTO_CLONES int intersectOrder(const T* b, const T o[3], const T d[3], T tmin,
  T tmax, T tolerance, T* t, bool firstOnly)
{
  const RayTables<T>& tab = rayTables<T>(K);
  const auto evaluate = [](const T* c, T x, T y, T z) { return evaluateSHSum<T>(K, c, x, y, z); };
  const T dO = d[0] * o[0] + d[1] * o[1] + d[2] * o[2];
  T e[3] = { o[0] - dO * d[0], o[1] - dO * d[1], o[2] - dO * d[2] };
  const T eo = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
  if (eo > T(0))
  {
    e[0] /= eo;
    e[1] /= eo;
    e[2] /= eo;
  }
  else
  {
    // The ray passes through the centre: the plane is any plane containing d.
    const int axis = std::abs(d[0]) < std::abs(d[1]) ? (std::abs(d[0]) < std::abs(d[2]) ? 0 : 2)
                                                     : (std::abs(d[1]) < std::abs(d[2]) ? 1 : 2);
    T a[3] = { T(0), T(0), T(0) };
    a[axis] = T(1);
    e[0] = a[0] - d[axis] * d[0];
    e[1] = a[1] - d[axis] * d[1];
    e[2] = a[2] - d[axis] * d[2];
    const T length = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    e[0] /= length;
    e[1] /= length;
    e[2] /= length;
  }

  // g(u_l, v_l) = F(u_l d + v_l e) on the great circle, then g's coefficients.
  T samples[kBatchLanes<K, T>];
  {
    T x[kBatchLanes<K, T>] = {}, y[kBatchLanes<K, T>] = {}, z[kBatchLanes<K, T>] = {};
    for (int l = 0; l <= K; ++l)
    {
      x[l] = tab.u[l] * d[0] + tab.v[l] * e[0];
      y[l] = tab.u[l] * d[1] + tab.v[l] * e[1];
      z[l] = tab.u[l] * d[2] + tab.v[l] * e[2];
    }
    evaluateSHSumBatch<K, T>(b, x, y, z, samples);
  }
  T g[K + 1];
  T gmax = T(0), sineMax = T(0);
  for (int i = 0; i <= K; ++i)
  {
    T sum = T(0);
    for (int l = 0; l <= K; ++l)
      sum += tab.inverseVandermonde[i][l] * samples[l];
    g[i] = sum;
    gmax += std::abs(sum) * tab.circleBound[i];
    sineMax += std::abs(sum) * tab.sineBound[i];
  }
  // Early outs: the ray's distance from the centre exceeds the glyph's bounding circle, or the
  // bound on |g(u, v) v| (the cross-section's distance from the line through the centre
  // parallel to the ray; sineBound carries a relative margin of 1e-6 against rounding).
  if (!(gmax > eo) || !(sineMax > eo))
    return 0;
  // The tighter test: the ray (height eo above the line through the centre, in the plane)
  // meets the glyph's cross-section r = |g(cos, sin)| only if the section's largest height
  // max |q|, q = g(cos, sin) sin, reaches eo. Sampled q with Bernstein's bound, plus the
  // samples' rounding error (|basis| <= 1): most rays that pass through a glyph's box but
  // not through its lobes stop here, before the polynomial and its root isolation.
  constexpr int M = 4 * (K + 1);
  T q[M];
  T heightBound = T(0), heightRounding = T(0);
  if (eo > T(0))
  {
    for (int j = 0; j < M; ++j)
      q[j] = T(0);
    T magnitude = T(0);
    for (int i = 0; i <= K; ++i)
    {
      // g(u, v) sin = sum_i g_i u^i v^(k-i) v = sum_i g_i u^i v^(k+1-i).
      const T gi = g[i];
      magnitude += std::abs(gi);
      for (int j = 0; j < M; ++j)
        q[j] += gi * tab.heightBasis[i][j];
    }
    T height = T(0);
    for (int j = 0; j < M; ++j)
      height = std::max(height, std::abs(q[j]));
    heightRounding = T(4 * (K + 2)) * std::numeric_limits<T>::epsilon() * magnitude;
    heightBound = (height + heightRounding) * tab.heightFactor;
    if (heightBound < eo)
      return 0;
  }

  // In units of gmax: w = (t + d.o) / gmax along the ray, eps = (e.o) / gmax <= 1, and
  //   P(w) = h(w)^2 - (w^2 + eps^2)^(k+1),  h(w) = sum_i g_i / gmax * eps^(k-i) w^i.
  const T scale = T(1) / gmax;
  const T eps = eo * scale;
  const T eps2 = eps * eps;
  T h[K + 1];
  T power = T(1);
  for (int i = K; i >= 0; --i)
  {
    h[i] = g[i] * scale * power;
    power *= eps;
  }
  // P's coefficients only where the root isolation needs them: a hit that the entry
  // certificate below places is refined on h directly.
  constexpr int N = 2 * K + 2;
  T P[N + 1];
  bool havePolynomial = false;
  const auto buildPolynomial = [&]
  {
    if (havePolynomial)
      return;
    havePolynomial = true;
    for (int i = 0; i <= N; ++i)
      P[i] = T(0);
    for (int i = 0; i <= K; ++i)
    {
      P[2 * i] += h[i] * h[i];
      for (int j = i + 1; j <= K; ++j)
        P[i + j] += T(2) * h[i] * h[j];
    }
    T eps2Power = T(1); // eps^(2 (k+1-j)), built from j = k+1 downwards
    for (int j = K + 1; j >= 0; --j)
    {
      P[2 * j] -= tab.binomial[j] * eps2Power;
      eps2Power *= eps2;
    }
  };

  // Roots lie within the bounding circle |w| <= sqrt(1 - eps^2); the bound is attained for a
  // sphere, so widen it by a few ulps to keep those roots inside the interval.
  const T wmax = std::sqrt(std::max(T(0), T(1) - eps2)) * (T(1) + T(16) * std::numeric_limits<T>::epsilon());
  T lo = std::max(-wmax, (tmin + dO) * scale);
  T hi = std::min(wmax, (tmax + dO) * scale);
  // The ray is inside the glyph exactly where |q(theta)| > eo, theta the angle of its point
  // (w = eps cot theta). Between samples whose bound stays below eo there is no crossing, so
  // the roots lie within the angles from the first to the last interval that may reach eo:
  // narrow [lo, hi] to those (widened by many root tolerances against rounding). Nothing is
  // narrowed when the interval across theta = 0 / pi (the ray's far ends) may reach eo.
  // [theta_j, theta_(j+1)]: the intervals where the ray may first and last reach eo
  int entryInterval = -1, exitInterval = -1;
  if (eo > T(0))
  {
    const T margin = tab.heightCurvature * heightBound + heightRounding;
    auto mayReach = [&](int j0, int j1) { return std::max(std::abs(q[j0]), std::abs(q[j1])) + margin >= eo; };
    if (!mayReach(M - 1, 0))
    {
      int first = -1, last = -1;
      for (int j = 0; j + 1 < M; ++j)
        if (mayReach(j, j + 1))
        {
          if (first < 0)
            first = j;
          last = j;
        }
      if (first < 0)
        return 0;
      // theta_first <= theta <= theta_(last+1): w from eps cot theta_(last+1) to eps cot theta_first.
      const T widen = T(16) * tolerance * std::max(wmax, eps);
      lo = std::max(lo, eps * tab.heightCotangent[last + 1] - widen);
      hi = std::min(hi, eps * tab.heightCotangent[first] + widen);
      entryInterval = last;
      exitInterval = first;
    }
  }
  if (!(lo <= hi))
    return 0;
  // The entry certificate. Along the ray theta decreases, and the ray is certainly outside at
  // theta_(j+1), j = entryInterval (the intervals before it cannot reach eo). Walk on through
  // the intervals cut in kEntryCuts pieces: a piece that cannot reach eo (the curvature bound
  // above, on the shorter piece) is passed; the first that may must end certainly inside,
  // with q monotonic on it (its change exceeds what q'' allows for a turn). Then |q| = eo
  // exactly once in that piece, so the nearest root is the only root of P in its w-interval
  // and needs no root isolation (nor P: it is refined on E, entryFunction). Otherwise (grazing rays, thin lobes, a ray starting inside)
  // the isolation below finds it. If every piece is passed, the ray misses.
  bool entryFound = false;
  T entryRoot = T(0), entryEnd = T(0);
  if (entryInterval >= 0)
  {
    constexpr int cuts = RayTables<T>::kEntryCuts;
    const T fineMargin = tab.heightCurvature / T(cuts * cuts) * heightBound + heightRounding;
    const T quarterMargin = tab.heightCurvature / T(16 * cuts * cuts) * heightBound + heightRounding;
    bool decided = false;
    for (int j = entryInterval; j >= exitInterval && !decided; --j)
    {
      // q and w at the cut points of [theta_j, theta_(j+1)], from theta_(j+1) (cut = cuts) down.
      T value[cuts + 1], w[cuts + 1];
      value[cuts] = q[j + 1];
      w[cuts] = eps * tab.heightCotangent[j + 1];
      value[0] = q[j];
      w[0] = eps * tab.heightCotangent[j];
      for (int cut = 1; cut < cuts; ++cut)
      {
        const int slot = (cuts - 1) * j + cut - 1;
        T sum = T(0);
        for (int i = 0; i <= K; ++i) // q = sum_i g_i cos^i sin^(k+1-i)
          sum += g[i] * tab.fineBasis[i][slot];
        value[cut] = sum;
        w[cut] = eps * tab.fineCotangent[slot];
      }
      for (int cut = cuts; cut > 0 && !decided; --cut)
      {
        const T a = value[cut], b = value[cut - 1];
        if (std::max(std::abs(a), std::abs(b)) + fineMargin < eo)
          continue; // this piece cannot reach eo
        // A piece that may reach eo but ends certainly outside (its curvature margin is
        // wide): passed when its quarters show that it cannot reach eo after all.
        if (std::abs(a) + heightRounding < eo && std::abs(b) + heightRounding < eo)
        {
          const std::size_t slot = std::size_t(cuts * j + cut - 1);
          T quarters[3] = { T(0), T(0), T(0) };
          for (int i = 0; i <= K; ++i)
            for (int quarter = 0; quarter < 3; ++quarter)
              quarters[quarter] += g[i] * tab.pieceQuarters[(std::size_t(i) * tab.pieceStride + slot) * 3 + quarter];
          const T along[5] = { b, quarters[0], quarters[1], quarters[2], a };
          bool passed = true;
          for (int quarter = 0; quarter < 4; ++quarter)
            passed = passed && std::max(std::abs(along[quarter]), std::abs(along[quarter + 1])) + quarterMargin < eo;
          if (passed)
            continue;
        }
        decided = true;
        if (!(std::abs(a) + heightRounding < eo && std::abs(b) - heightRounding > eo &&
              w[cut] >= lo && w[cut - 1] <= hi))
          break;
        // q' cannot vanish on the piece: q' and q'' at its middle (their rounding: the basis
        // derivatives are at most m and m^2 in size), then Taylor with the bound on q'''.
        const std::size_t slot = std::size_t(cuts * j + cut - 1);
        T first = T(0), second = T(0);
        for (int i = 0; i <= K; ++i)
        {
          first += g[i] * tab.pieceFirst[std::size_t(i) * tab.pieceStride + slot];
          second += g[i] * tab.pieceSecond[std::size_t(i) * tab.pieceStride + slot];
        }
        constexpr T m = T(K + 1);
        const T slope = std::abs(first) - m * heightRounding -
          tab.pieceHalfWidth * (std::abs(second) + m * m * heightRounding) - tab.pieceCubic * heightBound;
        if (slope > T(0))
        {
          // The one root of P in the piece is the one sign change of E (same sign as P), whose
          // ends must agree with the certificate in E's own rounding too.
          T unused;
          const T fa = entryFunction<K>(h, eps2, w[cut], unused);
          const T fb = entryFunction<K>(h, eps2, w[cut - 1], unused);
          if (fa < T(0) && fb > T(0))
          {
            // q is monotonic on the piece and much closer to linear than P: start where
            // the line through its ends meets eo.
            const T start = w[cut] + (eo - std::abs(a)) / (std::abs(b) - std::abs(a)) * (w[cut - 1] - w[cut]);
            entryRoot = entryRootOnPiece<K>(h, eps2, w[cut], w[cut - 1], start,
              tolerance * std::max(wmax, eps), kRootIterationLimit);
            entryEnd = w[cut - 1];
            entryFound = true;
          }
        }
      }
    }
    // No piece from the entry to the exit interval can reach eo: the ray misses the glyph.
    if (!decided)
      return 0;
  }
  // A sample where the ray is certainly inside the glyph (|q| beyond eo by more than its
  // rounding) lies past the entry, so roots are searched for up to there first and then in the
  // rest: the first interval usually holds the entry alone and needs no subdivision, and a
  // nearest-hit query stops there. Both queries split at the same point, so the nearest root
  // is the same bits whether or not the others are asked for.
  T split = hi;
  if (eo > T(0) && !entryFound) // the certificate's piece end takes its place
  {
    const T widen = T(16) * tolerance * std::max(wmax, eps);
    for (int j = M - 1; j >= 0; --j) // along the ray: theta from pi down to 0
      if (std::abs(q[j]) - heightRounding > eo)
      {
        const T inside = eps * tab.heightCotangent[j] + widen;
        if (inside >= lo)
          split = std::min(hi, inside);
        break;
      }
  }
  // Root isolation by Bernstein subdivision in double; float keeps the derivative cascade (its
  // rounding level leaves too many Bernstein signs uncertain for subdivision to pay off).
  const T rootTolerance = tolerance * std::max(wmax, eps);
  const auto rootsIn = [&](T from, T to, T* found, bool first)
  {
    buildPolynomial();
    if constexpr (sizeof(T) >= sizeof(double))
      return polynomialRootsSubdivision<N, T>(P, from, to, rootTolerance, found, first);
    else
      return polynomialRoots<N, T>(P, from, to, rootTolerance, found, first);
  };
  const auto findRoots = [&](T* found, bool first)
  {
    int n = 0;
    T restFrom = split;
    if (entryFound)
    {
      found[n++] = entryRoot;
      restFrom = entryEnd;
    }
    else
      n = rootsIn(lo, split, found, first);
    if (restFrom >= hi || (first && n > 0))
      return n;
    T rest[N];
    const int more = rootsIn(restFrom, hi, rest, first);
    for (int i = 0; i < more && !(first && n > 0); ++i)
      if (n == 0 || rest[i] > found[n - 1])
        found[n++] = rest[i];
    return n;
  };
  T roots[2 * N];
  int count = findRoots(roots, firstOnly);
  // The centre itself solves P = 0 when the ray passes through it (P = w^2k (g_k^2 - w^2) at
  // eps = 0), and in float also when eps^k underflows. It is a surface point only where F
  // vanishes, so a root within a few tolerances of the centre is kept only if F is that small
  // there too. (Genuine roots near, but not at, the centre pass: we measured no misses.)
  const T centreRadius = T(64) * tolerance * std::max(wmax, eps);
  auto genuine = [&](T w)
  {
    const T r = std::sqrt(w * w + eps2);
    if (r >= centreRadius)
      return true;
    const T x = r > T(0) ? (w * d[0] + eps * e[0]) / r : d[0];
    const T y = r > T(0) ? (w * d[1] + eps * e[1]) / r : d[1];
    const T z = r > T(0) ? (w * d[2] + eps * e[2]) / r : d[2];
    return std::abs(evaluate(b, x, y, z)) * scale <= T(4) * centreRadius;
  };
  int kept = 0;
  for (int i = 0; i < count && kept < N; ++i) // at most N: the two pieces' roots are distinct
  {
    const T ti = roots[i] * gmax - dO;
    if (ti < tmin || ti > tmax || !genuine(roots[i]))
      continue;
    t[kept++] = ti;
  }
  if (firstOnly && kept == 0 && count > 0)
  {
    // The nearest root was the centre (or rounded out of range): look at all of them.
    count = findRoots(roots, false);
    for (int i = 0; i < count && kept == 0; ++i)
    {
      const T ti = roots[i] * gmax - dO;
      if (ti >= tmin && ti <= tmax && genuine(roots[i]))
        t[kept++] = ti;
    }
  }
  return kept;
}


using Lanes4 = double __attribute__((vector_size(32))); // two SSE2 registers, one AVX2 one

/// Glyphs whose box or largest radius one pass over a direction table serves: the table is
/// read from memory once for all of them (alone, one glyph's sums waited on the table's loads).
constexpr int kGlyphBatch = 4;

/// out[g][lane] = sum over j of b[g][j] * block[j * 8 + lane] for G glyphs, each summed in order
/// of j (the same bits as one glyph alone).
template <int G>
SIGHTLINE_INLINE_INTO_CLONES void seriesValuesOfBlockFor(
  const double* const* b, const double* block, int stride, double (*out)[8])
{
  Lanes4 low[G] = {}, high[G] = {};
  for (int j = 0; j < stride; ++j, block += 8)
  {
    Lanes4 basisLow, basisHigh;
    std::memcpy(&basisLow, block, sizeof(Lanes4));
    std::memcpy(&basisHigh, block + 4, sizeof(Lanes4));
#pragma GCC unroll 4
    for (int g = 0; g < G; ++g)
    {
      low[g] += b[g][j] * basisLow;
      high[g] += b[g][j] * basisHigh;
    }
  }
  for (int g = 0; g < G; ++g)
  {
    std::memcpy(out[g], &low[g], sizeof(Lanes4));
    std::memcpy(out[g] + 4, &high[g], sizeof(Lanes4));
  }
}

/// Cloned for AVX2 (chosen at load time, so the default build stays portable): four lanes per
/// instruction, and without FMA contraction the same bits as the SSE2 version.
SIGHTLINE_AVX2_CLONES void seriesValuesOfBlock(
  const double* b, const double* block, int stride, double* out)
{
  seriesValuesOfBlockFor<1>(&b, block, stride, reinterpret_cast<double(*)[8]>(out));
}

SIGHTLINE_AVX2_CLONES void seriesValuesOfBlockBatch(
  const double* const* b, const double* block, int stride, double (*out)[8])
{
  seriesValuesOfBlockFor<kGlyphBatch>(b, block, stride, out);
}

using Bits4 = long long __attribute__((vector_size(32)));

/// Per lane, the largest |F(w)| |w[axis]| over blocks of 8 directions and the first direction
/// reaching it (4 + 4 lanes; the box search's inner loop without a call per direction).
struct AxisMaxima
{
  Lanes4 value[3][2] = {};
  Bits4 index[3][2] = {};
};

/// The same sums as seriesValuesOfBlockFor for `blocks` blocks and G glyphs, then |F| |w[axis]|
/// against each glyph's running maxima (strictly greater replaces, so each lane keeps its first
/// direction). |F w[axis]| = |F| |w[axis]| exactly, so the maxima are those of the serial search.
template <int G>
SIGHTLINE_INLINE_INTO_CLONES void seriesAxisMaximaFor(const double* const* b,
  const double* basis, const double* absDirections, int stride, int blocks, AxisMaxima* maxima)
{
  // Plain statements only (no helper returning a vector: that would change the default
  // clone's calling convention).
  const Bits4 magnitude = Bits4{} + 0x7fffffffffffffffLL;
  const Bits4 laneOffsets[2] = { { 0, 1, 2, 3 }, { 4, 5, 6, 7 } };
  for (int block = 0; block < blocks; ++block, basis += std::size_t(stride) * 8, absDirections += 24)
  {
    Lanes4 sums[G][2] = {};
    for (int j = 0; j < stride; ++j)
    {
      Lanes4 basisValues[2];
      std::memcpy(&basisValues[0], basis + j * 8, sizeof(Lanes4));
      std::memcpy(&basisValues[1], basis + j * 8 + 4, sizeof(Lanes4));
#pragma GCC unroll 4
      for (int g = 0; g < G; ++g)
      {
        sums[g][0] += b[g][j] * basisValues[0];
        sums[g][1] += b[g][j] * basisValues[1];
      }
    }
    for (int g = 0; g < G; ++g)
      for (int half = 0; half < 2; ++half)
      {
        const Lanes4 absolute = Lanes4(Bits4(sums[g][half]) & magnitude);
        const Bits4 ids = laneOffsets[half] + 8LL * block;
        for (int axis = 0; axis < 3; ++axis)
        {
          Lanes4 component;
          std::memcpy(&component, absDirections + axis * 8 + half * 4, sizeof(Lanes4));
          const Lanes4 candidate = absolute * component;
          Lanes4& value = maxima[g].value[axis][half];
          Bits4& index = maxima[g].index[axis][half];
          const Bits4 larger = candidate > value;
          value = Lanes4((larger & Bits4(candidate)) | (~larger & Bits4(value)));
          index = (larger & ids) | (~larger & index);
        }
      }
  }
}

SIGHTLINE_AVX2_CLONES void seriesAxisMaxima(const double* b,
  const double* basis, const double* absDirections, int stride, int blocks, AxisMaxima& maxima)
{
  seriesAxisMaximaFor<1>(&b, basis, absDirections, stride, blocks, &maxima);
}

SIGHTLINE_AVX2_CLONES void seriesAxisMaximaBatch(const double* const* b,
  const double* basis, const double* absDirections, int stride, int blocks, AxisMaxima* maxima)
{
  seriesAxisMaximaFor<kGlyphBatch>(b, basis, absDirections, stride, blocks, maxima);
}

/// Spherical Fibonacci directions in the upper hemisphere with the basis evaluated at each.
struct FibonacciTable
{
  static constexpr int kLanes = 8; ///< directions summed side by side (seriesValuesOfBlock)
  int order = 0;
  int count = 0;
  int stride = 0; ///< shCoefficientCount(order)
  std::vector<dvec3> directions;
  /// Basis values in blocks of kLanes directions, coefficient-major inside a block:
  /// [block][coefficient][lane], zero past `count`.
  std::vector<double> blockedBasis;
  /// |direction components| in the same blocks: [block][axis][lane].
  std::vector<double> blockedAbsDirections;

  FibonacciTable(int k, int samples) : order(k), count(samples), stride(shCoefficientCount(k))
  {
    directions.resize(count);
    const int blocks = (count + kLanes - 1) / kLanes;
    blockedBasis.assign(std::size_t(blocks) * stride * kLanes, 0.0);
    blockedAbsDirections.assign(std::size_t(blocks) * 3 * kLanes, 0.0);
    std::vector<double> row(static_cast<std::size_t>(stride));
    for (int l = 0; l < count; ++l)
    {
      // Glyphs are point symmetric: the upper hemisphere sees every extent.
      directions[l] = detail::fibonacciDirection(l, count, true);
      evaluateSH<double>(k, directions[l].x, directions[l].y, directions[l].z, row.data());
      for (int j = 0; j < stride; ++j)
        blockedBasis[(std::size_t(l / kLanes) * stride + j) * kLanes + l % kLanes] = row[std::size_t(j)];
      for (int axis = 0; axis < 3; ++axis)
        blockedAbsDirections[(std::size_t(l / kLanes) * 3 + axis) * kLanes + l % kLanes] = std::abs(directions[l][axis]);
    }
  }

  /// visit(l, F(directions[l])) for every direction in order. Each value is summed over the
  /// coefficients in order, as one dot product alone would be (the same bits); kLanes of them
  /// run side by side, so the additions no longer wait on one another and vectorise.
  template <class Visit>
  void forEachValue(const double* b, Visit&& visit) const
  {
    const double* block = blockedBasis.data();
    for (int first = 0; first < count; first += kLanes, block += std::size_t(stride) * kLanes)
    {
      double value[kLanes];
      seriesValuesOfBlock(b, block, stride, value);
      for (int lane = 0; lane < kLanes && first + lane < count; ++lane)
        visit(first + lane, value[lane]);
    }
  }

  /// The same for kGlyphBatch glyphs in one pass over the table: visit(g, l, F_g(directions[l])),
  /// each glyph's values in the same order and with the same bits as forEachValue.
  template <class Visit>
  void forEachValueOfBatch(const double* const* b, Visit&& visit) const
  {
    const double* block = blockedBasis.data();
    for (int first = 0; first < count; first += kLanes, block += std::size_t(stride) * kLanes)
    {
      double value[kGlyphBatch][kLanes];
      seriesValuesOfBlockBatch(b, block, stride, value);
      for (int g = 0; g < kGlyphBatch; ++g)
        for (int lane = 0; lane < kLanes && first + lane < count; ++lane)
          visit(g, first + lane, value[g][lane]);
    }
  }
};

/// The box search's directions: k * 256, as the paper validated.
const FibonacciTable& fibonacciTable(int order)
{
  static std::unique_ptr<FibonacciTable> tables[kOrderSlots];
  static std::once_flag flags[kOrderSlots];
  std::call_once(flags[order / 2],
    [order] { tables[order / 2] = std::make_unique<FibonacciTable>(order, 256 * std::max(order, 1)); });
  return *tables[order / 2];
}

/// Coarser directions for the largest amplitude, which Newton's method then refines: about
/// four samples across the narrowest lobe (angular width ~ pi / k) suffice to land in its basin.
const FibonacciTable& peakSearchTable(int order)
{
  static std::unique_ptr<FibonacciTable> tables[kOrderSlots];
  static std::once_flag flags[kOrderSlots];
  std::call_once(flags[order / 2], [order]
    { tables[order / 2] = std::make_unique<FibonacciTable>(order, 64 + 6 * (order + 1) * (order + 1)); });
  return *tables[order / 2];
}

void checkGlyphOrder(int order)
{
  if (order < 0 || order > kMaxGlyphOrder || order % 2 != 0)
    throw std::invalid_argument("glyph order " + std::to_string(order) +
      " is not an even number in [0, " + std::to_string(kMaxGlyphOrder) + "]");
}

/// Largest |coordinate `axis`| of F(w) w near the direction w0, by Newton's method on the
/// tangency conditions with p[axis] held at 1 (the paper's formulation, Section 4.2):
///   n~(w) = F w - (I - w w^T) grad F = 0 in the two other components.
double refineExtent(int order, const double* b, dvec3 w0, int axis, double best)
{
  if (w0[axis] < 0.0)
    w0 = -w0;
  if (w0[axis] <= 1e-12)
    return best;
  dvec3 p = w0 / w0[axis];
  const int i0 = (axis + 1) % 3, i1 = (axis + 2) % 3;
  for (int iteration = 0; iteration < 5; ++iteration)
  {
    const double r = glm::length(p);
    const dvec3 w = p / r;
    const SHFunctionValue<double> f = evaluateSHFunction<double>(order, b, w.x, w.y, w.z, true);
    const dvec3 grad(f.gradient[0], f.gradient[1], f.gradient[2]);
    const auto& hs = f.hessian;
    const glm::dmat3 H(hs[0], hs[1], hs[2], hs[1], hs[3], hs[4], hs[2], hs[4], hs[5]);
    const double wg = glm::dot(w, grad);
    const dvec3 n = f.value * w - grad + w * wg;
    // dn/dw = (F + w.g) I - H + w (2 g + H w)^T ; dw/dp = (I - w w^T) / r.
    const glm::dmat3 dndw = (f.value + wg) * glm::dmat3(1.0) - H + glm::outerProduct(w, 2.0 * grad + H * w);
    const glm::dmat3 dwdp = (glm::dmat3(1.0) - glm::outerProduct(w, w)) / r;
    const glm::dmat3 J = dndw * dwdp; // J[column][row]
    const double a = J[i0][i0], bq = J[i1][i0], c = J[i0][i1], d = J[i1][i1];
    const double det = a * d - bq * c;
    if (!(std::abs(det) > 0.0) || !std::isfinite(det))
      break;
    const double r0 = -n[i0], r1 = -n[i1];
    const double step0 = (d * r0 - bq * r1) / det, step1 = (a * r1 - c * r0) / det;
    p[i0] += step0;
    p[i1] += step1;
    if (!isFinite(vec3(p)))
      break;
    const dvec3 wn = glm::normalize(p);
    const double extent = std::abs(evaluateSHSum<double>(order, b, wn.x, wn.y, wn.z) * wn[axis]);
    if (extent > best)
      best = extent;
    // Converging quadratically, a step this small leaves the tangent point within ~1e-10 and
    // the extent, stationary there, within ~1e-20 of its own size: no step would change it.
    if (step0 * step0 + step1 * step1 < 1e-10 * glm::dot(p, p))
      break;
  }
  return best;
}
} // namespace

namespace
{
/// Every order's intersection in one function, cloned for AVX2 (chosen when the library loads;
/// intersectOrder is inlined into each clone, so the SH sums, the height test and the
/// polynomial use the wider registers; without FMA contraction the same bits).
template <class T>
SIGHTLINE_INLINE_INTO_CLONES int intersectAnyOrder(int order, const T* coefficients,
  const T origin[3], const T direction[3], T tmin, T tmax, T tolerance, T* t, bool firstOnly)
{
  switch (order)
  {
#define SIGHTLINE_GLYPH_ORDER(K)                                                                     \
  case K:                                                                                          \
    return intersectOrder<K, T>(coefficients, origin, direction, tmin, tmax, tolerance, t, firstOnly);
    SIGHTLINE_GLYPH_ORDER(0)
    SIGHTLINE_GLYPH_ORDER(2)
    SIGHTLINE_GLYPH_ORDER(4)
    SIGHTLINE_GLYPH_ORDER(6)
    SIGHTLINE_GLYPH_ORDER(8)
    SIGHTLINE_GLYPH_ORDER(10)
    SIGHTLINE_GLYPH_ORDER(12)
    SIGHTLINE_GLYPH_ORDER(14)
    SIGHTLINE_GLYPH_ORDER(16)
#undef SIGHTLINE_GLYPH_ORDER
    default:
      checkGlyphOrder(order);
      return 0;
  }
}

SIGHTLINE_AVX2_CLONES int intersectAnyOrderDouble(int order, const double* coefficients,
  const double* origin, const double* direction, double tmin, double tmax, double tolerance,
  double* t, bool firstOnly)
{
  return intersectAnyOrder<double>(order, coefficients, origin, direction, tmin, tmax, tolerance, t, firstOnly);
}

SIGHTLINE_AVX2_CLONES int intersectAnyOrderFloat(int order, const float* coefficients,
  const float* origin, const float* direction, float tmin, float tmax, float tolerance, float* t,
  bool firstOnly)
{
  return intersectAnyOrder<float>(order, coefficients, origin, direction, tmin, tmax, tolerance, t, firstOnly);
}
} // namespace

template <class T>
int intersectSHGlyph(int order, const T* coefficients, const T origin[3], const T direction[3],
  T tmin, T tmax, T tolerance, T* t, bool firstOnly)
{
  if constexpr (sizeof(T) == sizeof(double))
    return intersectAnyOrderDouble(order, coefficients, origin, direction, tmin, tmax, tolerance, t, firstOnly);
  else
    return intersectAnyOrderFloat(order, coefficients, origin, direction, tmin, tmax, tolerance, t, firstOnly);
}

template int intersectSHGlyph<float>(
  int, const float*, const float[3], const float[3], float, float, float, float*, bool);
template int intersectSHGlyph<double>(
  int, const double*, const double[3], const double[3], double, double, double, double*, bool);

dvec3 shGlyphNormal(int order, const double* b, const dvec3& p, double* value)
{
  const double r = glm::length(p);
  if (!(r > 0.0))
    return dvec3(0.0);
  const dvec3 w = p / r;
  const SHFunctionValue<double> f = evaluateSHFunction<double>(order, b, w.x, w.y, w.z, false);
  const dvec3 grad(f.gradient[0], f.gradient[1], f.gradient[2]);
  if (value)
    *value = f.value;
  return p - f.value * (grad - w * glm::dot(w, grad)) / r;
}

bool insideSHGlyph(int order, const double* b, const dvec3& p)
{
  const double r = glm::length(p);
  if (!(r > 0.0))
    return true;
  const dvec3 w = p / r;
  return r < std::abs(evaluateSHSum<double>(order, b, w.x, w.y, w.z));
}

namespace
{
/// The lanes' maxima reduced as the serial search would (the largest, the first on a tie), then
/// each axis refined by Newton's method from its best direction.
dvec3 halfExtentsFromMaxima(int order, const double* b, const FibonacciTable& table, const AxisMaxima& maxima)
{
  dvec3 best(0.0);
  int bestIndex[3] = { 0, 0, 0 };
  for (int axis = 0; axis < 3; ++axis)
    for (int half = 0; half < 2; ++half)
      for (int lane = 0; lane < 4; ++lane)
      {
        const double value = maxima.value[axis][half][lane];
        const int index = int(maxima.index[axis][half][lane]);
        if (value > best[axis] || (value == best[axis] && value > 0.0 && index < bestIndex[axis]))
        {
          best[axis] = value;
          bestIndex[axis] = index;
        }
      }
  if (order == 0) // a sphere: its extent is known exactly
    return dvec3(std::abs(b[0]) * 0.5 / std::sqrt(kPi));
  for (int axis = 0; axis < 3; ++axis)
    best[axis] = refineExtent(order, b, table.directions[bestIndex[axis]], axis, best[axis]);
  return best;
}

int tableBlocks(const FibonacciTable& table)
{
  return (table.count + FibonacciTable::kLanes - 1) / FibonacciTable::kLanes;
}

double halfExtentMargin(int order)
{
  return order <= 8 ? 1.025 : 1.035;
}
} // namespace

dvec3 shGlyphHalfExtentsUnpadded(int order, const double* b)
{
  checkGlyphOrder(order);
  const FibonacciTable& table = fibonacciTable(order);
  AxisMaxima maxima;
  seriesAxisMaxima(b, table.blockedBasis.data(), table.blockedAbsDirections.data(), table.stride,
    tableBlocks(table), maxima);
  return halfExtentsFromMaxima(order, b, table, maxima);
}

void shGlyphHalfExtents(int order, std::size_t count, const double* const* coefficients, dvec3* halfExtents)
{
  checkGlyphOrder(order);
  const FibonacciTable& table = fibonacciTable(order);
  const double margin = halfExtentMargin(order);
  std::size_t g = 0;
  for (; g + kGlyphBatch <= count; g += kGlyphBatch)
  {
    AxisMaxima maxima[kGlyphBatch];
    seriesAxisMaximaBatch(coefficients + g, table.blockedBasis.data(),
      table.blockedAbsDirections.data(), table.stride, tableBlocks(table), maxima);
    for (int i = 0; i < kGlyphBatch; ++i)
      halfExtents[g + i] = margin * halfExtentsFromMaxima(order, coefficients[g + i], table, maxima[i]);
  }
  for (; g < count; ++g)
    halfExtents[g] = shGlyphHalfExtents(order, coefficients[g]);
}

dvec3 shGlyphHalfExtents(int order, const double* b)
{
  return halfExtentMargin(order) * shGlyphHalfExtentsUnpadded(order, b);
}

namespace
{
/// Climbs from the direction w (where |F| = best) to the top of its peak and returns |F| there.
double refinePeak(int order, const double* b, dvec3 w, double best, double sampleSpacing)
{
  // Newton's method on the sphere for the extremum of s F (s the sign of F at the sample):
  // Riemannian gradient P g and Hessian P H P - (w.g) P with P = I - w w^T, in a tangent basis.
  // A step is kept only when |F| grows, so the result is never worse than the sample.
  bool converged = false;
  for (int iteration = 0; iteration < 8 && !converged; ++iteration)
  {
    const SHFunctionValue<double> f = evaluateSHFunction<double>(order, b, w.x, w.y, w.z, true);
    const double sign = f.value < 0.0 ? -1.0 : 1.0;
    const dvec3 g = sign * dvec3(f.gradient[0], f.gradient[1], f.gradient[2]);
    const auto& h = f.hessian;
    const glm::dmat3 H = sign * glm::dmat3(h[0], h[1], h[2], h[1], h[3], h[4], h[2], h[4], h[5]);
    const dvec3 u = glm::normalize(glm::cross(w, std::abs(w.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
    const dvec3 v = glm::cross(w, u);
    const double wg = glm::dot(w, g);
    const double huu = glm::dot(u, H * u) - wg, huv = glm::dot(u, H * v), hvv = glm::dot(v, H * v) - wg;
    const double gu = glm::dot(u, g), gv = glm::dot(v, g);
    const double det = huu * hvv - huv * huv;
    if (!(huu < 0.0 && det > 0.0)) // outside the peak's concave basin: compass search below
      break;
    const double su = -(hvv * gu - huv * gv) / det, sv = -(huu * gv - huv * gu) / det;
    // Quadratic convergence: after a step under 1e-5 the peak is within ~1e-10, its height (a
    // stationary value) within ~1e-20 of itself.
    converged = su * su + sv * sv < 1e-10;
    const dvec3 candidate = glm::normalize(w + su * u + sv * v);
    const double value = std::abs(evaluateSHSum<double>(order, b, candidate.x, candidate.y, candidate.z));
    if (!(value > best))
      break;
    best = value;
    w = candidate;
  }
  if (converged)
    return best;
  // A sharp lobe between samples: a compass search (four tangent steps, halved when none
  // improves) climbs to it where Newton's quadratic model does not hold.
  const auto amplitude = [&](const dvec3& x) { return std::abs(evaluateSHSum<double>(order, b, x.x, x.y, x.z)); };
  dvec3 u = glm::normalize(glm::cross(w, std::abs(w.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
  for (double step = 2.0 * sampleSpacing; step > 1e-5;)
  {
    const dvec3 v = glm::cross(w, u);
    bool moved = false;
    for (const dvec3& t : { u, -u, v, -v })
    {
      const dvec3 candidate = glm::normalize(w + step * t);
      const double value = amplitude(candidate);
      if (value > best)
      {
        best = value;
        w = candidate;
        moved = true;
        break;
      }
    }
    if (!moved)
      step *= 0.5;
    u = glm::normalize(u - glm::dot(u, w) * w);
  }
  return best;
}
} // namespace

namespace
{
/// The few best samples of |F| that lie on different peaks (not within ~17 degrees of each other
/// or of the antipode), best first: two lobes of nearly equal height must both be climbed.
struct PeakCandidates
{
  static constexpr int kCandidates = 4;
  static constexpr double kSameLobe = 0.955;
  int candidate[kCandidates];
  double height[kCandidates];
  int found = 0;

  /// Offers direction l with value F; directions are offered in order of l.
  void offer(const FibonacciTable& table, int l, double value)
  {
    value = std::abs(value);
    if (found == kCandidates && value <= height[kCandidates - 1])
      return;
    int near = -1;
    for (int c = 0; c < found && near < 0; ++c)
      if (std::abs(glm::dot(table.directions[l], table.directions[candidate[c]])) > kSameLobe)
        near = c;
    if (near >= 0 && value <= height[near])
      return;
    int slot = near >= 0 ? near : (found < kCandidates ? found++ : kCandidates - 1);
    for (; slot > 0 && height[slot - 1] < value; --slot) // keep the list sorted, best first
    {
      height[slot] = height[slot - 1];
      candidate[slot] = candidate[slot - 1];
    }
    height[slot] = value;
    candidate[slot] = l;
  }

  /// The largest |F|: every candidate within 80 % of the best, climbed to its peak.
  double climb(int order, const double* b, const FibonacciTable& table) const
  {
    if (found == 0 || order == 0 || !(height[0] > 0.0))
      return found ? std::max(height[0], 0.0) : 0.0;
    const double spacing = std::sqrt(4.0 * kPi / table.count);
    double best = 0.0;
    for (int c = 0; c < found; ++c)
      if (height[c] > 0.8 * height[0])
        best = std::max(best, refinePeak(order, b, table.directions[candidate[c]], height[c], spacing));
    return best;
  }
};
} // namespace

double shGlyphMaxRadius(int order, const double* b)
{
  checkGlyphOrder(order);
  const FibonacciTable& table = peakSearchTable(order);
  PeakCandidates peaks;
  table.forEachValue(b, [&](int l, double value) { peaks.offer(table, l, value); });
  return peaks.climb(order, b, table);
}

void shGlyphMaxRadius(int order, std::size_t count, const double* const* coefficients, double* radii)
{
  checkGlyphOrder(order);
  const FibonacciTable& table = peakSearchTable(order);
  std::size_t g = 0;
  for (; g + kGlyphBatch <= count; g += kGlyphBatch)
  {
    PeakCandidates peaks[kGlyphBatch];
    table.forEachValueOfBatch(coefficients + g,
      [&](int i, int l, double value) { peaks[i].offer(table, l, value); });
    for (int i = 0; i < kGlyphBatch; ++i)
      radii[g + i] = peaks[i].climb(order, coefficients[g + i], table);
  }
  for (; g < count; ++g)
    radii[g] = shGlyphMaxRadius(order, coefficients[g]);
}

double shGlyphBoundingRadius(int order, const double* b)
{
  // |sum_m b_lm Y_lm| <= |b_l| sqrt(sum_m Y_lm^2) = |b_l| sqrt((2l + 1) / 4 pi) by the
  // addition theorem.
  double radius = 0.0;
  for (int l = 0; l <= order; l += 2)
  {
    double norm2 = 0.0;
    for (int m = -l; m <= l; ++m)
      norm2 += b[shIndex(l, m)] * b[shIndex(l, m)];
    radius += std::sqrt(norm2 * (2 * l + 1) / (4.0 * kPi));
  }
  return radius;
}

int shEffectiveOrder(int order, const double* b)
{
  for (int l = order; l > 0; l -= 2)
    for (int m = -l; m <= l; ++m)
      if (b[shIndex(l, m)] != 0.0)
        return l;
  return 0;
}
} // namespace sightline
