// Pictures and viewer of a map job (see pictures.hpp).
#include "pictures.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/render/map_pictures.hpp"
#include "spheremap/render/viewer_data.hpp"

namespace spheremap::cli {
namespace {

// "1crn" for 1crn.pdb.gz, "bunny" for bunny.ply.
std::string structure_name(const std::filesystem::path& input) {
  std::filesystem::path name = input.filename();
  if (name.extension() == ".gz") name = name.stem();
  return name.stem().string();
}

}  // namespace

Globe globe_of(const MapJobResult& result) {
  const Mesh& surface = result.prepared.mesh;
  std::vector<SurfaceProperty> properties = result.properties.empty()
                                                ? properties_from_attributes(surface, result.map.sphere)
                                                : result.properties;
  return make_globe(surface, result.map.sphere, std::move(properties), structure_name(result.input));
}

Globe globe_of(const MapFolder& folder) {
  try {
    return make_globe(folder.surface, folder.sphere, properties_from_attributes(folder.surface, folder.sphere),
                      folder.name);
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("{}: the map's files do not fit together ({}); map again", folder.folder.string(),
                                 e.what()));
  }
}

namespace {

bool parse_number(std::string_view text, double& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && std::isfinite(value);
}

}  // namespace

ValueRange parse_range(const std::string& text) {
  const auto comma = text.find(',');
  ValueRange range;
  if (comma == std::string::npos || !parse_number(std::string_view(text).substr(0, comma), range.lo) ||
      !parse_number(std::string_view(text).substr(comma + 1), range.hi) || !(range.lo < range.hi))
    throw InputError(fmt::format("--range '{}': expected LO,HI with LO < HI, e.g. --range -5,5", text));
  return range;
}

std::array<int, 2> parse_size(const std::string& text) {
  const auto x = text.find('x');
  std::array<int, 2> size{0, 0};
  const auto parse = [](std::string_view part, int& value) {
    const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
    return error == std::errc() && end == part.data() + part.size() && value > 0;
  };
  if (x == std::string::npos || !parse(std::string_view(text).substr(0, x), size[0]) ||
      !parse(std::string_view(text).substr(x + 1), size[1]))
    throw InputError(fmt::format("--size '{}': expected WIDTHxHEIGHT in pixels, e.g. --size 2048x1024", text));
  return size;
}

void write_pictures(const std::filesystem::path& folder, const MapJobResult& result) {
  const Globe globe = globe_of(result);
  write_map_pictures(folder, globe, viewer_data_for_map(result.prepared.mesh, result.map.sphere, globe.name));
}

}  // namespace spheremap::cli
