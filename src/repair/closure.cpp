#include "spheremap/repair/closure.hpp"

namespace spheremap {

const char* to_string(ClosureKind kind) { return kind == ClosureKind::kFill ? "fill" : "cut"; }

}  // namespace spheremap
