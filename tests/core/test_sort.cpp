// pfxParallelSort: order, stability and buffer checks for both record sizes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include "pfx/base_level/task/pfx_tbb_task_manager.h"
#include "pfx/low_level/sort/pfx_parallel_sort.h"

namespace pfx {
namespace {

// Keys with few distinct values in some bytes and random ones in others, so that both the
// skipped and the performed passes are exercised; data[0] numbers the records so that the
// comparison with std::stable_sort also checks stability.
template <class Record>
std::vector<Record> randomRecords(std::size_t n, std::mt19937_64& rng, PfxUInt64 keyMask) {
  std::vector<Record> records(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::memset(&records[i], 0, sizeof(Record));
    records[i].key = rng() & keyMask;
    records[i].data[0] = static_cast<PfxUInt32>(i);
    records[i].data[1] = static_cast<PfxUInt32>(rng());
  }
  return records;
}

template <class Record>
void expectSameRecords(const std::vector<Record>& a, const std::vector<Record>& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(Record)));
}

template <class Record>
void checkAgainstStableSort(PfxUInt64 keyMask, std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<Record> records = randomRecords<Record>(n, rng, keyMask);
  std::vector<Record> expected = records;
  std::stable_sort(expected.begin(), expected.end(),
                   [](const Record& x, const Record& y) { return x.key < y.key; });
  std::vector<Record> work = std::vector<Record>(n);
  ASSERT_EQ(PFX_OK, pfxParallelSort(records.data(), static_cast<PfxUInt32>(n), work.data(),
                                    static_cast<PfxUInt32>(n * sizeof(Record))));
  expectSameRecords(records, expected);
}

template <class Record>
class SortTest : public ::testing::Test {};
using RecordTypes = ::testing::Types<PfxSortData16, PfxSortData32>;
TYPED_TEST_SUITE(SortTest, RecordTypes);

TYPED_TEST(SortTest, RandomFullKeysMatchStableSort) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    checkAgainstStableSort<TypeParam>(~PfxUInt64(0), 1000 + seed * 37, seed);
  }
}

// One differing byte (one pass: the result must come back from the work buffer), two
// (bytes 0 and 7), three (an odd count again, with skipped bytes between).
TYPED_TEST(SortTest, SparseKeysMatchStableSort) {
  checkAgainstStableSort<TypeParam>(0x00ff000000000000ull, 777, 11);
  checkAgainstStableSort<TypeParam>(0xff000000000000ffull, 777, 12);
  checkAgainstStableSort<TypeParam>(0xff00ff00000000ffull, 777, 13);
}

TYPED_TEST(SortTest, ManyEqualKeysKeepInputOrder) {
  // Keys 0..3 only: every record shares its key with about a quarter of the others.
  checkAgainstStableSort<TypeParam>(0x3, 2000, 21);
  checkAgainstStableSort<TypeParam>(0x3000000000000000ull, 2000, 22);
}

// Short arrays (a robot's proxies and pairs) take an insertion sort; either side of where
// the radix passes take over, with few distinct keys so that stability is checked too.
TYPED_TEST(SortTest, ShortArraysMatchStableSort) {
  for (std::size_t n = 2; n <= 40; ++n) {
    checkAgainstStableSort<TypeParam>(~PfxUInt64(0), n, static_cast<unsigned>(100 + n));
    checkAgainstStableSort<TypeParam>(0x3000000000000003ull, n, static_cast<unsigned>(200 + n));
  }
}

TYPED_TEST(SortTest, AllKeysEqualLeavesArrayUnchanged) {
  std::mt19937_64 rng(5);
  std::vector<TypeParam> records = randomRecords<TypeParam>(300, rng, 0);
  for (auto& r : records) r.key = 0x0123456789abcdefull;
  const std::vector<TypeParam> before = records;
  std::vector<TypeParam> work = std::vector<TypeParam>(records.size());
  ASSERT_EQ(PFX_OK, pfxParallelSort(records.data(), 300, work.data(),
                                    static_cast<PfxUInt32>(300 * sizeof(TypeParam))));
  expectSameRecords(records, before);
}

