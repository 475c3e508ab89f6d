// Private to src/pipeline: wall-clock seconds for the stage timings of the report.
#pragma once

#include <chrono>

namespace spheremap::pipeline_detail {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace spheremap::pipeline_detail
