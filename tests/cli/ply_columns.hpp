// Test helper: the vertex columns of a binary little-endian PLY file as doubles (any scalar type; lists
// skipped), and its faces. Enough to check what write_map_outputs writes; not a general reader.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "../test_support.hpp"

namespace spheremap::testing_support {

struct PlyColumns {
  std::map<std::string, std::vector<double>> vertex;  // column name -> one value per vertex
  std::map<std::string, std::string> type;            // column name -> PLY type ("float", "uchar", ...)
  std::vector<std::array<std::int32_t, 3>> faces;
};

inline std::size_t ply_size(const std::string& type) {
  if (type == "char" || type == "uchar") return 1;
  if (type == "short" || type == "ushort") return 2;
  if (type == "int" || type == "uint" || type == "float") return 4;
  if (type == "double") return 8;
  throw std::runtime_error("ply type " + type);
}

inline double ply_load(const char* at, const std::string& type) {
  auto get = [&](auto value) {
    std::memcpy(&value, at, sizeof value);
    return static_cast<double>(value);
  };
  if (type == "char") return get(std::int8_t{});
  if (type == "uchar") return get(std::uint8_t{});
  if (type == "short") return get(std::int16_t{});
  if (type == "ushort") return get(std::uint16_t{});
  if (type == "int") return get(std::int32_t{});
  if (type == "uint") return get(std::uint32_t{});
  if (type == "float") return get(float{});
  return get(double{});
}

inline PlyColumns read_ply_columns(const std::filesystem::path& path) {
  const std::string bytes = slurp(path);
  const auto end = bytes.find("end_header\n");
  if (end == std::string::npos || bytes.find("binary_little_endian") == std::string::npos)
    throw std::runtime_error("not a binary little-endian PLY: " + path.string());
  std::istringstream header(bytes.substr(0, end));
  struct Property {
    std::string name, type, count_type;  // count_type set: a list
  };
  std::vector<Property> vertex;
  std::size_t vertices = 0, faces = 0;
  std::string element, line;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "element") {
      words >> element;
      (element == "vertex" ? vertices : faces) = [&] {
        std::size_t n = 0;
        words >> n;
        return n;
      }();
    } else if (key == "property" && element == "vertex") {
      Property p;
      words >> p.type;
      if (p.type == "list") words >> p.count_type >> p.type;
      words >> p.name;
      vertex.push_back(p);
    }
  }
  PlyColumns columns;
  const char* at = bytes.data() + end + 11;
  for (std::size_t v = 0; v < vertices; ++v)
    for (const Property& p : vertex) {
      if (!p.count_type.empty()) {
        const auto n = static_cast<std::size_t>(ply_load(at, p.count_type));
        at += ply_size(p.count_type) + n * ply_size(p.type);
        continue;
      }
      columns.vertex[p.name].push_back(ply_load(at, p.type));
      columns.type[p.name] = p.type;
      at += ply_size(p.type);
    }
  for (std::size_t f = 0; f < faces; ++f) {
    std::array<std::int32_t, 3> face{};
    std::memcpy(face.data(), at + 1, 12);
    columns.faces.push_back(face);
    at += 13;
  }
  return columns;
}

}  // namespace spheremap::testing_support
