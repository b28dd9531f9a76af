// SPDX-License-Identifier: BSD-3-Clause
// Generalized tubes (Han et al. 2019) as one Embree user geometry: control points with radii,
// each linked to a predecessor (or -1), drawn as a sphere at every point and the tangential cone
// stump (TubeLink.h) to its predecessor. Bifurcations need no special case: two links naming
// the same predecessor share its sphere.
//
// The paper's four implementation choices (Section 4.2) are all here, picked by TubeLayout:
// - primitives: a "combined" primitive per link (its end sphere and its stump, one BVH leaf) or
//   "separate" spheres and stumps (two BVH leaves per link);
// - transforms: stump parameters computed on the fly from the two control points (the smallest
//   memory: a point, a radius and a predecessor index per link) or precomputed per link.
// A fifth, "chunked" primitives, is for whole-brain tractograms (10^8 links and more), where the
// BVH (60-80 bytes per primitive) dominates: one primitive is a chunk of up to chunkSize
// consecutive links of one run (each node's predecessor the node before it), tested link by
// link with the same sphere and stump code; the chunk's members need no predecessor index and
// a chunk of equal radii stores one. It draws exactly what "combined, on-the-fly" draws.
//
// Opaque scenes use the first-hit path (intersect()). Translucent scenes use the union's
// surfaces instead (insideIntervals() and unionSurfaces() in Geometry.h, Section 4.3): every
// overlap interval along the ray is collected and only transitions between outside and inside
// are drawn, so overlapping links show no interior surfaces.
#pragma once

