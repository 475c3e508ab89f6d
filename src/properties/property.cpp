#include "spheremap/properties/property.hpp"

namespace spheremap {

std::string_view to_string(ScaleKind kind) {
  switch (kind) {
    case ScaleKind::sequential: return "sequential";
    case ScaleKind::diverging: return "diverging";
    case ScaleKind::categorical: return "categorical";
    case ScaleKind::spectrum: return "spectrum";
  }
  return "sequential";
}

}  // namespace spheremap
