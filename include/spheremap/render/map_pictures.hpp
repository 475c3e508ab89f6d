// The pictures a map job writes beside its map (stage: render): OUTPUT/pictures/ (Mollweide maps and their
// numeric grids of a few properties, hemisphere figures) and OUTPUT/index.html (the viewer). `spheremap render`
// draws any other property, projection or format on request.
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

/// The properties whose Mollweide maps write_map_pictures draws, when the globe has them: electrostatics,
/// hydrophobicity, sequence_position, octant (drawing every property took about half of a map's time). Never
/// throws.
const std::vector<std::string>& default_map_properties();

/// Writes, in `folder` (which must exist): pictures/<property>-mollweide.png (2048 x 1024) and
/// pictures/<property>-mollweide.tsv (360 x 180 cells) for each default_map_properties() `globe` has, in the
/// globe's order,
/// pictures/octant-hemispheres.png and pictures/<featured_property>-hemispheres.png, and index.html (the
/// viewer of `viewer`). Every file atomically. Returns the files written, in that order.
/// Throws as map_figure and hemisphere_figure, and InputError naming a file that cannot be written.
std::vector<std::filesystem::path> write_map_pictures(const std::filesystem::path& folder, const Globe& globe,
                                                      const ViewerData& viewer, int threads = 0);

}  // namespace spheremap
