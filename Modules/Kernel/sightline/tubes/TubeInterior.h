// SPDX-License-Identifier: BSD-3-Clause
// Hidden-link culling for dense opaque tube sets (Documentation/tubes.md, "Whole-brain
// tractograms"). A ray that starts outside a union of solids first hits the union's boundary,
// and no point of that boundary lies inside any solid. So a link whose whole solid lies inside
// other links' solids can never be the first hit of such a ray, and an opaque frame seen from
// outside may leave it out: the image, its depth and its picks are exactly the same.
//
// "Inside" is decided conservatively on a voxel grid: a voxel counts as covered when it lies in
// the open solid of one link (TubeInteriorGrid), and a link is hidden when every voxel near it
// is covered. At 10^9 links in a brain (tubes filling the volume ~190 times over) about 19 of
// 20 links are hidden; in sparse sets none are, and the set is not culled.
#pragma once

#include "sightline/core/HugePages.h"
#include "sightline/tubes/TubeSet.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace sightline
{
/// Voxels each certainly inside one tube link's solid, in bricks of 4x4x4 voxels (one 64-bit
/// word a brick), so that "every voxel in a box is covered" reads a word per 64 voxels.
/// Coordinates are the tube set's (relative to its origin). Marking is thread-safe.
class TubeInteriorGrid
{
public:
  /// A grid over `bounds` of cubic voxels of edge `voxel` (> 0).
  TubeInteriorGrid(const Box3& bounds, double voxel);

  /// Marks voxels that a point of the segment from a to b lies in, where the ball of radius
  /// voxel * sqrt(3) about that point is inside the link's solid: links whose smaller radius
  /// exceeds that (the hull of the two end spheres holds every such ball). Others mark none.
  /// Returns whether the link marked any.
  bool coverLink(const vec4& a, const vec4& b);
  /// A voxel to mark: its brick and its bit there.
  struct Mark
  {
    std::size_t brick;
    std::uint64_t bit;
  };
  /// coverLink() for the links of a run of `count` nodes (nodes[i - 1] to nodes[i]), except
  /// links whose ends both lie in full bricks (they would add at most a voxel between);
  /// `marks` is scratch space.
  void coverRun(const vec4* nodes, std::size_t count, std::vector<Mark>& marks);
  /// Whether every voxel of every brick that meets `box` is covered (false outside the grid).
  /// Call summarize() after the last coverLink() first: covers() then reads its summaries, and
  /// sees no later marks (which can only make it answer false where it might say true).
  bool covers(const Box3& box) const;
  /// covers() for boxes that lie in blocks of 4x4x4 bricks wholly covered, in a few reads
  /// whatever the box's size; false for others, and before summarize().
  bool blocksCover(const Box3& box) const;
  /// Notes which blocks of 4x4x4 bricks are wholly covered, so that covers() reads eight
  /// counts for a box inside such blocks (most boxes, deep in a dense set), and which bricks
  /// are, a bit each for the others.
  void summarize();

  double voxel() const { return Voxel; }
  std::size_t brickCount() const { return Bricks.size(); }
  std::size_t fullBrickCount() const;
  std::size_t memoryBytes() const { return Bricks.size() * sizeof(std::uint64_t); }

private:
  bool collectMarks(const vec4& a, const vec4& b, std::vector<Mark>& marks) const;
  /// Whether the brick holding `point` is full (false outside the grid).
  bool fullAt(const vec4& point) const;
  void applyMarks(const std::vector<Mark>& marks);
  /// The bricks `box` meets, lo..hi inclusive per axis; false where it leaves the grid.
  bool brickRange(const Box3& box, std::int64_t lo[3], std::int64_t hi[3]) const;
  /// Whether blocks lo..hi (inclusive) are all full, from FullBlockSums.
  bool blocksCover(const std::int64_t lo[3], const std::int64_t hi[3]) const;
  /// Bricks in tiles of 2x2x2 (a cache line), tiles in x, y, z order: a link's neighbourhood
  /// is a few cache lines.
  std::size_t brickOf(std::int64_t x, std::int64_t y, std::int64_t z) const
  {
    const std::size_t tile = std::size_t(((z >> 1) * (BrickDims[1] >> 1) + (y >> 1)) * (BrickDims[0] >> 1) + (x >> 1));
    return 8 * tile + std::size_t((x & 1) + 2 * (y & 1) + 4 * (z & 1));
  }

  dvec3 Lower;
  double Voxel;
  double Slack; ///< absolute rounding allowance of positions, voxel indices and float boxes
  double InverseVoxel;
  double MarkingReach; ///< voxel * sqrt(3) and Slack: links thinner than that mark nothing
  std::int64_t VoxelDims[3];
  std::int64_t BrickDims[3];
  /// On huge pages where Linux gives them: marking reads it at random (70 MB for a brain).
  using Table = std::vector<std::atomic<std::uint64_t>, HugePageAllocator<std::atomic<std::uint64_t>>>;
  Table Bricks;
  std::int64_t BlockDims[3] = { 0, 0, 0 };
  /// summarize(): at (x, y, z), the count of full blocks (all 64 bricks full) below x, y and
  /// z, with a zero layer before each axis: a box's count from 8 entries.
  std::vector<std::uint32_t> FullBlockSums;
  std::vector<std::uint8_t> FullBricks; ///< summarize(): a bit per full brick, a byte per tile
};

/// What outerLinks() found.
struct OuterLinkReport
{
  double fill = 0.0;          ///< tube volume / bounding-box volume, estimated from a sample
  double voxel = 0.0;         ///< grid voxel edge used (0: not attempted)
  std::size_t links = 0;      ///< links of the whole set
  std::size_t hiddenLinks = 0;
  std::size_t gridBytes = 0;
  double seconds = 0.0;        ///< all of it; of which:
  double markSeconds = 0.0;    ///< marking covered voxels
  double keepSeconds = 0.0;    ///< deciding which links are hidden
};

struct OuterLinkOptions
{
  /// Attempt only when tubes fill their bounding box this many times over (estimated from a
  /// sample of chunks): below that, the voxels a link certainly fills are too few for whole
  /// bricks to be covered, and the pass would find almost nothing hidden.
  double minimumFill = 50.0;
  /// Use the result only when at most this fraction of links is kept.
  double maximumKept = 0.5;
  /// Links per chunk of the result: its links lie in a thin shell, where short chunks' small
  /// boxes pay. At 10^9 links: 2.9-3.1 s a still frame with 2, 5.0-5.4 s with 4, for 2.5
  /// instead of 1.7 B/link of BVH.
  unsigned chunkSize = 2;
  /// Most bricks of the grid (8 bytes each): the voxel grows to stay below it.
  std::size_t maximumBricks = std::size_t(1) << 25;
  /// Called on the calling thread with the fraction done (0..1) between slices of the passes
  /// (may be empty). Its result, if any, is ignored: the pass cannot be stopped.
  std::function<void(double)> progress;
};

/// A chunked tube set holding only the links of `set` (chunked) that are not hidden by the
/// others, as described above: for every ray starting outside set.bounds() its nearest hit is
/// the nearest hit in `set`, the same link and part (the links it keeps draw exactly the same
/// solids; where a kept run begins after a hidden link, that link's end sphere is drawn too, and
/// it is hidden). Its selectionIndex() names `set`'s nodes. Null when `set` is not chunked, the
/// fill is below options.minimumFill, or more than options.maximumKept of the links are kept.
std::shared_ptr<TubeSet> outerLinks(
  const TubeSet& set, const OuterLinkOptions& options = {}, OuterLinkReport* report = nullptr);
} // namespace sightline
