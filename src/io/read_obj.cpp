// Wavefront OBJ: only `v` and `f` lines matter; every other line (vt, vn, g, o, usemtl, ...) is skipped.
#include <cstdint>
#include <limits>

#include <fmt/format.h>

#include "readers.hpp"

namespace spheremap::io_detail {
namespace {

void read_vertex(std::string_view rest, std::size_t line_number, PolygonSoup& soup, const std::string& file) {
  Vec3 position{};
  // Further values (w, or vertex colours) are ignored.
  for (double& coordinate : position) {
    const std::string_view token = take_token(rest);
    if (token.empty()) fail(file, fmt::format("line {}: a vertex needs 3 coordinates", line_number), kFix);
    if (!parse_double(token, coordinate)) {
      fail(file, fmt::format("line {}: expected a coordinate but found {}", line_number, quote(token)), kFix);
    }
  }
  soup.positions.push_back(position);
}

void read_face(std::string_view rest, std::size_t line_number, PolygonSoup& soup, const std::string& file) {
  const std::size_t face_number = soup.faces.size() + 1;
  const auto vertices_so_far = static_cast<std::int64_t>(soup.positions.size());
  std::vector<std::int32_t> corners;
  for (std::string_view token = take_token(rest); !token.empty(); token = take_token(rest)) {
    // A corner is `v`, `v/vt`, `v//vn` or `v/vt/vn`: only the position index is used.
    std::int64_t index = 0;
    const std::size_t used = parse_integer_prefix(token, index);
    if (used == 0 || (used < token.size() && token[used] != '/')) {
      fail(
          file,
          fmt::format("line {}: face {} has the corner {}, not a vertex index", line_number, face_number, quote(token)),
          kFix);
    }
    if (index == 0) {
      fail(file,
           fmt::format("line {}: face {} refers to vertex 0, but OBJ vertices are numbered from 1", line_number,
                       face_number),
           kFix);
    }
    // Negative indices count back from the last vertex read so far (-1 is the latest).
    const std::int64_t zero_based = index > 0 ? index - 1 : vertices_so_far + index;
    if (zero_based < 0) {
      fail(file,
           fmt::format("line {}: face {} refers to vertex {}, but only {} vertices precede it", line_number,
                       face_number, index, vertices_so_far),
           kFix);
    }
    if (zero_based > std::numeric_limits<std::int32_t>::max()) {
      fail(file,
           fmt::format("line {}: face {} refers to vertex {}, beyond any supported mesh size", line_number, face_number,
                       index),
           kFix);
    }
    corners.push_back(static_cast<std::int32_t>(zero_based));
  }
  soup.faces.push_back(std::move(corners));
}

}  // namespace

PolygonSoup read_obj(std::string_view bytes, const std::string& file) {
  require_text(bytes, file, "OBJ", bytes);
  PolygonSoup soup;
  std::size_t line_number = 0;
  std::size_t line_start = 0;
  while (line_start < bytes.size()) {
    std::string_view rest = take_line(bytes, line_start);
    ++line_number;

    const std::string_view keyword = take_token(rest);
    if (keyword == "v") {
      read_vertex(rest, line_number, soup, file);
    } else if (keyword == "f") {
      read_face(rest, line_number, soup, file);
    }
  }
  return soup;
}

}  // namespace spheremap::io_detail
