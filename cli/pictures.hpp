// The pictures and viewer `spheremap map` writes beside a map (OUTPUT/pictures/, OUTPUT/index.html).
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/pipeline/map_folder.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/render/globe.hpp"
#include "spheremap/render/hemispheres.hpp"

namespace spheremap::cli {

/// The globe of a finished map job: its prepared mesh and superposed sphere, with the job's properties
/// (MapJobResult::properties; until the registry fills them, those render computes from the surface's atom
/// attributes), named after the input file. Throws as make_globe.
Globe globe_of(const MapJobResult& result);

/// The globe of a finished output folder read back: the folder's properties (for folders before 0.2, those
/// properties_from_attributes computes). Throws InputError if its files do not fit together.
Globe globe_of(const MapFolder& folder);

/// The backbone of the structure `structure` (its CA atoms, one path per chain, in file order) coloured by
/// `property`: a CA takes the mean of the property over the globe vertices of its residue; a residue not on
/// the surface takes the value interpolated along the chain between its nearest neighbours that are (NaN
/// for categorical properties). Throws InputError if the globe has no residues, or the file cannot be read or
/// has no CA atom.
std::vector<TracePath> backbone_trace(const Globe& globe, const SurfaceProperty& property,
                                      const std::filesystem::path& structure);

/// "lo,hi" (--range) with lo < hi, both finite. Throws InputError naming the option otherwise.
ValueRange parse_range(const std::string& text);

/// "WxH" (--size), both positive. Throws InputError naming the option otherwise.
std::array<int, 2> parse_size(const std::string& text);

/// Writes `folder`/pictures/ and `folder`/index.html for `result` (write_map_pictures, on `threads` threads, 0:
/// all; the bytes do not depend on it). Throws as it.
void write_pictures(const std::filesystem::path& folder, const MapJobResult& result, int threads = 0);

}  // namespace spheremap::cli
