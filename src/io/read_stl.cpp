// STL, ASCII (`solid ... facet ... vertex x y z ... endsolid`) or binary (80-byte header, uint32
// triangle count, 50 bytes per triangle). STL shares no vertices: every facet brings its own corners.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>

#include <fmt/format.h>

#include "readers.hpp"

namespace spheremap::io_detail {
namespace {

constexpr std::size_t kHeaderBytes = 80;
constexpr std::size_t kCountBytes = 4;
constexpr std::size_t kTriangleBytes = 50;  // normal, 3 corners (12 float32), 2-byte attribute

std::uint32_t load_little_endian_u32(const char* at) {
  std::array<unsigned char, 4> bytes;
  std::memcpy(bytes.data(), at, 4);
  return static_cast<std::uint32_t>(bytes[0]) | static_cast<std::uint32_t>(bytes[1]) << 8 |
         static_cast<std::uint32_t>(bytes[2]) << 16 | static_cast<std::uint32_t>(bytes[3]) << 24;
}

float load_little_endian_float(const char* at) { return std::bit_cast<float>(load_little_endian_u32(at)); }

bool starts_with_solid(std::string_view bytes) {
  std::string_view rest = bytes;
  return take_token(rest) == "solid";
}

PolygonSoup read_binary_stl(std::string_view bytes, std::uint64_t triangle_count) {
  PolygonSoup soup;
  soup.positions.reserve(static_cast<std::size_t>(triangle_count) * 3);
  soup.faces.reserve(static_cast<std::size_t>(triangle_count));
  const char* triangle = bytes.data() + kHeaderBytes + kCountBytes;
  for (std::uint64_t t = 0; t < triangle_count; ++t, triangle += kTriangleBytes) {
    const auto first = static_cast<std::int32_t>(soup.positions.size());
    for (std::size_t corner = 0; corner < 3; ++corner) {
      const char* at = triangle + 12 * (corner + 1);  // the facet normal comes first
      soup.positions.push_back(
          {load_little_endian_float(at), load_little_endian_float(at + 4), load_little_endian_float(at + 8)});
    }
    soup.faces.push_back({first, first + 1, first + 2});
  }
  return soup;
}

PolygonSoup read_ascii_stl(std::string_view bytes, const std::string& file) {
  PolygonSoup soup;
  const auto line_of = [&](std::string_view token) {
    return line_number_at(bytes, static_cast<std::size_t>(token.data() - bytes.data()));
  };
  const auto skip_rest_of_line = [](std::string_view& rest) {
    const std::size_t end = rest.find('\n');
    rest.remove_prefix(end == std::string_view::npos ? rest.size() : end);
  };
  const auto read_coordinates = [&](std::string_view& rest, std::string_view keyword) {
    Vec3 values{};
    for (double& value : values) {
      const std::string_view token = take_token(rest);
      if (token.empty()) {
        fail(file, fmt::format("the file ends inside facet {} (truncated?)", soup.faces.size()), "re-export the mesh");
      }
      if (!parse_double(token, value)) {
        fail(file, fmt::format("line {}: '{}' needs 3 numbers but has {}", line_of(token), keyword, quote(token)),
             "fix the line or re-export the mesh");
      }
    }
    return values;
  };

  std::vector<std::int32_t> corners;
  bool inside_facet = false;
  std::string_view rest = bytes;
  for (std::string_view token = take_token(rest); !token.empty(); token = take_token(rest)) {
    if (token == "solid" || token == "endsolid") {
      skip_rest_of_line(rest);  // the solid's name, which may hold any words
    } else if (token == "facet") {
      if (inside_facet) {
        fail(
            file,
            fmt::format("line {}: facet {} starts before the previous one ends", line_of(token), soup.faces.size() + 1),
            "add the missing 'endfacet' or re-export the mesh");
      }
      inside_facet = true;
      corners.clear();
    } else if (token == "normal") {
      read_coordinates(rest, token);  // recomputed later from the corners
    } else if (token == "vertex") {
      if (!inside_facet) {
        fail(file, fmt::format("line {}: 'vertex' outside a facet", line_of(token)),
             "fix the file or re-export the mesh");
      }
      corners.push_back(static_cast<std::int32_t>(soup.positions.size()));
      soup.positions.push_back(read_coordinates(rest, token));
    } else if (token == "endfacet") {
      if (!inside_facet) {
        fail(file, fmt::format("line {}: 'endfacet' without 'facet'", line_of(token)),
             "fix the file or re-export the mesh");
      }
      inside_facet = false;
      soup.faces.push_back(corners);
    } else if (token != "outer" && token != "loop" && token != "endloop") {
      fail(file, fmt::format("line {}: unexpected {} in an ASCII STL file", line_of(token), quote(token)),
           "fix the file or re-export the mesh");
    }
  }
  if (inside_facet) {
    fail(file, fmt::format("the file ends inside facet {} (truncated?)", soup.faces.size()), "re-export the mesh");
  }
  return soup;
}

}  // namespace

PolygonSoup read_stl(std::string_view bytes, const std::string& file) {
  // A binary header may itself start with "solid" (some exporters do that), so the exact binary
  // size decides first.
  const bool ascii_look = starts_with_solid(bytes.substr(0, kHeaderBytes));
  if (bytes.size() >= kHeaderBytes + kCountBytes) {
    const std::uint64_t triangle_count = load_little_endian_u32(bytes.data() + kHeaderBytes);
    const std::uint64_t binary_size = kHeaderBytes + kCountBytes + kTriangleBytes * triangle_count;
    if (bytes.size() == binary_size) return read_binary_stl(bytes, triangle_count);
    if (!ascii_look) {
      if (bytes.size() < binary_size) {
        const std::uint64_t complete = (bytes.size() - kHeaderBytes - kCountBytes) / kTriangleBytes;
        fail(file, fmt::format("the file ends after {} of {} triangles (truncated?)", complete, triangle_count),
             "re-export the mesh");
      }
      // Some exporters pad binary files; the triangles themselves are complete.
      return read_binary_stl(bytes, triangle_count);
    }
  } else if (!ascii_look) {
    fail(file, fmt::format("the file has {} bytes: too short for a binary STL and not an ASCII STL", bytes.size()),
         "re-export the mesh");
  }
  for (const char c : bytes) {
    // Report a binary file whose header happens to start with "solid" as such, not as bad text.
    if (c == '\0') {
      fail(file,
           "the file starts with 'solid' like an ASCII STL but holds binary data, and its size does not match "
           "the triangle count of a binary STL (truncated?)",
           "re-export the mesh");
    }
  }
  require_text(bytes, file, "STL (ASCII)", bytes);
  return read_ascii_stl(bytes, file);
}

}  // namespace spheremap::io_detail
