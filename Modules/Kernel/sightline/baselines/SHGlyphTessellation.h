// SPDX-License-Identifier: BSD-3-Clause
// The tessellated baseline for SH glyphs, built the way DIPY/FURY's odf_slicer and MRtrix's
// mrview build theirs: a unit sphere mesh (here an icosphere) is copied once per glyph and each
// vertex v is moved to c + |F(v)| v, where F is the glyph's function. The glyphs come from an
// SHGlyphSet, whose canonical scaled coefficients (coefficients(i), order(i), center(i)) are
// the single place where input conventions are converted, so the exact and the tessellated
// glyphs are the same surface.
//
// Why |F(v)| v and not F(v) v: the exact glyph is the surface |p| = |F(p / |p|)|
// (SHGlyph.h). Both F(v) v and |F(v)| v lie on it (F is even, so a negative F(v) v equals
// |F(-v)| (-v)), but F(v) v sends the vertices of a negative lobe to the antipodal side, where
// the mesh turns inside out and overlaps itself; |F(v)| v keeps the sphere's topology and
// orientation. DIPY's odf_slicer scales by the signed value (optionally clipped); clipping is
// `clipNegative` here (max(F(v), 0) v, negative lobes collapse onto the centre, as with
// SHGlyphOptions::hideNegativeLobes).
#pragma once

#include "sightline/glyphs/SHGlyphSet.h"
#include "sightline/baselines/TriangleMesh.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace sightline
{
/// Most subdivisions makeIcosphere accepts (163,842 vertices, 327,680 triangles per sphere).
constexpr int kMaxIcosphereSubdivisions = 7;

/// Vertices of an icosphere with `subdivisions` levels: 10 * 4^s + 2 (12, 42, 162, 642, 2562,
/// 10242 for s = 0..5).
constexpr std::size_t icosphereVertexCount(int subdivisions)
{
  return 10 * (std::size_t(1) << (2 * subdivisions)) + 2;
}
/// Triangles of an icosphere with `subdivisions` levels: 20 * 4^s.
constexpr std::size_t icosphereTriangleCount(int subdivisions)
{
  return 20 * (std::size_t(1) << (2 * subdivisions));
}

/// A unit sphere mesh: vertices on the unit sphere, triangles counter-clockwise from outside.
struct Icosphere
{
  std::vector<dvec3> vertices;
  std::vector<std::uint32_t> triangles; ///< 3 indices per triangle
};

/// The regular icosahedron with every triangle split into four `subdivisions` times, new
/// vertices projected onto the unit sphere (as DIPY's create_unit_sphere / FURY's
/// prim_sphere("repulsion"-free) subdivision). Throws std::invalid_argument for subdivisions
/// outside [0, kMaxIcosphereSubdivisions].
Icosphere makeIcosphere(int subdivisions);

/// Normals of the tessellated glyphs.
enum class SHTessellationNormals
{
  Flat, ///< each triangle's geometric normal (no vertex normals)
  Mesh, ///< area-weighted mean of the adjacent triangles' normals per vertex (FURY, VTK's vtkPolyDataNormals)
  Exact, ///< the exact glyph normal at each vertex (Eq. 11, SHGlyph.h), interpolated
};

struct SHTessellationOptions
{
  int subdivisions = 3; ///< icosphere levels: 642 vertices, 1280 triangles per glyph
  /// Vertices at max(F(v), 0) v instead of |F(v)| v (negative lobes hidden).
  bool clipNegative = false;
  SHTessellationNormals normals = SHTessellationNormals::Mesh;
};

/// Statistics of a tessellation, for benchmarks.
struct SHTessellationInfo
{
  std::size_t glyphs = 0;
  std::size_t verticesPerGlyph = 0;
  std::size_t trianglesPerGlyph = 0;
  double seconds = 0.0; ///< wall time of the tessellation (all threads)
};

/// One triangle mesh holding every glyph of the set: glyph i occupies vertices
/// [i * verticesPerGlyph, (i + 1) * verticesPerGlyph) and triangles likewise. Vertices are
/// coloured by direction, |v| as RGB (SHGlyphSet's SHColoring::Direction), or with the set's
/// per-glyph colours when it has them. Throws std::invalid_argument for subdivisions out of
/// range and when the mesh would need more than 2^32 - 1 vertices.
std::shared_ptr<TriangleMesh> tessellateSHGlyphs(const SHGlyphSet& glyphs,
  const SHTessellationOptions& options = {}, SHTessellationInfo* info = nullptr);
} // namespace sightline
