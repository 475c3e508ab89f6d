#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "../../src/util/parallel.hpp"

namespace spheremap {
namespace {

TEST(Parallel, EveryChunkRunsOnceOnAValidWorker) {
  for (const int threads : {1, 2, 5}) {
    constexpr std::int64_t kChunks = 1000;
    std::vector<std::atomic<int>> runs(kChunks);
    std::atomic<bool> bad_worker{false};
    detail::parallel_chunks(kChunks, threads, [&](std::int64_t chunk, int worker) {
      ++runs[static_cast<std::size_t>(chunk)];
      if (worker < 0 || worker >= threads) bad_worker = true;
    });
    for (const auto& r : runs) ASSERT_EQ(r.load(), 1) << threads << " threads";
    EXPECT_FALSE(bad_worker);
  }
}

TEST(Parallel, NoChunksRunsNothing) {
  int runs = 0;
  detail::parallel_chunks(0, 4, [&](std::int64_t, int) { ++runs; });
  EXPECT_EQ(runs, 0);
}

TEST(Parallel, RangesCoverTheItemsInConsecutivePieces) {
  std::vector<std::atomic<int>> covered(103);
  std::atomic<int> longest{0};
  detail::parallel_ranges(103, 10, 3, [&](std::int64_t first, std::int64_t last) {
    ASSERT_LT(first, last);
    ASSERT_EQ(first % 10, 0);
    longest = std::max<int>(longest, static_cast<int>(last - first));
    for (auto i = first; i < last; ++i) ++covered[static_cast<std::size_t>(i)];
  });
  for (const auto& c : covered) EXPECT_EQ(c.load(), 1);
  EXPECT_EQ(longest.load(), 10);
}

TEST(Parallel, TheFirstExceptionIsRethrownAfterEveryThreadStopped) {
  std::atomic<int> started{0};
  EXPECT_THROW(detail::parallel_chunks(100, 4,
                                       [&](std::int64_t chunk, int) {
                                         ++started;
                                         if (chunk == 7) throw std::runtime_error("chunk 7");
                                       }),
               std::runtime_error);
  EXPECT_GE(started.load(), 8);
}

TEST(Parallel, ThreadCountDefaultsToTheHardware) {
  EXPECT_GE(detail::surface_threads(0), 1);
  EXPECT_LE(detail::surface_threads(0), 64);
  EXPECT_EQ(detail::surface_threads(3), 3);
}

TEST(Parallel, ReserveMappedReservesAndKeepsTheValuesWritable) {
  std::vector<double> values;
  detail::reserve_mapped(values, 1 << 20, 2);  // 8 MB: large enough for the threaded path
  EXPECT_GE(values.capacity(), std::size_t{1} << 20);
  EXPECT_TRUE(values.empty());
  values.assign(std::size_t{1} << 20, 1.5);
  EXPECT_EQ(values.back(), 1.5);
}

}  // namespace
}  // namespace spheremap