TYPED_TEST(SortTest, KnownSmallArray) {
  // Keys 5, 1, 5, 0 with payloads 0..3: ascending and stable gives 0(3), 1(1), 5(0), 5(2).
  std::vector<TypeParam> records(4);
  const PfxUInt64 keys[4] = {5, 1, 5, 0};
  for (PfxUInt32 i = 0; i < 4; ++i) {
    std::memset(&records[i], 0, sizeof(TypeParam));
    records[i].key = keys[i];
    records[i].data[0] = i;
  }
  std::vector<TypeParam> work(4);
  ASSERT_EQ(PFX_OK, pfxParallelSort(records.data(), 4, work.data(),
                                    static_cast<PfxUInt32>(4 * sizeof(TypeParam))));
  const PfxUInt64 expectedKeys[4] = {0, 1, 5, 5};
  const PfxUInt32 expectedPayload[4] = {3, 1, 0, 2};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(expectedKeys[i], records[i].key);
    EXPECT_EQ(expectedPayload[i], records[i].data[0]);
  }
}

TYPED_TEST(SortTest, EmptyAndSingleAreAccepted) {
  std::vector<TypeParam> work(1);
  EXPECT_EQ(PFX_OK, pfxParallelSort(static_cast<TypeParam*>(nullptr), 0, work.data(), 0));
  std::vector<TypeParam> one(1);
  std::memset(one.data(), 0, sizeof(TypeParam));
  one[0].key = 42;
  one[0].data[0] = 7;
  EXPECT_EQ(PFX_OK, pfxParallelSort(one.data(), 1, work.data(), sizeof(TypeParam)));
  EXPECT_EQ(42u, one[0].key);
  EXPECT_EQ(7u, one[0].data[0]);
}

TYPED_TEST(SortTest, BadBuffersAreRejectedAndDataUntouched) {
  std::mt19937_64 rng(9);
  std::vector<TypeParam> records = randomRecords<TypeParam>(64, rng, ~PfxUInt64(0));
  const std::vector<TypeParam> before = records;
  std::vector<TypeParam> work(65);
  const PfxUInt32 bytes = 64 * sizeof(TypeParam);

  EXPECT_EQ(PFX_ERR_NULL_POINTER,
            pfxParallelSort(static_cast<TypeParam*>(nullptr), 64, work.data(), bytes));
  EXPECT_EQ(PFX_ERR_OUT_OF_BUFFER, pfxParallelSort(records.data(), 64, nullptr, bytes));
  void* misaligned = reinterpret_cast<char*>(work.data()) + 8;
  EXPECT_EQ(PFX_ERR_INVALID_ALIGNMENT, pfxParallelSort(records.data(), 64, misaligned, bytes));
  EXPECT_EQ(PFX_ERR_OUT_OF_BUFFER, pfxParallelSort(records.data(), 64, work.data(), bytes - 1));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE, pfxParallelSort(records.data(), 64, records.data() + 32, bytes));
  expectSameRecords(records, before);
}

// Large arrays are sorted in chunks on several threads: the result must be the stable
// order all the same, for every key pattern (one pass, several, none).
TYPED_TEST(SortTest, TaskManagerGivesTheStableOrder) {
  for (PfxUInt32 threads : {2u, 4u}) {
    PfxTbbTaskManager manager;
    ASSERT_EQ(PFX_OK, manager.initialize(threads));
    unsigned seed = 100;
    for (PfxUInt64 keyMask : {~PfxUInt64(0), PfxUInt64(0xffff), PfxUInt64(0x00ff0000000000ffull),
                              PfxUInt64(0x3), PfxUInt64(0)}) {
      for (std::size_t n : {std::size_t(9000), std::size_t(100003)}) {
        std::mt19937_64 rng(++seed);
        std::vector<TypeParam> records = randomRecords<TypeParam>(n, rng, keyMask);
        std::vector<TypeParam> expected = records;
        std::stable_sort(expected.begin(), expected.end(),
                         [](const TypeParam& x, const TypeParam& y) { return x.key < y.key; });
        std::vector<TypeParam> work(n);
        ASSERT_EQ(PFX_OK, pfxParallelSort(records.data(), static_cast<PfxUInt32>(n), work.data(),
                                          static_cast<PfxUInt32>(n * sizeof(TypeParam)), &manager));
        expectSameRecords(records, expected);
      }
    }
  }
}

}  // namespace
}  // namespace pfx
