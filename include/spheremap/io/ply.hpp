// Writing PLY files (stage: io). Reading: io/mesh_io.hpp.
#pragma once

#include <filesystem>
#include <set>
#include <string>

#include "spheremap/mesh.hpp"

namespace spheremap {

struct PlyWriteOptions {
  bool ascii = false;  // ASCII writes every double with %.17g (round-trips exactly), every float with %.9g
  /// Real attributes written as `float` (the value rounded to the nearest float) instead of `double`.
  std::set<std::string> float_attributes;
  /// Integer attributes written as `uchar`; their values must be in [0, 255].
  std::set<std::string> uchar_attributes;
};

/// Writes `mesh` as PLY: `x y z` as double, then every real attribute as a `double` property and
/// every integer attribute as an `int` property (in name order; options.float_attributes and
/// options.uchar_attributes change the type of those named; `red`,
/// `green`, `blue` come last, in that order, as readers such as Open3D expect), then every text attribute as a
/// `list uchar uchar` property, then the faces as `list uchar int vertex_indices`. Binary
/// little-endian unless options.ascii. The file is written atomically (AtomicFile): a reader never
/// sees a partial file.
/// Preconditions: every attribute has one value per vertex, a name that is a PLY token other than
/// x, y, z, used by one kind of attribute only; text values of at most 255 bytes; uchar attributes in
/// [0, 255].
/// Throws std::invalid_argument if a precondition fails (nothing written), InputError if the file
/// cannot be written.
void write_ply(const std::filesystem::path& path, const Mesh& mesh, const PlyWriteOptions& options = {});

}  // namespace spheremap
