// spheremap view FOLDER: (re)writes FOLDER/index.html, the viewer of a finished map, and prints its path.
#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "pictures.hpp"
#include "spheremap/pipeline/map_folder.hpp"
#include "spheremap/render/viewer_data.hpp"

namespace spheremap::cli {
namespace {

struct ViewCommand {
  static constexpr const char* kName = "view";
  static constexpr const char* kDescription =
      "Write FOLDER/index.html, the viewer of a finished map folder (open it in a browser; it works offline)";

  std::string folder;
  void add(CLI::App* command) {
    command->add_option("folder", folder, "A folder `spheremap map` wrote (surface.ply, sphere.ply, report.json)")
        ->required();
  }
  int run() {
    const MapFolder map = read_map_folder(folder);
    const std::filesystem::path path = std::filesystem::path(folder) / "index.html";
    const Globe globe = globe_of(map);  // the properties the pictures show
    write_viewer_html(path, viewer_data_for_map(map.surface, map.sphere, map.name, globe.properties));
    std::cout << path.string() << "\n";
    return 0;
  }
};

}  // namespace

Command add_view_command(CLI::App& app) { return make_command<ViewCommand>(app); }

}  // namespace spheremap::cli
