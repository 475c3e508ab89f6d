// Pictures and viewer of a map job (see pictures.hpp).
#include "pictures.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/render/map_pictures.hpp"
#include "spheremap/render/viewer_data.hpp"
#include "spheremap/text.hpp"

namespace spheremap::cli {
namespace {

// "1crn" for 1crn.pdb.gz, "bunny" for bunny.ply.
std::string structure_name(const std::filesystem::path& input) {
  std::filesystem::path name = input.filename();
  if (name.extension() == ".gz") name = name.stem();
  return valid_utf8(name.stem().string());  // titles go through cairo, which takes UTF-8 only
}

}  // namespace

Globe globe_of(const MapJobResult& result) {
  const Mesh& surface = result.prepared.mesh;
  std::vector<SurfaceProperty> properties =
      result.properties.empty() ? properties_from_attributes(surface, result.map.sphere) : result.properties;
  return make_globe(surface, result.map.sphere, std::move(properties), structure_name(result.input));
}

Globe globe_of(const MapFolder& folder) {
  try {
    // Folders before 0.2 list no properties: compute those the pictures showed then.
    Globe globe = make_globe(
        folder.surface, folder.sphere,
        folder.properties.empty() ? properties_from_attributes(folder.surface, folder.sphere) : folder.properties,
        folder.name);
    globe.no_residues_reason = folder.no_residues_reason;
    return globe;
  } catch (const std::invalid_argument& e) {
    throw InputError(
        fmt::format("{}: the map's files do not fit together ({}); map again", folder.folder.string(), e.what()));
  }
}

std::vector<TracePath> backbone_trace(const Globe& globe, const SurfaceProperty& property,
                                      const std::filesystem::path& structure) {
  if (globe.residues.empty())
    throw InputError(fmt::format("--trace: this map has no residues ({})", no_residues_text(globe)));
  const Molecule molecule = read_structure(structure);
  // Mean value of each residue over its vertices.
  std::vector<double> sum(globe.residues.size(), 0.0);
  std::vector<int> count(globe.residues.size(), 0);
  for (std::size_t v = 0; v < globe.vertex_residue.size(); ++v) {
    const std::int32_t r = globe.vertex_residue[v];
    if (r >= 0 && !std::isnan(property.values[v])) sum[r] += property.values[v], ++count[r];
  }
  std::map<std::tuple<std::string, std::int32_t, std::string>, double> residue_value;
  for (std::size_t r = 0; r < globe.residues.size(); ++r)
    if (count[r] > 0) {
      const ResidueLabel& l = globe.residues[r];
      residue_value[{l.chain, l.number, l.insertion_code}] = sum[r] / count[r];
    }
  std::vector<TracePath> paths;
  std::string chain;
  for (const Atom& atom : molecule.atoms) {
    if (atom.name != "CA" || atom.hetero) continue;
    if (paths.empty() || atom.chain != chain) paths.emplace_back(), chain = atom.chain;
    const std::string insertion = atom.insertion_code == ' ' ? "" : std::string(1, atom.insertion_code);
    const auto found = residue_value.find({atom.chain, atom.residue_number, insertion});
    paths.back().points.push_back(atom.position);
    paths.back().values.push_back(found == residue_value.end() ? std::numeric_limits<double>::quiet_NaN()
                                                               : found->second);
  }
  if (paths.empty())
    throw InputError(fmt::format("{}: no CA atom, so no backbone to trace; leave out --trace", structure.string()));
  if (property.info.scale != ScaleKind::categorical)
    for (TracePath& path : paths) {
      // Buried residues: linear interpolation between the nearest known neighbours (the end value beyond).
      const auto n = static_cast<std::ptrdiff_t>(path.values.size());
      for (std::ptrdiff_t k = 0; k < n; ++k) {
        if (!std::isnan(path.values[k])) continue;
        std::ptrdiff_t before = k - 1, after = k + 1;
        while (before >= 0 && std::isnan(path.values[before])) --before;
        while (after < n && std::isnan(path.values[after])) ++after;
        if (before >= 0 && after < n) {
          const double t = static_cast<double>(k - before) / static_cast<double>(after - before);
          path.values[k] = (1 - t) * path.values[before] + t * path.values[after];
        } else if (before >= 0) {
          path.values[k] = path.values[before];
        } else if (after < n) {
          path.values[k] = path.values[after];
        }
      }
    }
  return paths;
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

void write_pictures(const std::filesystem::path& folder, const MapJobResult& result, int threads) {
  const Globe globe = globe_of(result);
  write_map_pictures(folder, globe,
                     viewer_data_for_map(result.prepared.mesh, result.map.sphere, globe.name, globe.properties),
                     threads);
}

}  // namespace spheremap::cli
