// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/baselines/SHGlyphTessellation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace sightline
{
namespace
{
std::uint32_t packColor(const vec3& rgb)
{
  auto channel = [](float c)
  { return std::uint32_t(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f)); };
  return channel(rgb.x) | (channel(rgb.y) << 8) | (channel(rgb.z) << 16) | (255u << 24);
}

void checkSubdivisions(int subdivisions)
{
  if (subdivisions < 0 || subdivisions > kMaxIcosphereSubdivisions)
    throw std::invalid_argument("icosphere subdivisions " + std::to_string(subdivisions) +
      " not in [0, " + std::to_string(kMaxIcosphereSubdivisions) + "]");
}
} // namespace

Icosphere makeIcosphere(int subdivisions)
{
  checkSubdivisions(subdivisions);
  Icosphere sphere;
  // The icosahedron: cyclic permutations of (0, +-1, +-phi).
  const double phi = 0.5 * (1.0 + std::sqrt(5.0));
  const double base[12][3] = { { -1, phi, 0 }, { 1, phi, 0 }, { -1, -phi, 0 }, { 1, -phi, 0 },
    { 0, -1, phi }, { 0, 1, phi }, { 0, -1, -phi }, { 0, 1, -phi }, { phi, 0, -1 }, { phi, 0, 1 },
    { -phi, 0, -1 }, { -phi, 0, 1 } };
  for (const auto& v : base)
    sphere.vertices.push_back(glm::normalize(dvec3(v[0], v[1], v[2])));
  sphere.triangles = { 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10,
    2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10,
    8, 6, 7, 9, 8, 1 };

  for (int level = 0; level < subdivisions; ++level)
  {
    // Each edge gets one midpoint, shared by the two triangles on either side.
    std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
    midpoints.reserve(sphere.triangles.size());
    auto midpoint = [&](std::uint32_t a, std::uint32_t b)
    {
      const std::uint64_t key = a < b ? (std::uint64_t(a) << 32 | b) : (std::uint64_t(b) << 32 | a);
      const auto found = midpoints.find(key);
      if (found != midpoints.end())
        return found->second;
      const std::uint32_t index = std::uint32_t(sphere.vertices.size());
      sphere.vertices.push_back(glm::normalize(sphere.vertices[a] + sphere.vertices[b]));
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<std::uint32_t> refined;
    refined.reserve(4 * sphere.triangles.size());
    for (std::size_t t = 0; t < sphere.triangles.size(); t += 3)
    {
      const std::uint32_t a = sphere.triangles[t], b = sphere.triangles[t + 1], c = sphere.triangles[t + 2];
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      refined.insert(refined.end(), { a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca });
    }
    sphere.triangles = std::move(refined);
  }
  return sphere;
}

std::shared_ptr<TriangleMesh> tessellateSHGlyphs(
  const SHGlyphSet& glyphs, const SHTessellationOptions& options, SHTessellationInfo* info)
{
  const auto start = std::chrono::steady_clock::now();
  const Icosphere sphere = makeIcosphere(options.subdivisions);
  const std::size_t nv = sphere.vertices.size();
  const std::size_t nt = sphere.triangles.size() / 3;
  const std::size_t n = glyphs.size();
  if (n * nv >= std::size_t(std::numeric_limits<std::uint32_t>::max()))
    throw std::invalid_argument("tessellating " + std::to_string(n) + " glyphs with " +
      std::to_string(nv) + " vertices each exceeds 32-bit vertex indices");

  // Basis values at the sphere's vertices, per order used (glyphs may have trimmed bands).
  std::vector<std::vector<double>> basis(kMaxGlyphOrder / 2 + 1);
  for (std::size_t i = 0; i < n; ++i)
  {
    const int order = glyphs.order(unsigned(i));
    std::vector<double>& table = basis[order / 2];
    if (!table.empty())
      continue;
    const int stride = shCoefficientCount(order);
    table.resize(nv * stride);
    for (std::size_t v = 0; v < nv; ++v)
      evaluateSH<double>(order, sphere.vertices[v].x, sphere.vertices[v].y, sphere.vertices[v].z,
        table.data() + v * stride);
  }

  const bool colored = glyphs.hasPrimitiveColors();
  const bool withNormals = options.normals != SHTessellationNormals::Flat;
  std::vector<vec3> vertices(n * nv);
  std::vector<std::uint32_t> triangles(n * nt * 3);
  std::vector<std::uint32_t> colors(colored ? n * nv : 0);
  std::vector<vec3> normals(withNormals ? n * nv : 0);

  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i)
    {
      const unsigned glyph = unsigned(i);
      const int order = glyphs.order(glyph);
      const int stride = shCoefficientCount(order);
      const double* b = glyphs.coefficients(glyph);
      const double* table = basis[order / 2].data();
      const dvec3 center(glyphs.center(glyph));
      const std::size_t v0 = i * nv;
      for (std::size_t v = 0; v < nv; ++v)
      {
        double value = 0.0;
        for (int j = 0; j < stride; ++j)
          value += b[j] * table[v * stride + j];
        const double radius = options.clipNegative ? std::max(value, 0.0) : std::abs(value);
        const dvec3 offset = radius * sphere.vertices[v];
        vertices[v0 + v] = vec3(center + offset);
        if (colored)
          colors[v0 + v] = packColor(glyphs.surfaceColor(glyph, vec3(center + sphere.vertices[v])));
        if (options.normals == SHTessellationNormals::Exact)
        {
          dvec3 normal = radius > 0.0 ? shGlyphNormal(order, b, offset) : dvec3(0.0);
          const double length = glm::length(normal);
          normals[v0 + v] = length > 0.0 && std::isfinite(length) ? vec3(normal / length)
                                                                   : vec3(sphere.vertices[v]);
        }
      }
      const std::uint32_t base = std::uint32_t(v0);
      for (std::size_t t = 0; t < 3 * nt; ++t)
        triangles[3 * nt * i + t] = base + sphere.triangles[t];
      if (options.normals == SHTessellationNormals::Mesh)
      {
        // Cross products weight each face by twice its area; computed from the double offsets
        // (not the float world positions) so distant glyphs keep accurate normals.
        std::vector<dvec3> sum(nv, dvec3(0.0));
        std::vector<dvec3> local(nv);
        for (std::size_t v = 0; v < nv; ++v)
          local[v] = dvec3(vertices[v0 + v]) - center;
        for (std::size_t t = 0; t < nt; ++t)
        {
          const std::uint32_t a = sphere.triangles[3 * t], bb = sphere.triangles[3 * t + 1],
                              c = sphere.triangles[3 * t + 2];
          const dvec3 face = glm::cross(local[bb] - local[a], local[c] - local[a]);
          sum[a] += face;
          sum[bb] += face;
          sum[c] += face;
        }
        for (std::size_t v = 0; v < nv; ++v)
        {
          const double length = glm::length(sum[v]);
          normals[v0 + v] = length > 0.0 ? vec3(sum[v] / length) : vec3(sphere.vertices[v]);
        }
      }
    });

  auto mesh = std::make_shared<TriangleMesh>(std::move(vertices), std::move(triangles));
  if (colored)
    mesh->setVertexColors(std::move(colors));
  if (withNormals)
    mesh->setVertexNormals(std::move(normals));
  mesh->material = glyphs.material;
  if (info)
  {
    info->glyphs = n;
    info->verticesPerGlyph = nv;
    info->trianglesPerGlyph = nt;
    info->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return mesh;
}
} // namespace sightline
