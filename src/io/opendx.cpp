// OpenDX reader (no library in Debian reads it from C++; gemmi reads CCP4 maps only).
#include "spheremap/io/opendx.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

template <typename T>
bool parse(std::string_view text, T& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc{} && end == text.data() + text.size();
}

// The file's lines, read one at a time with their numbers, skipping blank lines and '#' comments.
class Lines {
 public:
  Lines(std::string text, const std::filesystem::path& path) : text_(std::move(text)), path_(path) {}

  // The next line that is not blank nor a comment; false at the end.
  bool next(std::string_view& line) {
    while (position_ < text_.size()) {
      const std::size_t end = std::min(text_.find('\n', position_), text_.size());
      line = std::string_view(text_).substr(position_, end - position_);
      position_ = end + 1;
      ++number_;
      const auto first = line.find_first_not_of(" \t\r");
      if (first != std::string_view::npos && line[first] != '#') return true;
    }
    return false;
  }

  // Bytes not read yet.
  [[nodiscard]] std::size_t remaining() const { return text_.size() - std::min(position_, text_.size()); }

  [[nodiscard]] InputError error(const std::string& problem) const {
    return InputError(fmt::format("{}:{}: {}; is it an OpenDX map as APBS writes it (write pot dx)?", path_.string(),
                                  number_, problem));
  }
  [[nodiscard]] InputError error_at_end(const std::string& problem) const {
    return InputError(fmt::format("{}: {}; the file looks truncated: write the map again", path_.string(), problem));
  }

 private:
  std::string text_;
  const std::filesystem::path& path_;
  std::size_t position_ = 0;
  std::int64_t number_ = 0;
};

// `keyword x y z` with three numbers.
template <typename T>
std::array<T, 3> three_numbers(const std::vector<std::string_view>& tokens, std::size_t first, const Lines& lines,
                               const char* what) {
  std::array<T, 3> values{};
  if (tokens.size() < first + 3) throw lines.error(fmt::format("expected {} followed by three numbers", what));
  for (int d = 0; d < 3; ++d)
    if (!parse(tokens[first + d], values[d]) || !std::isfinite(static_cast<double>(values[d])))
      throw lines.error(fmt::format("'{}' in the {} is not a number", tokens[first + d], what));
  return values;
}

std::size_t find_token(const std::vector<std::string_view>& tokens, std::string_view word) {
  return static_cast<std::size_t>(std::find(tokens.begin(), tokens.end(), word) - tokens.begin());
}

double determinant(const std::array<Vec3, 3>& d) { return dot(d[0], cross(d[1], d[2])); }

// The header up to `data follows`: the grid without its values, and the number of values announced.
std::int64_t read_header(Lines& lines, DxGrid& grid) {
  std::string_view line;
  const auto expect = [&](const char* what) {
    if (!lines.next(line)) throw lines.error_at_end(fmt::format("the file ends before its {}", what));
    return split(line);
  };
  auto tokens = expect("'object 1 class gridpositions counts nx ny nz' line");
  const std::size_t counts_at = find_token(tokens, "counts");
  if (tokens.empty() || tokens[0] != "object" || find_token(tokens, "gridpositions") == tokens.size() ||
      counts_at == tokens.size())
    throw lines.error("expected 'object 1 class gridpositions counts nx ny nz'");
  grid.counts = three_numbers<std::int64_t>(tokens, counts_at + 1, lines, "grid counts");
  for (const auto n : grid.counts)
    if (n < 2 || n > 100000) throw lines.error(fmt::format("a grid count of {} (each must be 2 to 100000)", n));
  tokens = expect("origin");
  if (tokens.empty() || tokens[0] != "origin") throw lines.error("expected 'origin x y z'");
  grid.origin = three_numbers<double>(tokens, 1, lines, "origin");
  for (auto& delta : grid.delta) {
    tokens = expect("three delta lines");
    if (tokens.empty() || tokens[0] != "delta") throw lines.error("expected 'delta dx dy dz' (three of them)");
    delta = three_numbers<double>(tokens, 1, lines, "delta");
  }
  const double scale = norm(grid.delta[0]) * norm(grid.delta[1]) * norm(grid.delta[2]);
  if (!(std::abs(determinant(grid.delta)) > 1e-9 * scale))
    throw lines.error("the three delta vectors are zero or lie in a plane: not a 3D grid");
  tokens = expect("'object 3 class array ... items N data follows' line");
  if (find_token(tokens, "gridconnections") != tokens.size()) {
    const std::size_t at = find_token(tokens, "counts");
    if (at == tokens.size() || three_numbers<std::int64_t>(tokens, at + 1, lines, "grid connections") != grid.counts)
      throw lines.error("the gridconnections counts differ from the gridpositions counts");
    tokens = expect("'object 3 class array ... items N data follows' line");
  }
  const std::size_t items_at = find_token(tokens, "items");
  std::int64_t items = 0;
  if (tokens.empty() || tokens[0] != "object" || find_token(tokens, "array") == tokens.size() ||
      items_at + 1 >= tokens.size() || !parse(tokens[items_at + 1], items))
    throw lines.error("expected 'object 3 class array type double rank 0 items N data follows'");
  const std::int64_t expected = grid.counts[0] * grid.counts[1] * grid.counts[2];
  if (items != expected)
    throw lines.error(fmt::format("{} items announced, but the grid has {} x {} x {} = {} points", items,
                                  grid.counts[0], grid.counts[1], grid.counts[2], expected));
  return items;
}

}  // namespace

DxGrid read_dx(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(fmt::format("{}: cannot open the potential map; check the path and permissions", path.string()));
  std::stringstream content;
  content << in.rdbuf();
  Lines lines(content.str(), path);
  DxGrid grid;
  const std::int64_t items = read_header(lines, grid);
  // Reserve no more than the rest of the file can hold (a value takes two bytes at least): a header may lie.
  grid.values.reserve(std::min(static_cast<std::size_t>(items), lines.remaining() / 2 + 1));
  std::string_view line;
  while (static_cast<std::int64_t>(grid.values.size()) < items) {
    if (!lines.next(line))
      throw lines.error_at_end(fmt::format("only {} of the {} values announced", grid.values.size(), items));
    for (const auto token : split(line)) {
      double value = 0;
      if (!parse(token, value)) {
        if (std::isalpha(static_cast<unsigned char>(token[0])) && token != "nan" && token != "inf")
          throw lines.error(
              fmt::format("'{}' after only {} of the {} values announced", token, grid.values.size(), items));
        throw lines.error(fmt::format("'{}' is not a number", token));
      }
      if (!std::isfinite(value)) throw lines.error(fmt::format("'{}' is not a finite number", token));
      if (static_cast<std::int64_t>(grid.values.size()) == items)
        throw lines.error(fmt::format("more values than the {} announced", items));
      grid.values.push_back(value);
    }
  }
  // The data ends at the next keyword (attribute, object, component); a number there means wrong counts.
  if (lines.next(line)) {
    const auto tokens = split(line);
    double value = 0;
    if (!tokens.empty() && parse(tokens[0], value))
      throw lines.error(fmt::format("more values than the {} announced", items));
  }
  return grid;
}

}  // namespace spheremap
