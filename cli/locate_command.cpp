// spheremap locate FOLDER --lat LAT --lon LON | --residue A:45: what lies under a point of the globe, or
// where a residue lies on it.
#include <cmath>
#include <iostream>

#include <fmt/format.h>

#include "commands.hpp"
#include "pictures.hpp"
#include "spheremap/error.hpp"
#include "spheremap/render/locate.hpp"
#include "spheremap/render/residue_selection.hpp"

namespace spheremap::cli {
namespace {

struct LocateCommand {
  static constexpr const char* kName = "locate";
  static constexpr const char* kDescription =
      "In a finished map folder: the residue under a point of the globe (--lat, --lon in degrees), or where a "
      "residue lies on the globe (--residue A:45)";

  std::string folder, residue;
  std::optional<double> latitude, longitude;
  void add(CLI::App* command);
  int run();
};

void LocateCommand::add(CLI::App* command) {
  command->add_option("folder", folder, "A folder `spheremap map` wrote (surface.ply, sphere.ply, report.json)")
      ->required();
  command->add_option("--lat", latitude, "Latitude in degrees, -90 (south, -z) to 90 (north, +z)");
  command->add_option("--lon", longitude, "Longitude in degrees, -180 to 180 (0 on +x, 90 on +y)");
  command->add_option("--residue", residue, "A residue CHAIN:NUMBER[INSERTION], e.g. A:45 or H:52A");
}

std::string degrees(double radians) { return fmt::format("{:.2f}", radians / kDegree); }

std::string value_text(double value) { return std::isnan(value) ? "no value" : fmt::format("{:.6g}", value); }

int locate_point_command(const Globe& globe, double lat, double lon) {
  const SphereLocator locator = make_sphere_locator(globe.sphere, globe.triangles);
  const PointLocation at = locate_point(globe, locator, {lat * kDegree, lon * kDegree});
  if (at.hit.triangle < 0) throw InputError("the map has no triangle there (an empty or broken map?); map again");
  std::cout << fmt::format("latitude {:.2f}, longitude {:.2f}: triangle {}, nearest vertex {}\n", lat, lon,
                           at.hit.triangle, at.vertex);
  if (at.residue >= 0) {
    const ResidueLabel& r = globe.residues[at.residue];
    std::cout << fmt::format("residue {} {}\n", residue_id(r), r.name);
    std::string corners;
    for (const std::int32_t c : at.corner_residues)
      corners += (corners.empty() ? "" : ", ") + residue_id(globe.residues[c]);
    std::cout << "residues of the triangle's corners: " << corners << "\n";
  } else {
    std::cout << "residue: none (" << (globe.residues.empty() ? no_residues_text(globe) : "no atom there") << ")\n";
  }
  for (std::size_t k = 0; k < globe.properties.size(); ++k) {
    const auto& info = globe.properties[k].info;
    std::string text = value_text(at.values[k]);
    if (info.scale == ScaleKind::categorical && !std::isnan(at.values[k])) {
      const auto c = static_cast<std::size_t>(at.values[k]);
      if (c < info.categories.size()) text += " (" + info.categories[c] + ")";
    }
    std::cout << fmt::format("{} {}{}\n", info.name, text, info.unit.empty() ? "" : " " + info.unit);
  }
  return 0;
}

int locate_residue_command(const Globe& globe, const std::string& text) {
  const std::vector<ResidueRange> ranges = parse_residue_selection(text);
  if (ranges.size() != 1 || ranges[0].first != ranges[0].last || ranges[0].first_insertion != ranges[0].last_insertion)
    throw InputError(fmt::format("--residue '{}': give one residue, e.g. A:45", text));
  const std::vector<std::int32_t> found = select_residues(globe, ranges, "--residue");
  for (const std::int32_t r : found) {
    const ResidueLabel& label = globe.residues[r];
    const auto extent = residue_extent(globe, r);
    if (!extent) {
      std::cout << fmt::format("residue {} {}: not on the surface (buried)\n", residue_id(label), label.name);
      continue;
    }
    std::cout << fmt::format(
        "residue {} {}: centre latitude {}, longitude {}; {} vertices within {}° of the centre; latitude {} to {}, "
        "longitude {} to {}{}\n",
        residue_id(label), label.name, degrees(extent->centre.latitude), degrees(extent->centre.longitude),
        extent->vertices, degrees(extent->radius), degrees(extent->latitude_lo), degrees(extent->latitude_hi),
        degrees(extent->longitude_lo), degrees(extent->longitude_hi),
        extent->longitude_lo > extent->longitude_hi ? " (across ±180°)" : "");
  }
  return 0;
}

int LocateCommand::run() {
  const bool point = latitude.has_value() || longitude.has_value();
  if (point == !residue.empty())
    throw InputError("give either --lat and --lon, or --residue (e.g. spheremap locate out/ --lat 12.5 --lon -40)");
  if (point && (!latitude || !longitude)) throw InputError("--lat and --lon go together: give both");
  if (point && !(std::abs(*latitude) <= 90))
    throw InputError(fmt::format("--lat {}: it must be in -90..90", *latitude));
  if (point && !(std::abs(*longitude) <= 180))
    throw InputError(fmt::format("--lon {}: it must be in -180..180", *longitude));
  if (!residue.empty()) parse_residue_selection(residue);  // a typo fails before the folder is read
  const Globe globe = globe_of(read_map_folder(folder));
  return point ? locate_point_command(globe, *latitude, *longitude) : locate_residue_command(globe, residue);
}

}  // namespace

Command add_locate_command(CLI::App& app) { return make_command<LocateCommand>(app); }

}  // namespace spheremap::cli
