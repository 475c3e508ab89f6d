// A potential map's values at points: trilinear interpolation of an OpenDX grid (--potential-map, --apbs).
#pragma once

#include <string>
#include <vector>

#include "spheremap/io/opendx.hpp"

namespace spheremap {

/// The trilinear interpolation of the grid at every point (exact for a field linear in x, y and z).
/// `name` names the map in messages. Throws InputError when any point lies outside the grid's box, saying
/// how many points, how far outside the farthest one is (Å) and the fix (a larger grid).
std::vector<double> interpolate_dx(const DxGrid& grid, const std::vector<Vec3>& points, const std::string& name);

}  // namespace spheremap
