// The one data type that flows through the pipeline: a triangle mesh as plain data.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace spheremap {

using Vec3 = std::array<double, 3>;
using Triangle = std::array<std::int32_t, 3>;

/// A per-vertex text attribute, dictionary-coded: vertex v has the text dictionary[codes[v]]. Atom and
/// residue names repeat across thousands of vertices, so one small string table is kept instead of a
/// string per vertex. Each text is at most 255 bytes (a PLY list with a uchar length).
struct TextAttribute {
  std::vector<std::string> dictionary;
  std::vector<std::int32_t> codes;

  [[nodiscard]] const std::string& at(std::size_t vertex) const { return dictionary[codes[vertex]]; }
};

/// A triangle mesh: positions, triangles (indices into positions, counter-clockwise seen from
/// outside once the mesh has been prepared) and named per-vertex attributes.
///
/// Invariants every producer keeps and every consumer may rely on:
/// - every triangle index is in [0, positions.size());
/// - every attribute has exactly positions.size() entries (for text attributes: codes), and every text
///   code indexes its dictionary.
/// Real-valued attributes are written to PLY as `double` properties, integer ones as `int`, text ones
/// as `list uchar uchar` (the bytes of the text).
struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
  std::map<std::string, std::vector<double>> real_attributes;
  std::map<std::string, std::vector<std::int32_t>> integer_attributes;
  std::map<std::string, TextAttribute> text_attributes;

  [[nodiscard]] std::size_t vertex_count() const { return positions.size(); }
  [[nodiscard]] std::size_t triangle_count() const { return triangles.size(); }
};

/// Vertices and faces as read from a file, before triangulation, welding and checks.
/// Faces may have any number (>= 3) of corners.
struct PolygonSoup {
  std::vector<Vec3> positions;
  std::vector<std::vector<std::int32_t>> faces;
};

}  // namespace spheremap
