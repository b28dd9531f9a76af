// SPDX-License-Identifier: BSD-3-Clause
// Independent references for the kernel tests: camera matrices written from the OpenGL formulas
// (gluLookAt, glFrustum, glOrtho) in plain arrays rather than GLM, a long double linear solver for
// unprojection, and a long double ray-sphere solution. Nothing here calls the kernel's maths.
#pragma once

#include "sightline/core/Camera.h"
#include "sightline/core/EmbreeScene.h"
#include "sightline/spheres/SphereSet.h"

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

namespace sightline_test
{
/// A value with 3 significant digits, for test output.
inline std::string number(long double x)
{
  std::ostringstream out;
  out.precision(3);
  out << double(x);
  return out.str();
}

using sightline::dvec3;

/// Row-major 4x4 matrix: m[row][column], acting on column vectors.
using Matrix4 = std::array<std::array<long double, 4>, 4>;

inline Matrix4 multiply(const Matrix4& a, const Matrix4& b)
{
  Matrix4 product{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k)
        product[i][j] += a[i][k] * b[k][j];
  return product;
}

inline std::array<long double, 3> normalized(std::array<long double, 3> v)
{
  const long double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return { v[0] / length, v[1] / length, v[2] / length };
}

inline std::array<long double, 3> cross(const std::array<long double, 3>& a,
                                        const std::array<long double, 3>& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

/// gluLookAt: rows are side, up and -forward, then the eye moved to the origin.
inline Matrix4 referenceLookAt(const dvec3& eye, const dvec3& target, const dvec3& up)
{
  const auto forward = normalized({ target.x - (long double)eye.x, target.y - (long double)eye.y,
                                    target.z - (long double)eye.z });
  const auto side = normalized(cross(forward, { up.x, up.y, up.z }));
  const auto trueUp = cross(side, forward);
  const std::array<long double, 3> e{ eye.x, eye.y, eye.z };
  auto dot = [](const std::array<long double, 3>& a, const std::array<long double, 3>& b)
  { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  Matrix4 m{};
  for (int j = 0; j < 3; ++j)
  {
    m[0][j] = side[j];
    m[1][j] = trueUp[j];
    m[2][j] = -forward[j];
  }
  m[0][3] = -dot(side, e);
  m[1][3] = -dot(trueUp, e);
  m[2][3] = dot(forward, e);
  m[3][3] = 1;
  return m;
}

/// glFrustum(l, r, b, t, n, f).
inline Matrix4 referenceFrustum(long double l, long double r, long double b, long double t,
                                long double n, long double f)
{
  Matrix4 m{};
  m[0][0] = 2 * n / (r - l);
  m[0][2] = (r + l) / (r - l);
  m[1][1] = 2 * n / (t - b);
  m[1][2] = (t + b) / (t - b);
  m[2][2] = -(f + n) / (f - n);
  m[2][3] = -2 * f * n / (f - n);
  m[3][2] = -1;
  return m;
}

/// glOrtho(l, r, b, t, n, f).
inline Matrix4 referenceOrtho(long double l, long double r, long double b, long double t,
                              long double n, long double f)
{
  Matrix4 m{};
  m[0][0] = 2 / (r - l);
  m[0][3] = -(r + l) / (r - l);
  m[1][1] = 2 / (t - b);
  m[1][3] = -(t + b) / (t - b);
  m[2][2] = -2 / (f - n);
  m[2][3] = -(f + n) / (f - n);
  m[3][3] = 1;
  return m;
}

/// vtkCamera's composite projection for these parameters: the near-plane half height is
/// near * tan(angle / 2) (or the parallel scale), the half width that times the aspect.
inline Matrix4 referenceWorldToClip(const sightline::CameraParameters& p, double aspect)
{
  const Matrix4 view = referenceLookAt(p.position, p.focalPoint, p.viewUp);
  const long double pi = 3.14159265358979323846264338327950288L;
  const long double halfHeight = p.parallelProjection
    ? (long double)p.parallelScale
    : p.nearClip * std::tan((long double)p.viewAngle * pi / 360.0L);
  const long double halfWidth = halfHeight * aspect;
  const Matrix4 projection = p.parallelProjection
    ? referenceOrtho(-halfWidth, halfWidth, -halfHeight, halfHeight, p.nearClip, p.farClip)
    : referenceFrustum(-halfWidth, halfWidth, -halfHeight, halfHeight, p.nearClip, p.farClip);
  return multiply(projection, view);
}

/// Pixel coordinates (lower-left origin) and window depth of a world point.
struct WindowPoint
{
  long double x, y, depth;
};

inline WindowPoint referenceProject(const Matrix4& worldToClip, const dvec3& p, int width,
                                    int height)
{
  std::array<long double, 4> clip{};
  for (int row = 0; row < 4; ++row)
    clip[row] = worldToClip[row][0] * p.x + worldToClip[row][1] * p.y + worldToClip[row][2] * p.z +
      worldToClip[row][3];
  const long double ndcX = clip[0] / clip[3], ndcY = clip[1] / clip[3], ndcZ = clip[2] / clip[3];
  return { (ndcX + 1) * width / 2, (ndcY + 1) * height / 2, (ndcZ + 1) / 2 };
}

/// The world point at pixel coordinates (px, py) and window depth: solves
/// worldToClip * (x, y, z, 1) = w * ndc by Gaussian elimination with partial pivoting, i.e. without
/// inverting the matrix the way the camera does.
inline dvec3 referenceUnproject(const Matrix4& worldToClip, long double px, long double py,
                                long double depth, int width, int height)
{
  const long double ndc[3] = { 2 * px / width - 1, 2 * py / height - 1, 2 * depth - 1 };
  // Unknowns (x, y, z, w): rows i < 3 say clip_i - w ndc_i = 0, row 3 says clip_w - w = 0.
  std::array<std::array<long double, 5>, 4> system{};
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 3; ++j)
      system[i][j] = worldToClip[i][j];
    system[i][3] = -(i < 3 ? ndc[i] : 1.0L);
    system[i][4] = -worldToClip[i][3];
  }
  for (int column = 0; column < 4; ++column)
  {
    int pivot = column;
    for (int row = column + 1; row < 4; ++row)
      if (std::fabs(system[row][column]) > std::fabs(system[pivot][column]))
        pivot = row;
    std::swap(system[column], system[pivot]);
    for (int row = 0; row < 4; ++row)
    {
      if (row == column)
        continue;
      const long double factor = system[row][column] / system[column][column];
      for (int k = column; k < 5; ++k)
        system[row][k] -= factor * system[column][k];
    }
  }
  return { double(system[0][4] / system[0][0]), double(system[1][4] / system[1][1]),
           double(system[2][4] / system[2][2]) };
}

/// Smallest root of |o + t d - c|^2 = r^2 with tnear < t < tfar, from the textbook quadratic in
/// long double (64-bit mantissa: cancellation costs nothing at the scales tested).
inline std::optional<long double> referenceSphereHit(const dvec3& origin, const dvec3& direction,
                                                     const dvec3& center, double radius,
                                                     long double tnear = 0,
                                                     long double tfar = INFINITY)
{
  const long double fx = (long double)origin.x - center.x, fy = (long double)origin.y - center.y,
                    fz = (long double)origin.z - center.z;
  const long double dx = direction.x, dy = direction.y, dz = direction.z;
  const long double a = dx * dx + dy * dy + dz * dz;
  const long double halfB = fx * dx + fy * dy + fz * dz;
  const long double c = fx * fx + fy * fy + fz * fz - (long double)radius * radius;
  const long double discriminant = halfB * halfB - a * c;
  if (discriminant < 0)
    return std::nullopt;
  const long double root = std::sqrt(discriminant);
  for (long double t : { (-halfB - root) / a, (-halfB + root) / a })
    if (t > tnear && t < tfar)
      return t;
  return std::nullopt;
}

/// A committed scene holding one sphere set.
inline std::unique_ptr<sightline::EmbreeScene> makeScene(
  std::shared_ptr<sightline::SphereSet> spheres)
{
  auto scene = std::make_unique<sightline::EmbreeScene>();
  scene->add(std::move(spheres));
  scene->commit();
  return scene;
}

inline std::string outputPath(const std::string& name)
{
  return std::string(SIGHTLINE_TEST_OUTPUT_DIR) + "/" + name;
}
/// A camera set up from parameters plus its independent reference matrix.
struct View
{
  sightline::CameraParameters parameters;
  int width;
  int height;

