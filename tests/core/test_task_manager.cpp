// The task manager: every index of a parallel-for runs exactly once, in ranges of at least
// the grain size, also nested and with any number of threads; bad input runs nothing.
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <vector>

#include "pfx/base_level/task/pfx_tbb_task_manager.h"

namespace pfx {
namespace {

struct Coverage {
  explicit Coverage(PfxUInt32 n) : hits(new std::atomic<int>[n]), count(n) {
    for (PfxUInt32 i = 0; i < n; ++i) hits[i] = 0;
  }
  std::unique_ptr<std::atomic<int>[]> hits;
  PfxUInt32 count;
  std::atomic<int> calls{0};
  std::atomic<int> shortRanges{0};
  std::atomic<int> badRanges{0};
};

struct CoverageTask {
  Coverage* coverage;
  PfxUInt32 grainSize;
};

void coverRange(void* context, PfxUInt32 begin, PfxUInt32 end) {
  const CoverageTask& task = *static_cast<const CoverageTask*>(context);
  Coverage& c = *task.coverage;
  ++c.calls;
  if (begin >= end || end > c.count) {
    ++c.badRanges;
    return;
  }
  if (end - begin < task.grainSize) ++c.shortRanges;
  for (PfxUInt32 i = begin; i < end; ++i) ++c.hits[i];
}

void expectEachOnce(const Coverage& c) {
  for (PfxUInt32 i = 0; i < c.count; ++i) ASSERT_EQ(c.hits[i], 1) << "index " << i;
}

TEST(TaskManager, EveryIndexExactlyOnceInRangesOfTheGrainSize) {
  for (PfxUInt32 threads : {1u, 2u, 4u, 7u}) {
    PfxTbbTaskManager manager;
    ASSERT_EQ(manager.initialize(threads), PFX_OK);
    EXPECT_EQ(manager.getNumThreads(), threads);
    for (PfxUInt32 count : {1u, 2u, 63u, 1000u, 100003u}) {
      for (PfxUInt32 grain : {1u, 3u, 64u, 5000u}) {
        Coverage coverage(count);
        CoverageTask task{&coverage, grain};
        ASSERT_EQ(manager.parallelFor(count, grain, coverRange, &task), PFX_OK);
        expectEachOnce(coverage);
        EXPECT_EQ(coverage.badRanges, 0);
        // Every range holds a grain, unless the whole count is smaller than one.
        if (count >= grain) {
          EXPECT_EQ(coverage.shortRanges, 0) << count << " / " << grain;
        } else {
          EXPECT_EQ(coverage.calls, 1);
        }
        EXPECT_LE(coverage.calls, int(count / grain > 0 ? count / grain : 1));
      }
    }
  }
}

TEST(TaskManager, EmptyRangeRunsNothing) {
  PfxTbbTaskManager manager;
  ASSERT_EQ(manager.initialize(2), PFX_OK);
  Coverage coverage(1);
  CoverageTask task{&coverage, 1};
  EXPECT_EQ(manager.parallelFor(0, 1, coverRange, &task), PFX_OK);
  EXPECT_EQ(manager.parallelFor(0, 1, nullptr, nullptr), PFX_OK);
  EXPECT_EQ(coverage.calls, 0);
  int calls = 0;
  EXPECT_EQ(pfxParallelFor(&manager, 0, 1, [&](PfxUInt32, PfxUInt32) { ++calls; }), PFX_OK);
  EXPECT_EQ(calls, 0);
}

TEST(TaskManager, NestedLoopsShareTheThreads) {
  PfxTbbTaskManager manager;
  ASSERT_EQ(manager.initialize(4), PFX_OK);
  constexpr PfxUInt32 kOuter = 37, kInner = 1001;
  Coverage coverage(kOuter * kInner);
  ASSERT_EQ(pfxParallelFor(&manager, kOuter, 1,
                           [&](PfxUInt32 begin, PfxUInt32 end) {
                             for (PfxUInt32 i = begin; i < end; ++i) {
                               pfxParallelFor(&manager, kInner, 16, [&](PfxUInt32 b, PfxUInt32 e) {
                                 for (PfxUInt32 j = b; j < e; ++j) ++coverage.hits[i * kInner + j];
                               });
                             }
                           }),
            PFX_OK);
  expectEachOnce(coverage);
}

TEST(TaskManager, WithoutManagerTheCallingThreadRunsOneRange) {
  std::vector<std::pair<PfxUInt32, PfxUInt32>> ranges;
  const auto record = [&](PfxUInt32 begin, PfxUInt32 end) { ranges.emplace_back(begin, end); };
  ASSERT_EQ(pfxParallelFor(nullptr, 500, 7, record), PFX_OK);
  PfxTbbTaskManager single;  // one thread until initialized otherwise
  EXPECT_EQ(single.getNumThreads(), 1u);
  ASSERT_EQ(pfxParallelFor(&single, 300, 7, record), PFX_OK);
  ASSERT_EQ(ranges.size(), 2u);
  EXPECT_EQ(ranges[0], std::make_pair(PfxUInt32(0), PfxUInt32(500)));
  EXPECT_EQ(ranges[1], std::make_pair(PfxUInt32(0), PfxUInt32(300)));
}

TEST(TaskManager, BadInputRunsNothing) {
  PfxTbbTaskManager manager;
  ASSERT_EQ(manager.initialize(2), PFX_OK);
  Coverage coverage(100);
  CoverageTask task{&coverage, 1};
  EXPECT_EQ(manager.parallelFor(100, 0, coverRange, &task), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(manager.parallelFor(100, 4, nullptr, &task), PFX_ERR_NULL_POINTER);
  int calls = 0;
  EXPECT_EQ(pfxParallelFor(&manager, 100, 0, [&](PfxUInt32, PfxUInt32) { ++calls; }),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxParallelFor(nullptr, 100, 0, [&](PfxUInt32, PfxUInt32) { ++calls; }),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(coverage.calls, 0);
  EXPECT_EQ(calls, 0);

  // Too many threads: refused, and the manager keeps its threads.
  EXPECT_EQ(manager.initialize(PFX_MAX_THREADS + 1), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(manager.getNumThreads(), 2u);
  // Zero: as many as the process may use, at least one.
  ASSERT_EQ(manager.initialize(0), PFX_OK);
  EXPECT_GE(manager.getNumThreads(), 1u);
  EXPECT_LE(manager.getNumThreads(), PFX_MAX_THREADS);
}

TEST(TaskManager, ChunksCoverTheItemsInOrderAndDifferByOne) {
  PfxTbbTaskManager four;
  ASSERT_EQ(four.initialize(4), PFX_OK);
  EXPECT_EQ(pfxNumChunks(nullptr, 100000, 10, 64), 1u);
  EXPECT_EQ(pfxNumChunks(&four, 100000, 10, 64), 16u);
  EXPECT_EQ(pfxNumChunks(&four, 100000, 10, 8), 8u);
  EXPECT_EQ(pfxNumChunks(&four, 35, 10, 64), 3u);
  EXPECT_EQ(pfxNumChunks(&four, 5, 10, 64), 1u);
  for (PfxUInt32 count : {0u, 1u, 17u, 1000u, 4000000000u}) {
    for (PfxUInt32 chunks : {1u, 3u, 16u, 64u}) {
      EXPECT_EQ(pfxChunkBegin(count, chunks, 0), 0u);
      EXPECT_EQ(pfxChunkBegin(count, chunks, chunks), count);
      for (PfxUInt32 c = 0; c < chunks; ++c) {
        const PfxUInt32 size = pfxChunkBegin(count, chunks, c + 1) - pfxChunkBegin(count, chunks, c);
        EXPECT_LE(size, count / chunks + 1);
        EXPECT_GE(size, count / chunks);
      }
    }
  }
}

}  // namespace
}  // namespace pfx
