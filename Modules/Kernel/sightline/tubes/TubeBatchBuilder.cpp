// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/tubes/TubeBatchBuilder.h"

#include <stdexcept>
#include <string>
#include <utility>

namespace sightline
{
void TubeBatchBuilder::Batch::clear()
{
  points.clear();
  radii.clear();
  colors.clear();
  runEnds.clear();
}

TubeBatchBuilder::TubeBatchBuilder(const dvec3& origin, unsigned chunkSize, bool withColors)
  : Builder(origin, chunkSize, withColors)
  , WithColors(withColors)
{
}

TubeBatchBuilder::~TubeBatchBuilder()
{
  if (Worker.valid())
    Worker.wait();
}

void TubeBatchBuilder::reserve(std::size_t points, std::size_t runs)
{
  wait();
  Builder.reserve(points, runs);
}

void TubeBatchBuilder::wait()
{
  if (Worker.valid())
    Worker.get();
}

TubeBatchBuilder::Batch TubeBatchBuilder::add(Batch&& batch)
{
  const std::size_t count = batch.points.size();
  if (batch.radii.size() != count || (WithColors ? batch.colors.size() != count : !batch.colors.empty()))
    throw std::invalid_argument("sightline::TubeBatchBuilder: a batch of " + std::to_string(count) +
      " points has " + std::to_string(batch.radii.size()) + " radii and " +
      std::to_string(batch.colors.size()) + " colours (" + (WithColors ? "one each" : "radii one each, no colours") +
      " expected)");
  for (std::size_t k = 0; k < batch.runEnds.size(); ++k)
    if (batch.runEnds[k] > count || (k > 0 && batch.runEnds[k] < batch.runEnds[k - 1]))
      throw std::invalid_argument("sightline::TubeBatchBuilder: run end " + std::to_string(k) + " (" +
        std::to_string(batch.runEnds[k]) + ") decreases or passes the batch's " + std::to_string(count) + " points");
  if ((batch.runEnds.empty() ? 0 : batch.runEnds.back()) != count)
    throw std::invalid_argument("sightline::TubeBatchBuilder: a batch's runs end before its last point");
  wait();
  Batch spare = std::move(Building);
  spare.clear();
  Building = std::move(batch);
  Given += count;
  // The worker reads only Building and writes only Builder, neither of which is touched here
  // until the next wait().
  Worker = std::async(std::launch::async,
    [this]
    {
      const Batch& runs = Building;
      Builder.addRuns(runs.points.data(), runs.radii.data(), WithColors ? runs.colors.data() : nullptr,
        runs.runEnds.data(), runs.runEnds.size());
    });
  return spare;
}

std::shared_ptr<TubeSet> TubeBatchBuilder::finish()
{
  wait();
  Building = Batch{};
  return Builder.finish();
}
} // namespace sightline
