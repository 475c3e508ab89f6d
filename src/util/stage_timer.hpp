// Private to the library (util/): the one stage timer of every layer. Wall-clock seconds of consecutive
// stages, kept for the report's timings_seconds. Built with -DSPHEREMAP_STAGE_TIMES, every lap is also
// printed on stderr with the process's CPU time, to profile steps the report does not list (the surface
// field's, for instance).
#pragma once

#include <chrono>
#include <string>
#include <string_view>
#include <vector>

#include "spheremap/timing.hpp"

#ifdef SPHEREMAP_STAGE_TIMES
#include <cstdio>
#include <ctime>
#endif

namespace spheremap::detail {

class StageTimer {
 public:
  /// Starts the first stage. Laps are appended to `laps` when it is not null; `scope` names them on
  /// stderr when traced (e.g. "surface": "surface stage contour 0.412 s wall 0.820 s CPU").
  explicit StageTimer(const char* scope, std::vector<StageTime>* laps = nullptr) : scope_(scope), laps_(laps) {}

  /// Ends the current stage under the name `stage` and starts the next; returns the stage's seconds.
  double lap(std::string_view stage) {
    const auto now = Clock::now();
    const double seconds = std::chrono::duration<double>(now - start_).count();
    if (laps_) laps_->push_back({std::string(stage), seconds});
    start_ = now;
#ifdef SPHEREMAP_STAGE_TIMES
    const double cpu = cpu_seconds();
    std::fprintf(stderr, "%s stage %-12.*s %.3f s wall %.3f s CPU\n", scope_, static_cast<int>(stage.size()),
                 stage.data(), seconds, cpu - cpu_);
    cpu_ = cpu;
#endif
    return seconds;
  }

  /// Seconds since the current stage began.
  [[nodiscard]] double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  using Clock = std::chrono::steady_clock;
  [[maybe_unused]] const char* scope_;
  std::vector<StageTime>* laps_;
  Clock::time_point start_ = Clock::now();
#ifdef SPHEREMAP_STAGE_TIMES
  static double cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
  double cpu_ = cpu_seconds();
#endif
};

}  // namespace spheremap::detail
