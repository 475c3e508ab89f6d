// Wall-clock seconds of a named stage, as the report's timings_seconds lists them.
#pragma once

#include <string>

namespace spheremap {

struct StageTime {
  std::string stage;  // e.g. "poles", "solve", "field", "contour"
  double seconds;
};

}  // namespace spheremap
