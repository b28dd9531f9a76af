// SPDX-License-Identifier: BSD-3-Clause
// HugePageAllocator: large blocks start on a 2 MiB boundary (where a huge page can back them),
// small ones come from the ordinary allocator, and vectors using it behave as std::vector does
// through growth, copies and shrinking.
#include "sightline/core/HugePages.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <vector>

using namespace sightline;

TEST(HugePages, LargeBlocksAreHugePageAlignedAndVectorsBehave)
{
  using Table = std::vector<std::uint32_t, HugePageAllocator<std::uint32_t>>;
  Table table;
  for (std::uint32_t i = 0; i < 3u << 20; ++i) // grows through small and large blocks: 12 MiB
    table.push_back(i * 7u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(table.data()) % HugePageAllocator<int>::kHugePage, 0u);
  Table copy = table;
  EXPECT_EQ(copy, table);
  table.resize(1000);
  table.shrink_to_fit(); // back to a small block
  ASSERT_EQ(table.size(), 1000u);
  for (std::uint32_t i = 0; i < 1000; ++i)
    ASSERT_EQ(table[i], i * 7u);
  EXPECT_EQ(std::accumulate(copy.begin(), copy.end(), std::uint64_t(0)),
    std::uint64_t(7) * ((std::uint64_t(3) << 20) * ((std::uint64_t(3) << 20) - 1) / 2));
  EXPECT_THROW(HugePageAllocator<double>().allocate(std::size_t(-1) / 4), std::bad_array_new_length);
}
