// A fixture for scripts/check-layers.py, never compiled: sphere/ may not include metrics/, so the checker
// must reject this tree (CTest Layout.CheckerRejectsAnUpwardInclude).
#pragma once
#include "spheremap/metrics/distortion.hpp"
