// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/baselines/TriangleMesh.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace sightline
{
namespace
{
vec3 unpackRGB(std::uint32_t c)
{
  return vec3(float(c & 0xffu), float((c >> 8) & 0xffu), float((c >> 16) & 0xffu)) / 255.0f;
}
} // namespace

TriangleMesh::TriangleMesh(std::vector<vec3> vertices, std::vector<std::uint32_t> triangles)
  : Vertices(std::move(vertices))
  , Indices(std::move(triangles))
{
  if (Indices.size() % 3 != 0)
    throw std::invalid_argument("sightline::TriangleMesh: " + std::to_string(Indices.size()) +
      " indices are not a whole number of triangles (3 per triangle)");
  if (Vertices.size() >= std::size_t(std::numeric_limits<std::uint32_t>::max()))
    throw std::invalid_argument("sightline::TriangleMesh: " + std::to_string(Vertices.size()) +
      " vertices exceed the 32-bit indices");
  VertexCount = Vertices.size();
  TriangleCount = Indices.size() / 3;
  for (std::size_t i = 0; i < VertexCount; ++i)
  {
    if (!isFinite(Vertices[i]))
      throw std::invalid_argument(
        "sightline::TriangleMesh: vertex " + std::to_string(i) + " is not finite");
    AllBounds.extend(Vertices[i]);
  }
  for (std::size_t i = 0; i < Indices.size(); ++i)
    if (Indices[i] >= VertexCount)
      throw std::invalid_argument("sightline::TriangleMesh: triangle " + std::to_string(i / 3) +
        " refers to vertex " + std::to_string(Indices[i]) + " of " + std::to_string(VertexCount));
  Vertices.emplace_back(0.0f); // padding for Embree's 16-byte loads
}

void TriangleMesh::setVertexColors(std::vector<std::uint32_t> colors)
{
  if (colors.size() != VertexCount)
    throw std::invalid_argument("sightline::TriangleMesh: " + std::to_string(colors.size()) +
      " vertex colours for " + std::to_string(VertexCount) + " vertices");
  VertexColors = std::move(colors);
  TriangleColors.clear();
}

void TriangleMesh::setTriangleColors(std::vector<std::uint32_t> colors)
{
  if (colors.size() != TriangleCount)
    throw std::invalid_argument("sightline::TriangleMesh: " + std::to_string(colors.size()) +
      " triangle colours for " + std::to_string(TriangleCount) + " triangles");
  TriangleColors = std::move(colors);
  VertexColors.clear();
}

void TriangleMesh::setVertexNormals(std::vector<vec3> normals)
{
  if (!normals.empty() && normals.size() != VertexCount)
    throw std::invalid_argument("sightline::TriangleMesh: " + std::to_string(normals.size()) +
      " vertex normals for " + std::to_string(VertexCount) + " vertices");
  Normals = std::move(normals);
}

RTCGeometry TriangleMesh::createEmbreeGeometry(RTCDevice device) const
{
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
    Vertices.data(), 0, sizeof(vec3), VertexCount);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, Indices.data(),
    0, 3 * sizeof(std::uint32_t), TriangleCount);
  if (!Normals.empty())
  {
    rtcSetGeometryUserData(geometry, const_cast<TriangleMesh*>(this));
    rtcSetGeometryIntersectFilterFunction(geometry, &TriangleMesh::intersectFilter);
  }
  rtcCommitGeometry(geometry);
  return geometry;
}

void TriangleMesh::intersectFilter(const RTCFilterFunctionNArguments* args)
{
  // Every accepted candidate gets its interpolated normal; the nearest one is what remains.
  const auto* self = static_cast<const TriangleMesh*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i)
  {
    if (args->valid[i] != -1)
      continue;
    const unsigned primitive = RTCHitN_primID(args->hit, args->N, i);
    const float u = RTCHitN_u(args->hit, args->N, i);
    const float v = RTCHitN_v(args->hit, args->N, i);
    const std::uint32_t* t = self->Indices.data() + 3 * std::size_t(primitive);
    const vec3 n = (1.0f - u - v) * self->Normals[t[0]] + u * self->Normals[t[1]] + v * self->Normals[t[2]];
    RTCHitN_Ng_x(args->hit, args->N, i) = n.x;
    RTCHitN_Ng_y(args->hit, args->N, i) = n.y;
    RTCHitN_Ng_z(args->hit, args->N, i) = n.z;
  }
}

vec3 TriangleMesh::primitiveColor(unsigned primitive) const
{
  if (!TriangleColors.empty())
    return unpackRGB(TriangleColors[primitive]);
  const std::uint32_t* t = Indices.data() + 3 * std::size_t(primitive);
  return (unpackRGB(VertexColors[t[0]]) + unpackRGB(VertexColors[t[1]]) + unpackRGB(VertexColors[t[2]])) / 3.0f;
}

vec3 TriangleMesh::barycentric(unsigned primitive, const vec3& point) const
{
  const std::uint32_t* t = Indices.data() + 3 * std::size_t(primitive);
  const dvec3 a(Vertices[t[0]]), b(Vertices[t[1]]), c(Vertices[t[2]]);
  const dvec3 e1 = b - a, e2 = c - a, q = dvec3(point) - a;
  // Least squares in the triangle's plane: [e1 e2]^T [e1 e2] (w1, w2) = [e1 e2]^T q.
  const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const double r1 = glm::dot(e1, q), r2 = glm::dot(e2, q);
  const double det = d11 * d22 - d12 * d12;
  double w1 = 1.0 / 3.0, w2 = 1.0 / 3.0;
  if (det > 0.0)
  {
    w1 = (d22 * r1 - d12 * r2) / det;
    w2 = (d11 * r2 - d12 * r1) / det;
  }
  // Rounding can put a hit just outside its triangle: clamp and renormalise.
  w1 = std::clamp(w1, 0.0, 1.0);
  w2 = std::clamp(w2, 0.0, 1.0);
  double w0 = std::max(0.0, 1.0 - w1 - w2);
  const double sum = w0 + w1 + w2;
  return vec3(float(w0 / sum), float(w1 / sum), float(w2 / sum));
}

vec3 TriangleMesh::surfaceColor(unsigned primitive, const dvec3& point) const
{
  if (VertexColors.empty())
    return primitiveColor(primitive);
  const std::uint32_t* t = Indices.data() + 3 * std::size_t(primitive);
  const vec3 w = barycentric(primitive, vec3(point));
  return w.x * unpackRGB(VertexColors[t[0]]) + w.y * unpackRGB(VertexColors[t[1]]) +
    w.z * unpackRGB(VertexColors[t[2]]);
}

std::size_t TriangleMesh::memoryBytes() const
{
  return Vertices.capacity() * sizeof(vec3) + Indices.capacity() * sizeof(std::uint32_t) +
    VertexColors.capacity() * sizeof(std::uint32_t) +
    TriangleColors.capacity() * sizeof(std::uint32_t) + Normals.capacity() * sizeof(vec3);
}
} // namespace sightline
