// Object File Format: `OFF`, counts `V F [E]`, V lines `x y z ...`, F lines `n i1 .. in [colour]`.
// Accepted variants: the C/N/ST prefixes (COFF, NOFF, STOFF, ...: extra per-vertex values are ignored),
// the counts on the keyword line (`OFF 8 6 0`), a missing keyword or edge count, `#` comments and blank
// lines anywhere.
#include <algorithm>
#include <cstdint>
#include <limits>

#include <fmt/format.h>

#include "readers.hpp"

namespace spheremap::io_detail {
namespace {

/// Hands out the lines that hold data: comments stripped, blank lines skipped.
class DataLines {
 public:
  explicit DataLines(std::string_view text) : text_(text) {}

  /// Returns false at the end of the text.
  bool next(std::string_view& line) {
    while (next_start_ < text_.size()) {
      std::size_t end = text_.find('\n', next_start_);
      if (end == std::string_view::npos) end = text_.size();
      line = text_.substr(next_start_, end - next_start_);
      next_start_ = end + 1;
      ++line_number_;
      line = line.substr(0, line.find('#'));
      if (std::any_of(line.begin(), line.end(), [](char c) { return !is_blank(c); })) return true;
    }
    return false;
  }

  [[nodiscard]] std::size_t line_number() const { return line_number_; }

 private:
  std::string_view text_;
  std::size_t next_start_ = 0;
  std::size_t line_number_ = 0;
};

bool is_off_keyword(std::string_view token) { return token.size() >= 3 && token.substr(token.size() - 3) == "OFF"; }

/// Reads `V F [E]` from `line`; returns {V, F}.
std::pair<std::int64_t, std::int64_t> read_counts(std::string_view line, std::size_t line_number,
                                                  const std::string& file) {
  std::int64_t counts[2] = {0, 0};
  for (std::int64_t& count : counts) {
    const std::string_view token = take_token(line);
    if (!parse_integer(token, count) || count < 0) {
      fail(file,
           fmt::format("line {}: bad OFF header: expected the vertex and face counts but found {}", line_number,
                       token.empty() ? std::string("the end of the line") : quote(token)),
           "the line after 'OFF' must read '<vertex count> <face count> <edge count>'");
    }
  }
  return {counts[0], counts[1]};
}

}  // namespace

PolygonSoup read_off(std::string_view bytes, const std::string& file) {
  require_text(bytes, file, "OFF", bytes);
  DataLines lines(bytes);
  std::string_view line;
  if (!lines.next(line)) fail(file, "bad OFF header: the file holds only comments or blank lines", kFix);

  std::string_view after_keyword = line;
  const std::string_view first_token = take_token(after_keyword);
  std::int64_t unused = 0;
  std::string_view counts_line = line;  // without the keyword the counts come first
  if (!parse_integer(first_token, unused)) {
    if (!is_off_keyword(first_token)) {
      fail(file, fmt::format("bad OFF header: the file starts with {}, not 'OFF'", quote(first_token)),
           "check that it really is an OFF file");
    }
    const std::string_view prefix = first_token.substr(0, first_token.size() - 3);
    if (prefix.find_first_not_of("STCN") != std::string_view::npos) {
      fail(file, fmt::format("the OFF variant {} (4D or n-dimensional) is not supported", quote(first_token)),
           "convert it to a 3D OFF, OBJ or PLY file");
    }
    std::string_view probe = after_keyword;
    if (take_token(probe) == "BINARY") {
      fail(file, "binary OFF is not supported", "convert it to a text OFF, OBJ or PLY file");
    }
    counts_line = after_keyword;
    if (std::all_of(counts_line.begin(), counts_line.end(), is_blank) && !lines.next(counts_line)) {
      fail(file, "bad OFF header: the file ends before the vertex and face counts", kFix);
    }
  }
  const auto [vertex_count, face_count] = read_counts(counts_line, lines.line_number(), file);

  PolygonSoup soup;
  // Bound the reservation by what the file could hold, so a lying header cannot exhaust memory.
  constexpr std::size_t kMinimumLineBytes = 6;  // "0 0 0\n"
  const std::size_t line_capacity = bytes.size() / kMinimumLineBytes + 1;
  soup.positions.reserve(std::min(static_cast<std::size_t>(vertex_count), line_capacity));
  soup.faces.reserve(std::min(static_cast<std::size_t>(face_count), line_capacity));

  for (std::int64_t v = 0; v < vertex_count; ++v) {
    if (!lines.next(line)) {
      fail(file, fmt::format("the file ends after {} of {} vertices (truncated?)", v, vertex_count),
           "re-export the mesh");
    }
    Vec3 position{};
    for (double& coordinate : position) {
      const std::string_view token = take_token(line);
      if (!parse_double(token, coordinate)) {
        fail(file,
             fmt::format("line {}: vertex {} needs 3 coordinates but has {}", lines.line_number(), v,
                         token.empty() ? std::string("fewer") : quote(token)),
             kFix);
      }
    }
    soup.positions.push_back(position);
  }

  for (std::int64_t f = 0; f < face_count; ++f) {
    if (!lines.next(line)) {
      fail(file, fmt::format("the file ends after {} of {} faces (truncated?)", f, face_count), "re-export the mesh");
    }
    std::int64_t corner_count = 0;
    const std::string_view count_token = take_token(line);
    if (!parse_integer(count_token, corner_count) || corner_count < 0) {
      fail(file,
           fmt::format("line {}: face {} should start with its corner count but starts with {}", lines.line_number(), f,
                       quote(count_token)),
           kFix);
    }
    // Each index takes at least two characters, which bounds the reservation.
    std::vector<std::int32_t> corners;
    corners.reserve(std::min(static_cast<std::size_t>(corner_count), line.size() / 2 + 1));
    for (std::int64_t c = 0; c < corner_count; ++c) {
      const std::string_view token = take_token(line);
      std::int64_t index = 0;
      if (!parse_integer(token, index)) {
        fail(file,
             fmt::format("line {}: face {} has {} corners but its index {} is {}", lines.line_number(), f, corner_count,
                         c + 1, token.empty() ? std::string("missing") : quote(token)),
             kFix);
      }
      if (index < 0 || index > std::numeric_limits<std::int32_t>::max()) {
        fail(file,
             fmt::format("line {}: face {} refers to vertex {}, but the vertices are numbered 0 to {}",
                         lines.line_number(), f, index, vertex_count - 1),
             "the file is corrupt or truncated; re-export the mesh");
      }
      corners.push_back(static_cast<std::int32_t>(index));
    }
    // Whatever follows the indices is an optional face colour.
    soup.faces.push_back(std::move(corners));
  }
  return soup;
}

}  // namespace spheremap::io_detail
