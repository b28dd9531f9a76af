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
/// (neither zero). Newton steps that would leave the bracket become bisections, and the
/// bracket shrinks with every evaluation, so this terminates even where Newton alone cycles.
template <int N, class T>
T monotonicRoot(const T* c, T a, T b, T fa, T fb, T tolerance, int maxIterations)
{
  // Yuksel's scheme takes Newton steps inside the bracket. Our polynomials are often flat over
  // most of an interval (a cluster of complex roots near the glyph centre makes the higher
  // derivatives behave like (x - r)^m), where Newton crawls with ratio (m - 1) / m: we measured
  // 13-16 steps per root at degree 18. Laguerre's step uses the degree and the second
  // derivative, is exact for such clusters and converges cubically at simple roots: 3-4
  // steps. A step that leaves the bracket becomes a bisection; only a Laguerre step that
  // moved less than the tolerance, or a bracket narrower than it, ends the iteration.
  T x = a - fa * (b - a) / (fb - fa);
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
} // namespace sightline
