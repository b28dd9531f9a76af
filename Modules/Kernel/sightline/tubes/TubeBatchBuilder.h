// SPDX-License-Identifier: BSD-3-Clause
// Building a chunked tube set from a streamed input (Documentation/tubes.md, "Whole-brain
// tractograms"): the caller reads and converts one piece while the piece before is built on a
// thread of its own. At 10^9 links both halves take most of a minute each; overlapped, the
// first image waits for the longer half only, and that half (storing) spreads each batch over
// TBB's threads in slices (TubeRunBuilder::addRuns), so the two halves share the cores.
#pragma once

#include "sightline/tubes/TubeSet.h"

#include <cstddef>
#include <cstdint>
#include <future>
#include <memory>
#include <vector>

namespace sightline
{
/// TubeRunBuilder fed in batches of runs, each built on a worker thread while the caller fills
/// the next. The set is the one that TubeRunBuilder gives for the same runs in the same order.
class TubeBatchBuilder
{
public:
  /// Runs one after the other: run k is points [runEnds[k - 1], runEnds[k]) (from 0 for k = 0).
  struct Batch
  {
    std::vector<vec3> points;          ///< relative to the builder's origin
    std::vector<float> radii;          ///< one per point
    std::vector<std::uint32_t> colors; ///< RGBA8, one per point where the builder has colours
    std::vector<std::size_t> runEnds;
    /// Ends the run of the points appended since the last call (an empty run adds nothing).
    void endRun() { runEnds.push_back(points.size()); }
    /// Empty, keeping the storage.
    void clear();
  };

  /// As TubeRunBuilder's.
  explicit TubeBatchBuilder(const dvec3& origin = dvec3(0.0),
    unsigned chunkSize = TubeLayout::kDefaultChunkSize, bool withColors = false);
  /// Waits for the batch being built (its errors are dropped: finish() reports them).
  ~TubeBatchBuilder();
  TubeBatchBuilder(const TubeBatchBuilder&) = delete;
  TubeBatchBuilder& operator=(const TubeBatchBuilder&) = delete;

  /// As TubeRunBuilder::reserve(); before the first batch.
  void reserve(std::size_t points, std::size_t runs = 0);
  /// Builds `batch` after the batches before it, on the worker thread, and returns an empty
  /// batch to fill next: the storage of one already built, so that its pages are reused.
  /// Throws std::invalid_argument for a malformed batch (sizes that disagree, run ends that
  /// decrease or pass the points) before handing it over, and rethrows what building an earlier
  /// batch threw (TubeRunBuilder::addRun's errors).
  Batch add(Batch&& batch);
  /// Points handed over so far (kept or dropped): the constructor index the next batch's first
  /// point gets.
  std::size_t pointsGiven() const { return Given; }
  /// Waits for the last batch and returns the tube set (rethrowing what building threw).
  std::shared_ptr<TubeSet> finish();

private:
  /// Waits for the batch being built; rethrows what it threw.
  void wait();

  TubeRunBuilder Builder;
  bool WithColors;
  Batch Building; ///< the batch the worker reads; not touched here until wait()
  std::future<void> Worker;
  std::size_t Given = 0;
};
} // namespace sightline
