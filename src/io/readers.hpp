// Private to src/io: the per-format mesh readers and the text-parsing helpers they share.
//
// Every reader takes the whole file in memory (`bytes`) and the file name to put in messages.
// Readers check every bound themselves (the input may be hostile) and throw InputError; the checks
// common to all formats (index range, finite coordinates, at least one face) run afterwards in
// read_polygon_soup.
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap::io_detail {

/// The fix a text mesh reader's message suggests for a bad line.
inline constexpr const char* kFix = "fix the line or re-export the mesh";

PolygonSoup read_obj(std::string_view bytes, const std::string& file);
PolygonSoup read_off(std::string_view bytes, const std::string& file);
PolygonSoup read_ply(std::string_view bytes, const std::string& file);

/// The vertex element's properties other than x, y, z, by name: integer types, floating-point types, and
/// lists of uchar (text); other lists are skipped. `text_codes` is the dictionary being built.
struct PlyVertexAttributes {
  std::map<std::string, std::vector<double>> real;
  std::map<std::string, std::vector<std::int32_t>> integer;
  std::map<std::string, TextAttribute> text;
  std::map<std::string, std::map<std::string, std::int32_t>> text_codes;
};

/// read_ply keeping the vertex attributes in `attributes` (nullptr: none).
PolygonSoup read_ply(std::string_view bytes, const std::string& file, PlyVertexAttributes* attributes);
PolygonSoup read_stl(std::string_view bytes, const std::string& file);

/// Throws InputError with the message "<file>: <problem>; <fix>".
[[noreturn]] void fail(const std::string& file, const std::string& problem, const std::string& fix);

/// 1-based number of the line that contains byte `offset` of `text` (for messages only: O(offset)).
std::size_t line_number_at(std::string_view text, std::size_t offset);

/// Throws InputError if `text` holds a byte that never occurs in a text file (NUL and most control
/// characters), which means a binary file was given to a text-format reader.
/// `base_offset` is where `text` starts within the file, for the message.
void require_text(std::string_view text, const std::string& file, std::string_view format_name,
                  std::string_view whole_file, std::size_t base_offset = 0);

/// Whitespace of text mesh formats; '\r' is included so CRLF files need no special case.
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// Removes the first whitespace-separated token of `rest` (newlines included as whitespace when
/// `rest` spans lines) and returns it; returns an empty view when `rest` holds only whitespace.
inline std::string_view take_token(std::string_view& rest) {
  std::size_t begin = 0;
  while (begin < rest.size() && (is_blank(rest[begin]) || rest[begin] == '\n')) ++begin;
  std::size_t end = begin;
  while (end < rest.size() && !is_blank(rest[end]) && rest[end] != '\n') ++end;
  std::string_view token = rest.substr(begin, end - begin);
  rest.remove_prefix(end);
  return token;
}

/// The line of `bytes` that starts at `line_start` (without its '\n'); moves `line_start` past it.
/// Precondition: line_start <= bytes.size().
inline std::string_view take_line(std::string_view bytes, std::size_t& line_start) {
  std::size_t line_end = bytes.find('\n', line_start);
  if (line_end == std::string_view::npos) line_end = bytes.size();
  const std::string_view line = bytes.substr(line_start, line_end - line_start);
  line_start = line_end + 1;
  return line;
}

/// Parses a decimal number that fills `token` exactly ("1", "-2.5e3", "+.5", "inf", "nan").
/// Non-finite values are accepted here; read_polygon_soup rejects them with the vertex number.
inline bool parse_double(std::string_view token, double& value) {
  // from_chars rejects a leading '+', which some exporters write.
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end && !token.empty();
}

/// Parses the integer at the start of `token`; returns the number of characters used (0 on failure
/// or overflow of int64).
inline std::size_t parse_integer_prefix(std::string_view token, std::int64_t& value) {
  std::size_t skipped = (token.size() > 1 && token[0] == '+' && token[1] != '-') ? 1 : 0;
  const char* begin = token.data() + skipped;
  auto [ptr, ec] = std::from_chars(begin, token.data() + token.size(), value);
  if (ec != std::errc()) return 0;
  return static_cast<std::size_t>(ptr - token.data());
}

/// Parses an integer that fills `token` exactly.
inline bool parse_integer(std::string_view token, std::int64_t& value) {
  return !token.empty() && parse_integer_prefix(token, value) == token.size();
}

/// Shortens a token for quoting in a message (a binary blob could be megabytes long).
std::string quote(std::string_view token);

}  // namespace spheremap::io_detail
