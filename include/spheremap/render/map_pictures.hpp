// The pictures a map job writes beside its map (stage: render): OUTPUT/pictures/ (a Mollweide map and its
// numeric grid of every property, hemisphere figures) and OUTPUT/index.html (the viewer).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/render/globe.hpp"
#include "spheremap/render/viewer.hpp"

namespace spheremap {

/// The property of the second hemisphere figure (beside octant's): the first of electrostatics,
/// sequence_position, hydrophobicity, b_factor that `globe` has, else none (""). Never throws.
std::string featured_property(const Globe& globe);

/// Writes, in `folder` (which must exist): pictures/<property>-mollweide.png (2048 x 1024) and
/// pictures/<property>-mollweide.tsv (360 x 180 cells) for every property of `globe`,
/// pictures/octant-hemispheres.png and pictures/<featured_property>-hemispheres.png, and index.html (the
/// viewer of `viewer`). Every file atomically. Returns the files written, in that order.
/// Throws as map_figure and hemisphere_figure, and InputError naming a file that cannot be written.
std::vector<std::filesystem::path> write_map_pictures(const std::filesystem::path& folder, const Globe& globe,
                                                      const ViewerData& viewer, int threads = 0);

}  // namespace spheremap
