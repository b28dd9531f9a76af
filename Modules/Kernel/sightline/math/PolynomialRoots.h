// SPDX-License-Identifier: BSD-3-Clause
// Real roots of a polynomial in an interval by bracketed iteration on monotonic pieces
// (after C. Yuksel, "High-performance polynomial root finding for graphics", HPG 2022):
// the roots of the derivative split [xmin, xmax] into intervals where the polynomial is
// monotonic, so each interval holds at most one root and a sign change brackets it. The
// derivative's roots come from the same procedure one degree lower, down to the quadratic
// formula. The degree is a template parameter: coefficient arrays live on the stack, the
// recursion unrolls at compile time and the hot path never allocates.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace sightline
{
/// Evaluates c[0] + c[1] x + ... + c[N] x^N by Horner's rule.
template <int N, class T>
inline T evaluatePolynomial(const T* c, T x)
{
  T value = c[N];
  for (int i = N - 1; i >= 0; --i)
    value = value * x + c[i];
  return value;
}

/// Value and first derivative together (one Horner pass).
template <int N, class T>
inline void evaluatePolynomialAndDerivative(const T* c, T x, T& value, T& derivative)
{
  value = c[N];
  derivative = T(0);
  for (int i = N - 1; i >= 0; --i)
  {
    derivative = derivative * x + value;
    value = value * x + c[i];
  }
}

/// Value, first and second derivative together.
template <int N, class T>
inline void evaluatePolynomialDerivatives2(const T* c, T x, T& value, T& first, T& second)
{
  value = c[N];
  first = T(0);
  second = T(0);
  for (int i = N - 1; i >= 0; --i)
  {
    second = second * x + first;
    first = first * x + value;
    value = value * x + c[i];
  }
  second *= T(2);
}

namespace detail
{

/// The root of a polynomial that is monotonic on [a, b] with f(a), f(b) of opposite signs
/// (neither zero; only f(a) is needed), from the first guess x (a guess outside (a, b) becomes the midpoint). Newton
/// steps that would leave the bracket become bisections, and the bracket shrinks with every
/// evaluation, so this terminates even where Newton alone cycles.
template <int N, class T>
T monotonicRootFrom(const T* c, T a, T b, T fa, T x, T tolerance, int maxIterations)
{
  // Yuksel's scheme takes Newton steps inside the bracket. Our polynomials are often flat over
  // most of an interval (a cluster of complex roots near the glyph centre makes the higher
  // derivatives behave like (x - r)^m), where Newton crawls with ratio (m - 1) / m: we measured
  // 13-16 steps per root at degree 18. Laguerre's step uses the degree and the second
  // derivative, is exact for such clusters and converges cubically at simple roots: 3-4
  // steps. A step that leaves the bracket becomes a bisection; only a Laguerre step that
  // moved less than the tolerance, or a bracket narrower than it, ends the iteration.
  if (!(x > a && x < b))
    x = T(0.5) * (a + b);
  for (int iteration = 0; iteration < maxIterations; ++iteration)
  {
    T fx, d1, d2;
    evaluatePolynomialDerivatives2<N>(c, x, fx, d1, d2);
    if (fx == T(0))
      return x;
    if ((fx < T(0)) == (fa < T(0)))
      a = x;
    else
      b = x;
    const T G = d1 / fx;
    const T H = G * G - d2 / fx;
    const T root = std::sqrt(std::max(T(0), T(N - 1) * (T(N) * H - G * G)));
    const T next = x - T(N) / (G >= T(0) ? G + root : G - root);
    if (next > a && next < b) // false for a zero denominator and NaN too
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

/// The same from the secant's guess.
template <int N, class T>
T monotonicRoot(const T* c, T a, T b, T fa, T fb, T tolerance, int maxIterations)
{
  return monotonicRootFrom<N>(c, a, b, fa, a - fa * (b - a) / (fb - fa), tolerance, maxIterations);
}

template <class T>
int quadraticRoots(const T* c, T xmin, T xmax, T* roots)
{
  const T a = c[2], b = c[1], k = c[0];
  T r0, r1;
  int count = 0;
  if (a == T(0))
  {
    if (b == T(0))
      return 0;
    r0 = -k / b;
    if (r0 >= xmin && r0 <= xmax)
      roots[count++] = r0;
    return count;
  }
  const T discriminant = b * b - T(4) * a * k;
  if (discriminant < T(0))
    return 0;
  // q avoids the cancellation of -b + sqrt(b^2 - 4ac) when b^2 >> |4ac|.
  const T q = T(-0.5) * (b + std::copysign(std::sqrt(discriminant), b));
  r0 = q / a;
  r1 = q != T(0) ? k / q : r0;
  if (r0 > r1)
    std::swap(r0, r1);
  if (r0 >= xmin && r0 <= xmax)
    roots[count++] = r0;
  if (r1 >= xmin && r1 <= xmax && (count == 0 || r1 != roots[0]))
    roots[count++] = r1;
  return count;
}
} // namespace detail

/// Default iteration cap for the Newton-bisection on one monotonic piece.
constexpr int kRootIterationLimit = 90;

/// Finds the real roots of the degree-N polynomial c in [xmin, xmax], sorted ascending,
/// writes them to `roots` (room for N) and returns their number. Roots are accurate to about
/// `tolerance`; a root of even multiplicity (a touching point) is reported only where the
/// polynomial reaches exactly zero. With `firstOnly`, stops after the smallest root.
template <int N, class T>
int polynomialRoots(const T* c, T xmin, T xmax, T tolerance, T* roots, bool firstOnly = false,
  int maxIterations = kRootIterationLimit)
{
  static_assert(N >= 1, "polynomialRoots needs degree >= 1");
  if (!(xmin <= xmax)) // empty interval (or NaN bounds)
    return 0;
  if constexpr (N <= 2)
  {
    T padded[3] = { c[0], c[1], N == 2 ? c[N] : T(0) };
    const int count = detail::quadraticRoots(padded, xmin, xmax, roots);
    return firstOnly ? std::min(count, 1) : count;
  }
  else
  {
    // Critical points: roots of the derivative (scaled by 1/N, which does not move them).
    T derivative[N];
    for (int i = 0; i < N; ++i)
      derivative[i] = c[i + 1] * (T(i + 1) / T(N));
    T critical[N];
    const int criticalCount =
      polynomialRoots<N - 1>(derivative, xmin, xmax, tolerance, critical, false, maxIterations);

    int count = 0;
    T a = xmin;
    T fa = evaluatePolynomial<N>(c, a);
    for (int i = 0; i <= criticalCount; ++i)
    {
      const T b = i < criticalCount ? critical[i] : xmax;
      const T fb = evaluatePolynomial<N>(c, b);
      if (fa == T(0))
      {
        if (count == 0 || roots[count - 1] != a)
          roots[count++] = a;
      }
      else if (fb != T(0) && ((fa < T(0)) != (fb < T(0))))
        roots[count++] = detail::monotonicRoot<N>(c, a, b, fa, fb, tolerance, maxIterations);
      if (firstOnly && count > 0)
        return 1;
      a = b;
      fa = fb;
    }
    if (fa == T(0) && (count == 0 || roots[count - 1] != a))
      roots[count++] = a;
    return firstOnly ? std::min(count, 1) : count;
  }
}

namespace detail
{
/// Bernstein coefficients on y in [-1, 1] (s = (y + 1) / 2 in [0, 1]) of the monomials y^i:
///   y^i = sum_j table[j][i] B_j^N(s),  table[j][i] = e_i(-1 x (N - j), +1 x j) / C(N, i),
/// the blossom of y^i; every entry lies in [-1, 1], so the conversion is well conditioned.
template <int N, class T>
struct BernsteinTable
{
  T m[N + 1][N + 1];
  BernsteinTable()
  {
    long double binomial[N + 1][N + 1] = {};
    for (int n = 0; n <= N; ++n)
    {
      binomial[n][0] = 1.0L;
      for (int r = 1; r <= n; ++r)
        binomial[n][r] = binomial[n - 1][r - 1] + (r <= n - 1 ? binomial[n - 1][r] : 0.0L);
    }
    for (int j = 0; j <= N; ++j)
      for (int i = 0; i <= N; ++i)
      {
        long double e = 0.0L;
        for (int a = 0; a <= std::min(i, j); ++a)
          if (i - a <= N - j)
            e += binomial[j][a] * binomial[N - j][i - a] * ((i - a) % 2 == 0 ? 1.0L : -1.0L);
        m[j][i] = T(e / binomial[N][i]);
      }
  }
};

template <int N, class T>
const BernsteinTable<N, T>& bernsteinTable()
{
  static const BernsteinTable<N, T> table;
  return table;
}

/// De Casteljau at the midpoint: `left` receives [0, 1/2], `b` becomes [1/2, 1].
template <int N, class T>
inline void splitBernsteinHalf(T* b, T* left)
{
  left[0] = b[0];
  for (int r = 1; r <= N; ++r)
  {
    for (int j = 0; j <= N - r; ++j)
      b[j] = T(0.5) * (b[j] + b[j + 1]);
    left[r] = b[0];
  }
}

/// De Casteljau at t: `b` becomes the piece [0, t] (the right piece is dropped).
template <int N, class T>
inline void keepBernsteinLeft(T* b, T t)
{
  T work[N + 1];
  for (int j = 0; j <= N; ++j)
    work[j] = b[j];
  b[0] = work[0];
  for (int r = 1; r <= N; ++r)
  {
    for (int j = 0; j <= N - r; ++j)
      work[j] = work[j] + t * (work[j + 1] - work[j]);
    b[r] = work[0];
  }
}

/// De Casteljau at t: `b` becomes the piece [t, 1].
template <int N, class T>
inline void keepBernsteinRight(T* b, T t)
{
  for (int r = 1; r <= N; ++r)
    for (int j = 0; j <= N - r; ++j)
      b[j] = b[j] + t * (b[j + 1] - b[j]);
}

/// Sign variations of the Bernstein coefficients (zeros skipped), capped at 2.
template <int N, class T>
inline int bernsteinVariations(const T* b)
{
  int variations = 0;
  int sign = 0;
  for (int j = 0; j <= N; ++j)
  {
    const int s = (b[j] > T(0)) - (b[j] < T(0));
    if (s != 0)
    {
      if (sign != 0 && s != sign)
        ++variations;
      sign = s;
    }
  }
  return variations;
}
} // namespace detail

/// The same roots as polynomialRoots, isolated by Bernstein subdivision and refined by the same
/// bracketed Laguerre iteration. On an interval whose Bernstein coefficients all exceed their
/// rounding-error bound in magnitude, Descartes' rule of signs is certain: no sign variation
/// means no root, one means exactly one (bracketed by the ends). Anything else is halved; an
/// interval still undecided after `maxDepth` halvings (multiple or tightly clustered roots,
/// values below the rounding level) goes to polynomialRoots, so touching points and clusters
/// behave exactly as there. Much cheaper than the derivative cascade when the interval holds
/// few real roots, and for intervals without roots.
///
/// Bernstein coefficients come from those of c(r y) on y in [-1, 1], r = max(|a|, |b|), which
/// are well conditioned (every entry of the conversion lies in [-1, 1]); their rounding errors
/// scale like sum |c_i| r^i, so an interval whose r is at most half the one converted last is
/// converted afresh: near zero the polynomial can be orders of magnitude smaller than its
/// coefficients (a ray passing close to a glyph's centre), which the coefficients of a wide
/// interval cannot resolve but Horner's rule there (the cascade's arithmetic) can.
template <int N, class T>
int polynomialRootsSubdivision(const T* c, T xmin, T xmax, T tolerance, T* roots,
  bool firstOnly = false, int maxIterations = kRootIterationLimit, int maxDepth = 24)
{
  if (!(xmin <= xmax))
    return 0;
  if constexpr (N <= 4)
    return polynomialRoots<N, T>(c, xmin, xmax, tolerance, roots, firstOnly, maxIterations);
  else
  {
    const T R = std::max(std::abs(xmin), std::abs(xmax));
    if (!(R > T(0)) || !(xmin < xmax) || !std::isfinite(R))
      return polynomialRoots<N, T>(c, xmin, xmax, tolerance, roots, firstOnly, maxIterations);
    constexpr T ulp = std::numeric_limits<T>::epsilon();
    const detail::BernsteinTable<N, T>& table = detail::bernsteinTable<N, T>();
    // Writes the Bernstein coefficients on [a, b] to `out`, returns r and their error bound.
    auto convert = [&](T a, T b, T* out, T& error)
    {
      const T r = std::max(std::abs(a), std::abs(b));
      T scaled[N + 1];
      T power = T(1);
      T magnitude = T(0);
      for (int i = 0; i <= N; ++i)
      {
        scaled[i] = c[i] * power;
        magnitude += std::abs(scaled[i]);
        power *= r;
      }
      for (int j = 0; j <= N; ++j)
      {
        T sum = T(0);
        for (int i = 0; i <= N; ++i)
          sum += table.m[j][i] * scaled[i];
        out[j] = sum;
      }
      // One of the two ends is at y = +-1 already.
      if (b < r)
        detail::keepBernsteinLeft<N>(out, T(0.5) * (b / r + T(1)));
      else if (a > -r)
        detail::keepBernsteinRight<N>(out, T(0.5) * (a / r + T(1)));
      // Conversion (N + 1 terms, powers of r) and the de Casteljau cut (convex combinations).
      error = T(8 * (N + 1)) * ulp * magnitude;
      return r;
    };
    constexpr int kMaxDepth = 40;
    maxDepth = std::min(maxDepth, kMaxDepth);
    T stack[kMaxDepth + 2][N + 1];
    T stackA[kMaxDepth + 2], stackB[kMaxDepth + 2], stackR[kMaxDepth + 2], stackError[kMaxDepth + 2];
    int stackDepth[kMaxDepth + 2];
    stackR[0] = convert(xmin, xmax, stack[0], stackError[0]);
    stackA[0] = xmin;
    stackB[0] = xmax;
    stackDepth[0] = 0;
    int top = 1;

    int count = 0;
    auto append = [&](const T* found, int n)
    {
      for (int i = 0; i < n; ++i)
        if (count == 0 || found[i] > roots[count - 1])
          roots[count++] = found[i];
    };
    // Intervals are taken left to right, so a budget of them bounds the work where the signs
    // stay uncertain everywhere (a polynomial at the rounding level): what is left,
    // [a, xmax], goes to polynomialRoots at once.
    int budget = 4 * maxDepth;
    while (top > 0)
    {
      --top;
      T* p = stack[top];
      const T a = stackA[top], b = stackB[top];
      if (--budget < 0)
      {
        T found[N];
        const int n = polynomialRoots<N, T>(c, a, xmax, tolerance, found, firstOnly, maxIterations);
        append(found, n);
        return firstOnly ? std::min(count, 1) : count;
      }
      const int depth = stackDepth[top];
      T convertedR = stackR[top];
      T error = stackError[top];
      if (std::max(std::abs(a), std::abs(b)) <= T(0.5) * convertedR)
        convertedR = convert(a, b, p, error);
      // Sign variations, and whether every coefficient's sign is certain.
      int variations = 0;
      bool certain = true;
      T largest = T(0);
      for (int j = 0; j <= N; ++j)
      {
        const T magnitude = std::abs(p[j]);
        certain = certain && magnitude > error;
        largest = std::max(largest, magnitude);
        variations += j > 0 && ((p[j] < T(0)) != (p[j - 1] < T(0)));
      }
      if (certain && variations == 0)
        continue;
      bool fallback = true;
      if (certain && variations == 1)
      {
        const T fa = evaluatePolynomial<N>(c, a);
        const T fb = evaluatePolynomial<N>(c, b);
        if (fa != T(0) && fb != T(0) && ((fa < T(0)) != (fb < T(0))))
        {
          const T root = detail::monotonicRoot<N>(c, a, b, fa, fb, tolerance, maxIterations);
          append(&root, 1);
          fallback = false;
        }
      }
      else if (depth < maxDepth)
      {
        const T mid = T(0.5) * (a + b);
        if (mid > a && mid < b)
        {
          // The right half stays in place (popped last), the left half goes on top.
          detail::splitBernsteinHalf<N>(p, stack[top + 1]);
          const T childError = error + T(2 * (N + 1)) * ulp * largest;
          stackA[top] = mid;
          stackB[top] = b;
          stackA[top + 1] = a;
          stackB[top + 1] = mid;
          stackDepth[top] = stackDepth[top + 1] = depth + 1;
          stackR[top] = stackR[top + 1] = convertedR;
          stackError[top] = stackError[top + 1] = childError;
          top += 2;
          continue;
        }
      }
      if (fallback)
      {
        T found[N];
        const int n = polynomialRoots<N, T>(c, a, b, tolerance, found, firstOnly, maxIterations);
        append(found, n);
      }
      if (firstOnly && count > 0)
        return 1;
    }
    return count;
  }
}
} // namespace sightline
