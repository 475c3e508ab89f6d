// Writing binary glTF 2.0 (.glb) triangle meshes with vertex colours and application-specific per-vertex
// attributes (stage: io).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// One mesh for a .glb file.
struct GlbMesh {
  std::string name;
  std::vector<Vec3> positions;  // written as float (POSITION, with its min and max)
  std::vector<Vec3> normals;    // unit vectors (NORMAL); empty: none
  std::vector<std::array<std::uint8_t, 3>>
      colours;                      // sRGB (COLOR_0, normalized unsigned bytes, alpha 255); empty: none
  std::vector<Triangle> triangles;  // counter-clockwise seen from outside (glTF's front faces)
  /// Application-specific attributes, e.g. {"_ELECTROSTATICS", values}: a name starting with '_', one value per
  /// vertex, written as float SCALAR. glTF has no NaN: a NaN is written as `kGlbMissingValue`, named in the
  /// accessor's `extras.missing_value`.
  std::vector<std::pair<std::string, std::vector<double>>> attributes;
};

/// What a NaN becomes in a .glb attribute: the lowest float.
inline constexpr float kGlbMissingValue = -3.4028234663852886e38F;

/// "_" + the name in upper case: glTF's form for an application-specific attribute (electrostatics ->
/// _ELECTROSTATICS). Never throws (but std::bad_alloc).
std::string glb_attribute_name(const std::string& property);

/// Writes `mesh` as a binary glTF 2.0 file: one scene, one node, one mesh of one triangle primitive, one buffer
/// (the BIN chunk), one tightly packed buffer view per accessor at a 4-byte-aligned offset, 32-bit indices.
/// Written atomically (AtomicFile). Deterministic: the same mesh gives the same bytes.
/// Preconditions: normals, colours and every attribute empty or of one entry per position; attribute names start
/// with '_'; indices valid; at least one position. Throws std::invalid_argument if one fails (nothing written),
/// InputError if the file cannot be written.
void write_glb(const std::filesystem::path& path, const GlbMesh& mesh);

}  // namespace spheremap
