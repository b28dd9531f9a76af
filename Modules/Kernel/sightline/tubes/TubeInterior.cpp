// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/tubes/TubeInterior.h"

#include "sightline/tubes/TubeBatchBuilder.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace sightline
{
TubeInteriorGrid::TubeInteriorGrid(const Box3& bounds, double voxel)
  : Lower(dvec3(bounds.lower))
  , Voxel(voxel)
{
  if (!(voxel > 0.0) || !std::isfinite(voxel) || bounds.empty() || !isFinite(bounds.lower) ||
    !isFinite(bounds.upper))
    throw std::invalid_argument("sightline::TubeInteriorGrid: needs finite, non-empty bounds and a positive voxel");
  const dvec3 upper(bounds.upper);
  // Sample points and voxel indices are computed in double from float positions, and the
  // boxes covers() is given in float (rounded by up to 2^-24 of their coordinates): allow far
  // more than both.
  Slack = 1e-6 * std::max({ glm::length(Lower), glm::length(upper), voxel });
  InverseVoxel = 1.0 / voxel;
  MarkingReach = voxel * std::sqrt(3.0) + Slack;
  std::size_t bricks = 1;
  for (int axis = 0; axis < 3; ++axis)
  {
    const double cells = std::ceil((upper[axis] - Lower[axis]) / voxel) + 1.0;
    if (cells > 1e9)
      throw std::invalid_argument("sightline::TubeInteriorGrid: too many voxels along an axis");
    VoxelDims[axis] = std::int64_t(cells);
    BrickDims[axis] = ((VoxelDims[axis] + 7) / 8) * 2; // an even count: tiles of 2x2x2 bricks
    bricks *= std::size_t(BrickDims[axis]);
  }
  Bricks = Table(bricks); // zeroed: value-initialised
}

bool TubeInteriorGrid::coverLink(const vec4& a, const vec4& b)
{
  std::vector<Mark> marks;
  const bool marked = collectMarks(a, b, marks);
  applyMarks(marks);
  return marked;
}

void TubeInteriorGrid::coverRun(const vec4* nodes, std::size_t count, std::vector<Mark>& marks)
{
  // Gathered first, with their words prefetched, then set: the words of a run's links lie far
  // apart in the grid, and waiting for them one at a time was most of the time.
  // Where both ends' bricks are already full (most links, once a dense region has been
  // marked), a link adds nothing but the odd voxel of a brick between: skipped, which only
  // ever marks less. Each node's brick is read once, for both its links.
  marks.clear();
  bool previousFull = false;
  for (std::size_t i = 0; i < count; ++i)
  {
    const bool full = fullAt(nodes[i]);
    if (i > 0 && !(previousFull && full))
      collectMarks(nodes[i - 1], nodes[i], marks);
    previousFull = full;
  }
  applyMarks(marks);
}

bool TubeInteriorGrid::fullAt(const vec4& point) const
{
  const dvec3 q = (dvec3(vec3(point)) - Lower) * InverseVoxel;
  if (!(q.x >= 0.0 && q.y >= 0.0 && q.z >= 0.0 && q.x < double(VoxelDims[0]) && q.y < double(VoxelDims[1]) &&
        q.z < double(VoxelDims[2])))
    return false;
  const std::size_t brick = brickOf(std::int64_t(q.x) >> 2, std::int64_t(q.y) >> 2, std::int64_t(q.z) >> 2);
  return Bricks[brick].load(std::memory_order_relaxed) == ~std::uint64_t(0);
}

bool TubeInteriorGrid::collectMarks(const vec4& a, const vec4& b, std::vector<Mark>& marks) const
{
  // Every point of a voxel holding q lies within voxel * sqrt(3) of q; where q is on the axis,
  // the link's solid (the hull of its end spheres) holds the ball of the smaller radius about q.
  if (!(double(std::min(a.w, b.w)) > MarkingReach))
    return false;
  // In voxel units; indices by truncation (floor for the non-negative values inside the grid).
  const dvec3 from = (dvec3(vec3(a)) - Lower) * InverseVoxel;
  const dvec3 span = (dvec3(vec3(b)) - dvec3(vec3(a))) * InverseVoxel;
  // Samples a voxel apart: where tubes fill space a hundred times over, each voxel still gets
  // about 20 (half as far apart took twice as long for no more hidden links at 10^9 links).
  const int steps = std::max(1, int(std::ceil(glm::length(span))));
  const dvec3 step = span / double(steps);
  std::size_t last = ~std::size_t(0);
  for (int k = 0; k <= steps; ++k)
  {
    const dvec3 q = from + step * double(k);
    if (!(q.x >= 0.0 && q.y >= 0.0 && q.z >= 0.0 && q.x < double(VoxelDims[0]) &&
          q.y < double(VoxelDims[1]) && q.z < double(VoxelDims[2])))
      continue;
    const std::int64_t x = std::int64_t(q.x), y = std::int64_t(q.y), z = std::int64_t(q.z);
    const std::size_t voxel = std::size_t(x + VoxelDims[0] * (y + VoxelDims[1] * z));
    if (voxel == last)
      continue;
    last = voxel;
    const std::size_t brick = brickOf(x >> 2, y >> 2, z >> 2);
    __builtin_prefetch(&Bricks[brick]);
    // Written field by field into the vector: a Mark built on the stack was copied by one
    // 16-byte load of two 8-byte stores, which stalled on every mark.
    Mark& mark = marks.emplace_back();
    mark.brick = brick;
    mark.bit = std::uint64_t(1) << ((x & 3) + 4 * (y & 3) + 16 * (z & 3));
  }
  return true;
}

void TubeInteriorGrid::applyMarks(const std::vector<Mark>& marks)
{
  for (const Mark& mark : marks)
  {
    std::atomic<std::uint64_t>& word = Bricks[mark.brick];
    if (!(word.load(std::memory_order_relaxed) & mark.bit))
      word.fetch_or(mark.bit, std::memory_order_relaxed);
  }
}

void TubeInteriorGrid::summarize()
{
  // A bit per brick, a byte per tile of 2x2x2 (brickOf's order): the tests that get past the
  // blocks read 4 MB where the words are 256 MB, at random (most of the test's time at 10^9
  // links was waiting for them).
  FullBricks.assign(Bricks.size() / 8, 0);
  tbb::parallel_for(std::size_t(0), FullBricks.size(), std::size_t(1) << 14, [&](std::size_t first)
    {
      for (std::size_t tile = first; tile < std::min(FullBricks.size(), first + (std::size_t(1) << 14)); ++tile)
      {
        std::uint8_t bits = 0;
        for (std::size_t k = 0; k < 8; ++k)
          bits |= std::uint8_t(Bricks[8 * tile + k].load(std::memory_order_relaxed) == ~std::uint64_t(0)) << k;
        FullBricks[tile] = bits;
      }
    });
  for (int axis = 0; axis < 3; ++axis)
    BlockDims[axis] = (BrickDims[axis] + 3) / 4;
  const std::int64_t sx = BlockDims[0] + 1, sy = BlockDims[1] + 1, sz = BlockDims[2] + 1;
  FullBlockSums.assign(std::size_t(sx * sy * sz), 0);
  tbb::parallel_for(std::int64_t(0), BlockDims[2], [&](std::int64_t bz)
    {
      for (std::int64_t by = 0; by < BlockDims[1]; ++by)
        for (std::int64_t bx = 0; bx < BlockDims[0]; ++bx)
        {
          bool full = 4 * bx + 3 < BrickDims[0] && 4 * by + 3 < BrickDims[1] && 4 * bz + 3 < BrickDims[2];
          for (std::int64_t z = 4 * bz; full && z < 4 * bz + 4; ++z)
            for (std::int64_t y = 4 * by; full && y < 4 * by + 4; ++y)
              for (std::int64_t x = 4 * bx; full && x < 4 * bx + 4; ++x)
                full = Bricks[brickOf(x, y, z)].load(std::memory_order_relaxed) == ~std::uint64_t(0);
          FullBlockSums[std::size_t(((bz + 1) * sy + by + 1) * sx + bx + 1)] = full;
        }
    });
  // Summed along x, then y, then z: each entry counts the full blocks below and before it.
  for (int axis = 0; axis < 3; ++axis)
  {
    const std::int64_t strides[3] = { 1, sx, sx * sy };
    const std::int64_t dims[3] = { sx, sy, sz };
    const std::int64_t stride = strides[axis];
    for (std::size_t i = 0; i < FullBlockSums.size(); ++i)
      if ((std::int64_t(i) / stride) % dims[axis] != 0)
        FullBlockSums[i] += FullBlockSums[i - std::size_t(stride)];
  }
}

bool TubeInteriorGrid::blocksCover(const std::int64_t lo[3], const std::int64_t hi[3]) const
{
  // Blocks lo..hi inclusive (in block units): full when their count of full blocks is theirs.
  const std::int64_t sx = BlockDims[0] + 1, sy = BlockDims[1] + 1;
  const auto sum = [&](std::int64_t x, std::int64_t y, std::int64_t z)
  { return std::int64_t(FullBlockSums[std::size_t((z * sy + y) * sx + x)]); };
  const std::int64_t x0 = lo[0], y0 = lo[1], z0 = lo[2], x1 = hi[0] + 1, y1 = hi[1] + 1, z1 = hi[2] + 1;
  const std::int64_t full = sum(x1, y1, z1) - sum(x0, y1, z1) - sum(x1, y0, z1) - sum(x1, y1, z0) +
    sum(x0, y0, z1) + sum(x0, y1, z0) + sum(x1, y0, z0) - sum(x0, y0, z0);
  return full == (x1 - x0) * (y1 - y0) * (z1 - z0);
}

bool TubeInteriorGrid::brickRange(const Box3& box, std::int64_t lo[3], std::int64_t hi[3]) const
{
  // In brick units; indices by truncation (floor, as both are non-negative here).
  const double inverse = 0.25 / Voxel;
  for (int axis = 0; axis < 3; ++axis)
  {
    const double l = (double(box.lower[axis]) - Lower[axis] - Slack) * inverse;
    const double h = (double(box.upper[axis]) - Lower[axis] + Slack) * inverse;
    if (!(l >= 0.0) || !(h < double(BrickDims[axis])))
      return false;
    lo[axis] = std::int64_t(l);
    hi[axis] = std::int64_t(h);
  }
  return true;
}

bool TubeInteriorGrid::blocksCover(const Box3& box) const
{
  std::int64_t lo[3], hi[3];
  if (FullBlockSums.empty() || !brickRange(box, lo, hi))
    return false;
  for (int axis = 0; axis < 3; ++axis)
  {
    lo[axis] >>= 2;
    hi[axis] >>= 2;
  }
  return blocksCover(lo, hi);
}

bool TubeInteriorGrid::covers(const Box3& box) const
{
  std::int64_t lo[3], hi[3];
  if (!brickRange(box, lo, hi))
    return false;
  const bool summarized = !FullBricks.empty();
  if (summarized)
  {
    const std::int64_t blockLo[3] = { lo[0] >> 2, lo[1] >> 2, lo[2] >> 2 };
    const std::int64_t blockHi[3] = { hi[0] >> 2, hi[1] >> 2, hi[2] >> 2 };
    if (blocksCover(blockLo, blockHi))
      return true;
  }
  for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
    for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
      for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
      {
        const std::size_t brick = brickOf(x, y, z);
        if (summarized ? !(FullBricks[brick / 8] >> (brick % 8) & 1u)
                       : Bricks[brick].load(std::memory_order_relaxed) != ~std::uint64_t(0))
          return false;
      }
  return true;
}

std::size_t TubeInteriorGrid::fullBrickCount() const
{
  return std::size_t(std::count_if(Bricks.begin(), Bricks.end(),
    [](const std::atomic<std::uint64_t>& w) { return w.load(std::memory_order_relaxed) == ~std::uint64_t(0); }));
}

namespace
{
/// Kept nodes first to end, of one chunk's block: a run of the outer set starts at `first`.
struct KeptRun
{
  std::uint32_t first, end, chunk;
};
} // namespace

std::shared_ptr<TubeSet> outerLinks(const TubeSet& set, const OuterLinkOptions& options, OuterLinkReport* report)
{
  const auto started = std::chrono::steady_clock::now();
  OuterLinkReport local;
  OuterLinkReport& out = report ? *report : local;
  out = OuterLinkReport{};
  out.links = set.Links;
  if (!set.Chunked || set.Links == 0 || set.AllBounds.empty())
    return nullptr;
  const std::size_t chunks = set.Chunks.size() - 1;
  const Box3 bounds{ vec3(dvec3(set.AllBounds.lower) - set.Origin), vec3(dvec3(set.AllBounds.upper) - set.Origin) };

  // Calls visit(node, its ball, its predecessor's ball or null) for each node of a chunk.
  auto forEachLink = [&set](std::size_t chunk, auto&& visit)
  {
    const TubeSet::ChunkEntry& entry = set.Chunks[chunk];
    const std::uint32_t begin = entry.firstNode, end = set.Chunks[chunk + 1].firstNode;
    const std::uint32_t r = entry.firstRadius;
    const bool constant = set.Chunks[chunk + 1].firstRadius - r == 1;
    const TubeSet::ChunkPoints points = set.pointsOf(unsigned(chunk));
    vec4 previous(0.0f);
    bool linked = set.chunkStart(unsigned(chunk), previous);
    for (std::uint32_t node = begin; node < end; ++node)
    {
      const vec4 ball(points[node - begin], set.Radii[constant ? r : r + node - begin]);
      visit(node, ball, linked ? &previous : nullptr);
      previous = ball;
      linked = true;
    }
  };

  // The fill, and the links' smaller radii, from a sample of chunks spread over the set.
  const std::size_t stride = std::max<std::size_t>(1, chunks / 4096);
  double volume = 0.0;
  std::vector<float> radii;
  for (std::size_t c = 0; c < chunks; c += stride)
    forEachLink(c, [&](std::uint32_t, const vec4& ball, const vec4* previous)
      {
        if (!previous)
          return;
        const double r = 0.5 * (double(ball.w) + double(previous->w));
        volume += kPi * r * r * glm::length(dvec3(vec3(ball)) - dvec3(vec3(*previous)));
        radii.push_back(std::min(ball.w, previous->w));
      });
  const dvec3 extent = dvec3(bounds.upper) - dvec3(bounds.lower);
  out.fill = volume * double(stride) / std::max(extent.x * extent.y * extent.z, 1e-300);
  if (!(out.fill >= options.minimumFill) || radii.empty())
    return nullptr;

  // Voxels small enough that the median link marks the voxels along its axis.
  std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
  double voxel = 0.999 * double(radii[radii.size() / 2]) / std::sqrt(3.0);
  if (!(voxel > 0.0))
    return nullptr;
  const double cells = (extent.x / voxel + 2.0) * (extent.y / voxel + 2.0) * (extent.z / voxel + 2.0);
  if (cells / 64.0 > double(options.maximumBricks))
    voxel *= std::cbrt(cells / 64.0 / double(options.maximumBricks)) * 1.01;
  TubeInteriorGrid grid(bounds, voxel);
  out.voxel = voxel;
  out.gridBytes = grid.memoryBytes();

  // Chunks in the order of a coarse grid of buckets (32 a side) holding their first points, so
  // that the grid words a thread reads lie together: in file order, streamlines come from all
  // over the volume and every link's words were a cache miss.
  // (A grid that fits in the caches gains nothing: file order then.)
  std::vector<std::uint32_t> order(chunks);
  std::iota(order.begin(), order.end(), 0u);
  if (grid.memoryBytes() > (std::size_t(8) << 20))
  {
    const int side = 32;
    const dvec3 scale = double(side) / glm::max(extent, dvec3(1e-30));
    std::vector<std::uint16_t> bucket(chunks);
    tbb::parallel_for(std::size_t(0), chunks, std::size_t(1) << 16, [&](std::size_t c0)
      {
        for (std::size_t c = c0; c < std::min(chunks, c0 + (std::size_t(1) << 16)); ++c)
        {
          const dvec3 q = (dvec3(set.pointsOf(unsigned(c))[0]) - dvec3(bounds.lower)) * scale;
          const glm::ivec3 i = glm::clamp(glm::ivec3(q), glm::ivec3(0), glm::ivec3(side - 1));
          bucket[c] = std::uint16_t((i.z * side + i.y) * side + i.x);
        }
      });
    std::vector<std::size_t> start(side * side * side + 1, 0);
    for (std::uint16_t b : bucket)
      ++start[b + 1];
    for (std::size_t b = 1; b < start.size(); ++b)
      start[b] += start[b - 1];
    for (std::size_t c = 0; c < chunks; ++c)
      order[start[bucket[c]]++] = std::uint32_t(c);
  }

  const std::size_t block = 4096;
  const std::size_t blocks = (chunks + block - 1) / block;
  // The passes over the chunks run in slices, with progress reported between them (on this
  // thread): at 10^9 links they take a minute and more.
  const std::size_t slices = options.progress ? 20 : 1;
  auto inSlices = [&](double from, double to, const auto& body)
  {
    for (std::size_t s = 0; s < slices; ++s)
    {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(blocks * s / slices, blocks * (s + 1) / slices), body);
      if (options.progress)
        options.progress(from + (to - from) * double(s + 1) / double(slices));
    }
  };
  if (options.progress)
    options.progress(0.0);
  inSlices(0.0, 0.5,
    [&](const tbb::blocked_range<std::size_t>& range)
    {
      std::vector<vec4> nodes;
      std::vector<TubeInteriorGrid::Mark> marks;
      const std::size_t end = std::min(chunks, range.end() * block);
      for (std::size_t o = range.begin() * block; o < end; ++o)
      {
        // Chunks come in spatial order, from all over the set's memory: their table entries
        // are fetched 16 chunks ahead, their positions and radii 8 ahead.
        if (o + 16 < end)
        {
          const std::size_t ahead = order[o + 16];
          __builtin_prefetch(&set.Chunks[ahead]);
          __builtin_prefetch(&set.Chunks[ahead > 0 ? ahead - 1 : 0]);
        }
        if (o + 8 < end)
          set.prefetchChunk(order[o + 8]);
        const std::size_t c = order[o];
        nodes.clear();
        forEachLink(c, [&](std::uint32_t, const vec4& ball, const vec4* previous)
          {
            if (previous && nodes.empty())
              nodes.push_back(*previous);
            nodes.push_back(ball);
          });
        grid.coverRun(nodes.data(), nodes.size(), marks);
      }
    });

  grid.summarize();
  const auto marked = std::chrono::steady_clock::now();
  out.markSeconds = std::chrono::duration<double>(marked - started).count();

  // A node (its end sphere and its link from its predecessor) is kept unless every brick its
  // box meets is covered; the hull of the two spheres lies in their boxes. In file order: the
  // test reads mostly the small block summary, and the chunks then come from memory in order.
  order = {};
  std::vector<std::vector<KeptRun>> kept(blocks);
  inSlices(0.5, 0.9,
    [&](const tbb::blocked_range<std::size_t>& range)
    {
      for (std::size_t b = range.begin(); b < range.end(); ++b)
      {
        std::vector<KeptRun>& runs = kept[b];
        std::vector<Box3> boxes;
        for (std::size_t c = b * block; c < std::min(chunks, (b + 1) * block); ++c)
        {
          // The chunk's capsule holds all its links: where its box lies in full blocks, so does
          // each link's, and the chunk is hidden without decoding its points (most chunks, deep
          // in a dense set). Blocks only: its box meets thousands of bricks.
          const TubeSet::ChunkPoints points = set.pointsOf(unsigned(c));
          const float reach = set.Chunks[c].reach;
          Box3 capsule = sphereBox(vec4(points[0], reach));
          capsule.extend(sphereBox(vec4(points[set.Chunks[c + 1].firstNode - set.Chunks[c].firstNode - 1], reach)));
          if (grid.blocksCover(capsule))
            continue;
          // The links' boxes; then four links at a time by their joint box against the blocks,
          // and the links of a group that does not pass one by one (3*10^8 links on a harness,
          // three rounds: 5.9-6.8 s a test pass against 7.1-8.2 link by link; groups of 8
          // varied more).
          const std::uint32_t firstNode = set.Chunks[c].firstNode;
          boxes.resize(std::max<std::size_t>(boxes.size(), set.Chunks[c + 1].firstNode - firstNode));
          std::uint32_t count = 0;
          forEachLink(c, [&](std::uint32_t, const vec4& ball, const vec4* previous)
            {
              Box3 box = sphereBox(ball);
              if (previous)
                box.extend(sphereBox(*previous));
              boxes[count++] = box;
            });
          for (std::uint32_t g = 0; g < count; g += 4)
          {
            const std::uint32_t end = std::min(count, g + 4);
            Box3 group = boxes[g];
            for (std::uint32_t k = g + 1; k < end; ++k)
              group.extend(boxes[k]);
            if (grid.blocksCover(group))
              continue;
            for (std::uint32_t k = g; k < end; ++k)
            {
              const std::uint32_t node = firstNode + k;
              if (grid.covers(boxes[k]))
                continue;
              if (!runs.empty() && runs.back().end == node && node != set.Chunks[c].firstNode)
                ++runs.back().end;
              else
                runs.push_back(KeptRun{ node, node + 1, std::uint32_t(c) });
            }
          }
        }
      }
    });
  std::size_t keptNodes = 0, runCount = 0;
  for (const auto& runs : kept)
  {
    runCount += runs.size();
    for (const KeptRun& run : runs)
      keptNodes += run.end - run.first;
  }
  out.hiddenLinks = set.NodeCount - keptNodes; // nodes stand for links (and runs' first spheres)
  out.keepSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - marked).count();
  if (double(keptNodes) > options.maximumKept * double(set.NodeCount))
  {
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return nullptr;
  }

  // Each kept run goes on from its first node's predecessor (drawn as a start sphere: hidden).
  // Gathered here in batches while the batch before is built, in file order (the marking's
  // spatial order made no difference to a still frame at 10^9 links: 4.35 against 4.26 s).
  const bool colored = !set.Colors.empty();
  TubeBatchBuilder builder(set.Origin, options.chunkSize, colored);
  builder.reserve(keptNodes + runCount, runCount);
  std::vector<std::uint32_t> selected;
  selected.reserve(keptNodes + runCount);
  TubeBatchBuilder::Batch batch;
  for (const auto& runs : kept)
    for (const KeptRun& run : runs)
    {
      const TubeSet::ChunkEntry& entry = set.Chunks[run.chunk];
      const std::uint32_t r = entry.firstRadius;
      const bool constant = set.Chunks[run.chunk + 1].firstRadius - r == 1;
      const TubeSet::ChunkPoints chunkPoints = set.pointsOf(run.chunk);
      auto add = [&](std::uint32_t node, const vec4& ball)
      {
        batch.points.push_back(vec3(ball));
        batch.radii.push_back(ball.w);
        if (colored)
          batch.colors.push_back(set.Colors[node]);
        selected.push_back(node);
      };
      auto ballOf = [&](std::uint32_t node)
      {
        return vec4(chunkPoints[node - entry.firstNode], set.Radii[constant ? r : r + node - entry.firstNode]);
      };
      if (run.first == entry.firstNode)
      {
        vec4 start;
        if (set.chunkStart(run.chunk, start))
          add(std::uint32_t(entry.predecessor), start);
      }
      else
        add(run.first - 1, ballOf(run.first - 1));
      for (std::uint32_t node = run.first; node < run.end; ++node)
        add(node, ballOf(node));
      batch.endRun();
      if (batch.points.size() >= (std::size_t(1) << 20))
        batch = builder.add(std::move(batch));
    }
  builder.add(std::move(batch));
  std::shared_ptr<TubeSet> outer = builder.finish();
  outer->SelectedNode = std::move(selected);
  outer->SelectionTotal = set.selectionCount();
  outer->material = set.material;
  if (options.progress)
    options.progress(1.0);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return outer;
}
} // namespace sightline
