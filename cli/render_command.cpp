// spheremap render FOLDER --property P: a picture of one property of a finished map, without mapping again.
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "commands.hpp"
#include "pictures.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/atomic_file.hpp"
#include "spheremap/render/hemispheres.hpp"
#include "spheremap/render/map_picture.hpp"

namespace spheremap::cli {
namespace {

struct RenderCommand {
  static constexpr const char* kName = "render";
  static constexpr const char* kDescription =
      "Draw a property of a finished map folder: a map of the whole globe (PNG, SVG or PDF, with its numeric grid "
      "as TSV) or the hemisphere figure";

  std::string folder, property = "octant", projection = "mollweide", range, size, format = "png", outline, output;
  bool hemispheres = false, trace = false;
  void add(CLI::App* command);
  int run();
};

void RenderCommand::add(CLI::App* command) {
  command->add_option("folder", folder, "A folder `spheremap map` wrote (surface.ply, sphere.ply, report.json)")
      ->required();
  command->add_option("--property", property, "The property to draw (default octant); a wrong name lists them");
  command->add_option("--projection", projection,
                      "mollweide (default, equal-area), equirectangular (plate carrée) or sinusoidal (Flamsteed)");
  command->add_flag("--hemispheres", hemispheres,
                    "Draw the hemisphere figure (surface and globe from two opposite sides) instead of a map");
  command->add_flag("--trace", trace,
                    "With --hemispheres: a fifth panel, the backbone (CA trace) coloured alike, from the structure "
                    "file report.json names");
  command->add_option("--range", range, "Colour range LO,HI (values outside saturate), e.g. --range -5,5");
  command->add_option("--size", size, "Figure size WIDTHxHEIGHT in pixels (default 2048x1024; hemispheres 1600x1600)");
  command->add_option("--format", format, "png (default), svg or pdf");
  command->add_option("--outline", outline, "Outline residues on a map, e.g. A:45-60,B:12");
  command->add_option("-o,--output", output,
                      "The picture's file (default FOLDER/pictures/<property>-<projection>.<format>; the TSV grid "
                      "beside it, same name, .tsv)");
}

int RenderCommand::run() {
  // Every option is checked before anything is read or written.
  const auto parsed_projection = parse_projection(projection);
  if (!parsed_projection)
    throw InputError(fmt::format("--projection '{}': expected mollweide, equirectangular or sinusoidal", projection));
  const auto parsed_format = parse_image_format(format);
  if (!parsed_format) throw InputError(fmt::format("--format '{}': expected png, svg or pdf", format));
  std::optional<ValueRange> parsed_range;
  if (!range.empty()) parsed_range = parse_range(range);
  std::optional<std::array<int, 2>> parsed_size;
  if (!size.empty()) parsed_size = parse_size(size);
  if (hemispheres && !outline.empty()) throw InputError("--outline applies to maps, not to --hemispheres");
  if (trace && !hemispheres) throw InputError("--trace applies to --hemispheres only");
  std::vector<ResidueRange> outline_ranges;
  if (!outline.empty()) outline_ranges = parse_residue_selection(outline);

  const MapFolder map = read_map_folder(folder);
  const Globe globe = globe_of(map);
  const SurfaceProperty* chosen = find_globe_property(globe, property);
  if (chosen == nullptr)
    throw InputError(fmt::format("--property '{}': {} has no such property; it has {}", property, folder,
                                 globe_property_names(globe)));
  const std::string stem = property + "-" + (hemispheres ? "hemispheres" : std::string(to_string(*parsed_projection)));
  const std::filesystem::path path = output.empty() ? std::filesystem::path(folder) / "pictures" /
                                                          (stem + "." + std::string(to_string(*parsed_format)))
                                                    : std::filesystem::path(output);
  std::string picture, grid;
  if (hemispheres) {
    HemisphereOptions options;
    options.format = *parsed_format;
    options.range = parsed_range;
    if (parsed_size) options.width = (*parsed_size)[0], options.height = (*parsed_size)[1];
    if (trace) {
      const auto input = map.report.find("input");
      if (input == map.report.end() || !input->is_string())
        throw InputError(fmt::format("--trace: {}/report.json names no input structure", folder));
      options.trace = backbone_trace(globe, *chosen, input->get<std::string>());
      if (!parsed_size) options.width = 2100, options.height = 1500;
    }
    picture = hemisphere_figure(globe, *chosen, options);
  } else {
    MapFigureOptions options;
    options.format = *parsed_format;
    options.range = parsed_range;
    if (parsed_size) options.width = (*parsed_size)[0], options.height = (*parsed_size)[1];
    if (!outline_ranges.empty()) {
      options.outline = select_residues(globe, outline_ranges, "--outline");
      options.outline_label = outline;
    }
    const auto image = map_image_size(options);
    const SphereLocator locator = make_sphere_locator(globe.sphere, globe.triangles);
    picture = map_figure(globe, *chosen, sample_map(locator, *parsed_projection, image[0], image[1]), options);
    grid = map_grid_tsv(globe, *chosen, locator, *parsed_projection);
  }
  std::error_code error;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), error);
  write_file_atomically(path, picture);
  std::cout << path.string() << "\n";
  if (!grid.empty()) {
    std::filesystem::path tsv = path;
    tsv.replace_extension(".tsv");
    write_file_atomically(tsv, grid);
    std::cout << tsv.string() << "\n";
  }
  return 0;
}

}  // namespace

Command add_render_command(CLI::App& app) { return make_command<RenderCommand>(app); }

}  // namespace spheremap::cli