  Matrix4 reference() const { return referenceWorldToClip(parameters, double(width) / height); }
  sightline::Camera camera() const
  {
    return sightline::Camera::fromParameters(parameters, width, height);
  }
  sightline::vec3 viewDirection() const
  {
    return sightline::vec3(glm::normalize(parameters.focalPoint - parameters.position));
  }
};

/// Looking down -z at the origin from z = 10, parallel, half height `scale`.
inline View parallelView(int width, int height, double scale = 2.0)
{
  View view{ sightline::CameraParameters{}, width, height };
  view.parameters.position = { 0, 0, 10 };
  view.parameters.focalPoint = { 0, 0, 0 };
  view.parameters.viewUp = { 0, 1, 0 };
  view.parameters.parallelProjection = true;
  view.parameters.parallelScale = scale;
  view.parameters.nearClip = 1.0;
  view.parameters.farClip = 20.0;
  return view;
}

/// An oblique perspective view whose centre pixel looks straight at `focalPoint`.
inline View perspectiveView(int width, int height, sightline::dvec3 focalPoint)
{
  View view{ sightline::CameraParameters{}, width, height };
  view.parameters.position = { 3, 4, 9 };
  view.parameters.focalPoint = focalPoint;
  view.parameters.viewUp = { 0.2, 1, -0.1 };
  view.parameters.viewAngle = 25.0;
  view.parameters.nearClip = 0.5;
  view.parameters.farClip = 40.0;
  return view;
}
} // namespace sightline_test
