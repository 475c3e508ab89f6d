// The colour scales live in the core (properties/colour_scale.hpp), so that the PLY and glTF outputs of a map
// colour their vertices by the same rule as the pictures; this header keeps render's include working.
#pragma once

#include "spheremap/properties/colour_scale.hpp"