#include "sightline/core/Geometry.h"
#include "sightline/core/HugePages.h"
#include "sightline/math/Half.h"
#include "sightline/tubes/TubeLink.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sightline
{
struct TubeLayout
{
  enum class Primitives
  {
    Combined, ///< one primitive per link: end sphere + stump to the predecessor
    Separate, ///< spheres and stumps are primitives of their own
    Chunked,  ///< one primitive per run of up to chunkSize links (stumps always on the fly)
  };
  enum class Transforms
  {
    OnTheFly,    ///< stump parameters derived from the control points at every test
    Precomputed, ///< stump parameters stored per link
  };
  Primitives primitives = Primitives::Combined;
  Transforms transforms = Transforms::OnTheFly;
  /// Chunked: the most links per primitive. 8 from the tube-chains benchmark at 1M links: BVH
  /// 24.6 / 10.8 / 6.1 / 3.5 bytes per link for 4 / 8 / 16 / 32 against 94 combined, frames
  /// 1.4 / 1.8 / 3.6 / 8.6 times the combined layout's: 16 saves 5 more bytes at twice the time.
  unsigned chunkSize = kDefaultChunkSize;
  static constexpr unsigned kDefaultChunkSize = 8;

  /// "combined, on-the-fly" and so on, as the paper's Table 1 names them; "chunked (8 links), on-the-fly".
  std::string name() const;
};

class TubeRunBuilder;
struct OuterLinkOptions;
struct OuterLinkReport;

class TubeSet : public UserGeometry<TubeSet>
{
public:
  /// One control point per position; `radii` one per point; `predecessors` one per point,
  /// -1 for the first point of a tube. `colors` (RGBA8) is empty or one per point.
  /// Throws std::invalid_argument for size mismatches, a predecessor out of range and cyclic
  /// links (naming a point on the cycle). Points with a non-finite position, a non-finite or
  /// negative radius are dropped with their links and reported in report(); a link of zero
  /// length, or whose one sphere holds the other, draws only its spheres.
  TubeSet(const std::vector<vec3>& points, const std::vector<float>& radii,
    const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors = {},
    TubeLayout layout = {});
  /// The same with the points given relative to `origin`, kept in double: tubes far from the
  /// world origin keep float precision relative to the set's extent and are intersected with
  /// double rays in that frame.
  TubeSet(const dvec3& origin, const std::vector<vec3>& points, const std::vector<float>& radii,
    const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors = {},
    TubeLayout layout = {});

  std::size_t size() const override
  {
    return Chunked ? Chunks.size() - 1 : Nodes.size() + StumpEnds.size();
  }
  bool hasPrimitiveColors() const override { return !Colors.empty(); }
  vec3 primitiveColor(unsigned primitive) const override;
  std::size_t memoryBytes() const override;
  bool prefersCompactBvh() const override { return Chunked; }
  Box3 bounds() const override { return AllBounds; }
  void insideIntervals(unsigned primitive, const DoubleRay& ray, std::vector<InsideInterval>& out) const override;
  vec3 partNormal(std::uint32_t part, const dvec3& point) const override;
  vec3 partColor(std::uint32_t part) const override;
  /// Chunked: a pick names the link (node) hit; other layouts: the primitive (as before).
  std::uint32_t selectionIndex(unsigned primitive, std::uint32_t part) const override;
  std::size_t selectionCount() const override
  {
    return !SelectedNode.empty() ? SelectionTotal : Chunked ? NodeCount : size();
  }

  Box3 bounds(unsigned primitive) const;
  bool intersect(unsigned primitive, const DoubleRay& ray, SurfaceHit& hit) const;

  const TubeLayout& layout() const { return Layout; }
  /// Control points kept (after dropping bad ones) and links between them.
  std::size_t pointCount() const { return NodeCount; }
  std::size_t linkCount() const { return Links; }
  const ValidationReport& report() const { return Report; }
  /// Chunked layout: how many chunks hold their positions as float16 offsets (6 bytes a node)
  /// rather than floats (12): those of three nodes or more whose offsets are exact.
  std::size_t compactChunkCount() const;
  /// For picking: the kept control point whose link (from its predecessor) and end sphere a
  /// primitive draws, that point's predecessor (a kept index, or -1 where a tube starts), and
  /// its index among the points given to the constructor.
  /// Chunked layout: the first node of the chunk (a pick names its link: nodeOfSelection).
  std::uint32_t nodeOfPrimitive(unsigned primitive) const
  {
    return Chunked ? Chunks[primitive].firstNode : nodeOf(primitive);
  }
  /// The node a selection index (Geometry::selectionIndex, PixelPrimitive::primitive) names.
  std::uint32_t nodeOfSelection(std::uint32_t index) const
  {
    return Chunked ? index : nodeOf(index);
  }
  std::int32_t predecessorOf(std::uint32_t node) const;
  std::uint32_t sourceIndexOf(std::uint32_t node) const
  {
    return SourceIndex.empty() ? node : SourceIndex[node];
  }
  /// What control points (and precomputed stumps) are relative to.
  const dvec3& origin() const { return Origin; }

private:
  friend class TubeRunBuilder;
  friend std::shared_ptr<TubeSet> outerLinks(const TubeSet&, const OuterLinkOptions&, OuterLinkReport*);
  TubeSet() = default;
  /// What both public constructors do, once Origin is set.
  void construct(const std::vector<vec3>& points, const std::vector<float>& radii,
    const std::vector<std::int64_t>& predecessors, const std::vector<std::uint32_t>& colors);
  /// Three halves: a compact chunk's position offset from its anchor.
  struct Half3
  {
    std::uint16_t v[3];
  };
  /// Chunked layout: one chunk's positions, read in place (wide chunks) or decoded from the
  /// anchor and float16 offsets (compact chunks) to the very floats they were built from.
  struct ChunkPoints
  {
    const vec3* wide = nullptr;
    const Half3* offsets = nullptr;
    vec3 anchor{ 0.0f };
    vec3 operator[](std::uint32_t i) const
    {
      if (wide)
        return wide[i];
      const Half3& h = offsets[i];
      return anchor + vec3(halfToFloat(h.v[0]), halfToFloat(h.v[1]), halfToFloat(h.v[2]));
    }
  };
  ChunkPoints pointsOf(unsigned chunk) const;
  /// Starts loading what pointsOf(), chunkStart() and the chunk's radii read (its table
  /// entries should be in the cache): for passes that visit chunks out of order.
  void prefetchChunk(unsigned chunk) const;
  /// Chunked layout: the node a chunk's first link starts from (position, radius), read without
  /// a search where it is the previous chunk's last node; false where the chunk starts a tube.
  bool chunkStart(unsigned chunk, vec4& start) const;
  /// Chunked layout: the last chunk's reach and positions (compactly where that is exact) from
  /// its `count` nodes (and radii); `start` is the node its first link starts from, or null.
  void storeChunk(const vec3* positions, const float* radii, std::size_t count, const vec4* start);
  /// Stump parameters in single precision (the precomputed layouts).
  struct StoredStump
  {
    vec3 base, axis;
    float slope, cosine, radius1, u1, u2;
  };
  ConeStump stumpOf(std::uint32_t node) const;
  std::uint32_t nodeOf(unsigned primitive) const;
  /// Chunked layout: the chunks from Nodes and Predecessors, which are then freed.
  void buildChunks();
  /// Chunked layout: appends a node linked to `predecessor` (a kept node or -1); it joins the
  /// open chunk when it links to the node before and the chunk has room.
  void appendChunkNode(const vec3& position, float radius, std::int32_t predecessor);
  /// Chunked layout: appends `count` nodes, the first starting a tube and each other linked to
  /// the node before, in chunks stored at once (what appendChunkNode gives for the same nodes).
  void appendLinkedNodes(const vec3* points, const float* radii, std::size_t count);
  /// Chunked layout: reserves Compact (or Wide) once at the size ReserveHint and ChunkHint
  /// expect, before its first chunk is stored (a grown vector's trim would copy it at the peak).
  void reservePositions(bool compact);
  /// Chunked layout: appends the chunks of `part` (built alone, not finished) after this set's,
  /// its nodes numbered on from this set's: what building its runs here would have stored.
  void appendChunks(const TubeSet& part);
  /// Chunked layout: empties the chunk tables of a set being built, keeping their storage.
  void clearChunks();
  /// Chunked layout: stores the open (last) chunk, with one radius where all its radii are equal.
  void closeChunk();
  /// Chunked layout: closes the open chunk and ends the chunk tables with the node and radius
  /// counts (as the chunk members' comment below has them).
  void finishChunks();
  std::uint32_t chunkOf(std::uint32_t node) const;
  /// Position and radius of a node in any layout.
  vec4 nodeAt(std::uint32_t node) const;
  Box3 chunkBounds(unsigned chunk) const;
  /// The union of every primitive's bounds (AllBounds), in parallel.
  Box3 primitiveBoundsUnion() const;
  bool intersectChunk(unsigned chunk, const DoubleRay& ray, SurfaceHit& hit) const;
  void chunkIntervals(unsigned chunk, const DoubleRay& ray, std::vector<InsideInterval>& out) const;

  TubeLayout Layout;
  dvec3 Origin{ 0.0 };
  std::vector<vec4> Nodes;                 ///< kept control points: position (from Origin), radius
  std::vector<std::int32_t> Predecessors;  ///< kept index of each node's predecessor, or -1
  std::vector<std::uint32_t> SourceIndex;  ///< constructor index of each node; empty: the same
  std::vector<std::uint32_t> StumpEnds;    ///< separate layout: end node of each stump primitive
  std::vector<StoredStump> Stumps;         ///< precomputed: one per node (combined) or stump
  std::size_t Links = 0;
  std::size_t NodeCount = 0;
  // Chunked layout (Nodes and Predecessors empty): node i of chunk c, Chunks[c].firstNode <= i <
  // Chunks[c + 1].firstNode, links to i - 1, its first node to Chunks[c].predecessor; its radii
  // are Radii[Chunks[c].firstRadius ...], one for the chunk when the next chunk's firstRadius is
  // one more. A chunk's positions are either "wide", Wide[Chunks[c].positions ...], or
  // "compact" (the top bit of positions set): Compact[s] and Compact[s + 1] hold the bits of the
  // chunk's float anchor, then one float16 offset per node, for chunks where anchor + offset
  // gives back every float position exactly (Documentation/tubes.md: float16 files always do).
  struct ChunkEntry
  {
    std::uint32_t firstNode;
    std::int32_t predecessor; ///< of the first node: a kept node or -1
    std::uint32_t firstRadius;
    std::uint32_t positions;  ///< index into Wide, or kCompactChunk | index into Compact
    /// The radius about the segment from the first to the last node that holds the chunk (a
    /// ray missing that capsule misses every link).
    float reach;
  };
  static constexpr std::uint32_t kCompactChunk = 0x80000000u;
  bool Chunked = false;
  /// One per chunk, and an end marker (firstNode: the node count, firstRadius: Radii's size):
  /// one table, so that a chunk's test reads one cache line of it, not five.
  /// The tables every ray reads at random (10^9 links: 14 GB): on huge pages where Linux gives them.
  template <class T>
  using Table = std::vector<T, HugePageAllocator<T>>;
  Table<ChunkEntry> Chunks;
  Table<Half3> Compact;
  Table<vec3> Wide;
  Table<float> Radii;
  std::vector<vec3> OpenPositions; ///< building: the open chunk's positions
  std::size_t ReserveHint = 0;     ///< building: points expected (TubeRunBuilder::reserve)
  std::size_t ChunkHint = 0;       ///< building: chunks expected
  std::vector<std::uint32_t> Colors;
  /// outerLinks(): the node of the whole set each node stands for in picks, and that set's
  /// selectionCount(); empty for a whole set.
  std::vector<std::uint32_t> SelectedNode;
  std::size_t SelectionTotal = 0;
  Box3 AllBounds;
  ValidationReport Report;
};

/// Builds a chunked tube set (TubeLayout::Primitives::Chunked) one run of linked points at a
/// time, never holding the predecessor form the constructor takes: what streaming a whole-brain
/// tractogram piece by piece needs (Documentation/tubes.md). Runs added here draw exactly what
/// the constructor draws for the same points with each point's predecessor the point before
/// (-1 at a run's start): a point with a non-finite position or a negative or non-finite radius
/// is dropped with its links, and the run goes on from the next point as a new tube.
class TubeRunBuilder
{
public:
  /// Points are given relative to `origin` (see TubeSet's constructors).
  explicit TubeRunBuilder(const dvec3& origin = dvec3(0.0),
    unsigned chunkSize = TubeLayout::kDefaultChunkSize, bool withColors = false);

  /// Room for `points` control points in all, in `runs` runs where known, to spare the copies
  /// of growing vectors (a hint).
  void reserve(std::size_t points, std::size_t runs = 0);
  /// One tube through `count` points: `radii` one per point; `colors` (RGBA8) one per point,
  /// given exactly when the builder was made withColors. Throws std::invalid_argument past
  /// 2^31 - 1 points in all.
  void addRun(const vec3* points, const float* radii, const std::uint32_t* colors, std::size_t count);
  /// addRun() for `runs` runs one after the other, run k ending before point runEnds[k] (the
  /// first starting at 0): the same set, built in slices of about `slicePoints` points on
  /// TBB's threads where the runs hold no point to drop. Throws std::invalid_argument for run
  /// ends that decrease, and as addRun().
  void addRuns(const vec3* points, const float* radii, const std::uint32_t* colors,
    const std::size_t* runEnds, std::size_t runs, std::size_t slicePoints = kSlicePoints);
  /// Slices of a few hundred thousand points: large enough that appending them costs little,
  /// small enough that a streamed piece (millions) gives every thread several.
  static constexpr std::size_t kSlicePoints = std::size_t(1) << 18;

  /// Points given so far (kept or dropped): the constructor index the next point gets.
  std::size_t pointsGiven() const { return Given; }
  /// The tube set (the builder is empty afterwards).
  std::shared_ptr<TubeSet> finish();

private:
  /// Checks what addRun() and addRuns() check.
  void checkRuns(const std::uint32_t* colors, std::size_t count) const;

  std::shared_ptr<TubeSet> Set;
  /// addRuns(): sets the slices are built in, kept with their storage from batch to batch.
  std::vector<std::unique_ptr<TubeSet>> Slices;
  std::vector<std::uint32_t> SourceIndex; ///< filled from the first dropped point on
  std::size_t Given = 0;
  bool WithColors = false;
};
} // namespace sightline
