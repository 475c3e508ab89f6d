#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <vector>

#include "../../src/util/stage_timer.hpp"

namespace spheremap {
namespace {

TEST(StageTimer, LapsAreRecordedInOrderWithTheSecondsTheyReturn) {
  std::vector<StageTime> laps;
  detail::StageTimer timer("test", &laps);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double first = timer.lap("first");
  const double second = timer.lap("second");
  ASSERT_EQ(laps.size(), 2u);
  EXPECT_EQ(laps[0].stage, "first");
  EXPECT_EQ(laps[1].stage, "second");
  EXPECT_EQ(laps[0].seconds, first);
  EXPECT_EQ(laps[1].seconds, second);
  EXPECT_GE(first, 0.02);  // a sleep lasts at least as long as asked, on a steady clock
  EXPECT_GE(second, 0.0);
}

TEST(StageTimer, ALapStartsTheNextStage) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  detail::StageTimer timer("test");
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double first = timer.lap("first");
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double second = timer.lap("second");
  const double total = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_GE(first, 0.02);
  EXPECT_GE(second, 0.02);
  EXPECT_LE(first + second, total);  // a stage that went on counting would count the first one twice
  EXPECT_LE(timer.seconds(), total);
}

TEST(StageTimer, WithoutLapsOnlyReturnsTheSeconds) {
  detail::StageTimer timer("test");
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_GE(timer.lap("alone"), 0.005);
}

}  // namespace
}  // namespace spheremap
