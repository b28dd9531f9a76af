// SPDX-License-Identifier: BSD-3-Clause
// Indexed triangles as Embree's built-in RTC_GEOMETRY_TYPE_TRIANGLE: the tessellated baseline
// the exact primitives are compared with (e.g. SH glyphs deformed from an icosphere, see
// SHGlyphTessellation.h). Shading uses the geometric normal of each triangle unless vertex
// normals are given; those are interpolated with the hit's barycentric coordinates (Phong
// normals, as a rasteriser's per-vertex normals) by an Embree intersection filter.
#pragma once

#include "sightline/core/Geometry.h"

#include <array>
#include <cstdint>
#include <vector>

namespace sightline
{
class TriangleMesh : public Geometry
{
public:
  /// `triangles` holds three vertex indices per triangle, counter-clockwise seen from outside
  /// (only the orientation of the reported normal depends on it; shading is two-sided).
  /// Throws std::invalid_argument when the index count is not a multiple of 3, an index is
  /// out of range, a vertex is not finite, or there are more than 2^32 - 1 vertices.
  TriangleMesh(std::vector<vec3> vertices, std::vector<std::uint32_t> triangles);

  /// One RGBA8 colour per vertex (packRGBA8 layout), interpolated over each triangle. Replaces
  /// per-triangle colours. Throws std::invalid_argument for a size that does not match.
  void setVertexColors(std::vector<std::uint32_t> colors);
  /// One RGBA8 colour per triangle. Replaces per-vertex colours.
  void setTriangleColors(std::vector<std::uint32_t> colors);
  /// One shading normal per vertex (need not be unit length), interpolated with the hit's
  /// barycentric coordinates. Empty: the geometric normal. Set before the mesh is added to a
  /// scene.
  void setVertexNormals(std::vector<vec3> normals);

  std::size_t size() const override { return TriangleCount; }
  std::size_t vertexCount() const { return VertexCount; }
  const vec3& vertex(std::size_t i) const { return Vertices[i]; }
  std::array<std::uint32_t, 3> triangle(std::size_t i) const
  {
    return { Indices[3 * i], Indices[3 * i + 1], Indices[3 * i + 2] };
  }
  bool hasVertexNormals() const { return !Normals.empty(); }

  RTCGeometry createEmbreeGeometry(RTCDevice device) const override;
  bool hasPrimitiveColors() const override { return !VertexColors.empty() || !TriangleColors.empty(); }
  /// The triangle's colour, or the mean of its vertices' colours.
  vec3 primitiveColor(unsigned primitive) const override;
  /// Vertex colours interpolated at the point (projected onto the triangle's plane).
  vec3 surfaceColor(unsigned primitive, const dvec3& point) const override;
  std::size_t memoryBytes() const override;
  Box3 bounds() const override { return AllBounds; }

  /// Barycentric coordinates (w0, w1, w2), summing to 1, of the point nearest to `point` on
  /// triangle `primitive`.
  vec3 barycentric(unsigned primitive, const vec3& point) const;

private:
  static void intersectFilter(const RTCFilterFunctionNArguments* args);

  // Embree reads vertex buffers with 16-byte loads: Vertices holds one spare element.
  std::vector<vec3> Vertices;
  std::vector<std::uint32_t> Indices;
  std::vector<std::uint32_t> VertexColors;
  std::vector<std::uint32_t> TriangleColors;
  std::vector<vec3> Normals;
  std::size_t VertexCount = 0;
  std::size_t TriangleCount = 0;
  Box3 AllBounds;
};
} // namespace sightline
