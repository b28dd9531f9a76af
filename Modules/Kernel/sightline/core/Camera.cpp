// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/core/Camera.h"

#include <algorithm>

#include <glm/gtc/matrix_transform.hpp>

#include <stdexcept>

namespace sightline
{
namespace
{
dvec3 project(const dmat4& m, const dvec3& p)
{
  const dvec4 h = m * dvec4(p, 1.0);
  return dvec3(h) / h.w;
}
} // namespace

Camera::Camera(const dmat4& worldToClip, int width, int height)
  : WorldToClip(worldToClip)
  , ClipToWorld(glm::inverse(worldToClip))
  , Width(width)
  , Height(height)
{
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("sightline::Camera: image size must be positive, got " +
      std::to_string(width) + "x" + std::to_string(height));
  // Pixel coordinates map to NDC by x_ndc = 2 px / width - 1; planes of constant NDC z are
  // planes in world space, so their points are affine in (px, py).
  auto plane = [&](double zNdc, dvec3& base, dvec3& dx, dvec3& dy)
  {
    base = project(ClipToWorld, dvec3(-1.0, -1.0, zNdc));
    dx = (project(ClipToWorld, dvec3(1.0, -1.0, zNdc)) - base) / double(width);
    dy = (project(ClipToWorld, dvec3(-1.0, 1.0, zNdc)) - base) / double(height);
  };
  plane(-1.0, NearBase, NearDx, NearDy);
  plane(1.0, FarBase, FarDx, FarDy);
  if (!std::isfinite(NearBase.x + NearDx.x + NearDy.x + FarBase.x + FarDx.x + FarDy.x))
    throw std::invalid_argument("sightline::Camera: the projection matrix is singular");
}

dmat4 Camera::worldToClipMatrix(const CameraParameters& p, double aspect)
{
  const dmat4 view = glm::lookAt(p.position, p.focalPoint, p.viewUp);
  dmat4 projection;
  if (p.parallelProjection)
  {
    const double h = p.parallelScale;
    const double w = h * aspect;
    projection = glm::ortho(-w, w, -h, h, p.nearClip, p.farClip);
  }
  else
  {
    const double h = p.nearClip * std::tan(glm::radians(p.viewAngle) / 2.0);
    const double w = h * aspect;
    projection = glm::frustum(-w, w, -h, h, p.nearClip, p.farClip);
  }
  return projection * view;
}

Camera Camera::fromParameters(const CameraParameters& parameters, int width, int height)
{
  if (height <= 0)
    throw std::invalid_argument("sightline::Camera: image height must be positive");
  return Camera(worldToClipMatrix(parameters, double(width) / double(height)), width, height);
}

dvec3 Camera::unproject(double px, double py, double windowDepth) const
{
  const dvec3 ndc(2.0 * px / Width - 1.0, 2.0 * py / Height - 1.0, 2.0 * windowDepth - 1.0);
  return project(ClipToWorld, ndc);
}

double Camera::primaryRayParameterAt(double px, double py, double windowDepth) const
{
  const DoubleRay ray = doublePrimaryRay(px, py); // unit direction: t is a distance
  const double t = glm::dot(unproject(px, py, windowDepth) - ray.origin, ray.direction);
  return std::max(ray.tnear, t);
}
} // namespace sightline
