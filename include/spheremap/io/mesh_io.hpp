// Reading mesh files (stage: io). Writing: io/ply.hpp; atomic writes: io/atomic_file.hpp.
#pragma once

#include <filesystem>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Reads an OBJ, OFF, PLY (ASCII, binary little- or big-endian) or STL (ASCII or binary) file,
/// chosen by extension (case-insensitive; `.ply`, `.obj`, `.off`, `.stl`).
/// Faces keep all their corners (triangulation happens in prepare_mesh). OBJ `v/vt/vn` and negative
/// (relative) indices are understood; texture and normal data are ignored. STL has no shared vertices:
/// each facet brings three new positions, to be welded by prepare_mesh.
/// Throws InputError naming the file and the problem if the file is missing, unreadable, truncated,
/// of an unknown extension, has an index out of range, a non-finite coordinate, or no faces.
PolygonSoup read_polygon_soup(const std::filesystem::path& path);

/// Reads a triangle mesh written by write_ply (io/ply.hpp) back with its per-vertex attributes: every
/// scalar vertex property but x, y, z (integer types into integer_attributes, float and double into
/// real_attributes) and every `list uchar uchar` vertex property (text_attributes). Other lists are
/// skipped. Throws InputError naming the file if it cannot be read as read_polygon_soup says, or if a face
/// is not a triangle.
Mesh read_ply_mesh(const std::filesystem::path& path);

}  // namespace spheremap
