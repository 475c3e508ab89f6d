// The pictures and viewer `spheremap map` writes beside a map (OUTPUT/pictures/, OUTPUT/index.html).
#pragma once

#include <array>
#include <filesystem>
#include <string>

#include "spheremap/pipeline/map_folder.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/render/globe.hpp"

namespace spheremap::cli {

/// The globe of a finished map job: its prepared mesh and superposed sphere, with the job's properties
/// (MapJobResult::properties; until the registry fills them, those render computes from the surface's atom
/// attributes), named after the input file. Throws as make_globe.
Globe globe_of(const MapJobResult& result);

/// The globe of a finished output folder read back (properties as globe_of(MapJobResult) computes them).
/// Throws InputError if its files do not fit together.
Globe globe_of(const MapFolder& folder);

/// "lo,hi" (--range) with lo < hi, both finite. Throws InputError naming the option otherwise.
ValueRange parse_range(const std::string& text);

/// "WxH" (--size), both positive. Throws InputError naming the option otherwise.
std::array<int, 2> parse_size(const std::string& text);

/// Writes `folder`/pictures/ and `folder`/index.html for `result` (write_map_pictures). Throws as it.
void write_pictures(const std::filesystem::path& folder, const MapJobResult& result);

}  // namespace spheremap::cli
