// The default pictures of a map job (see map_pictures.hpp).
#include "spheremap/render/map_pictures.hpp"

#include <algorithm>
#include <functional>
#include <system_error>

#include <fmt/format.h>

#include "../util/parallel.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/atomic_file.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/render/hemispheres.hpp"
#include "spheremap/render/map_picture.hpp"
#include "spheremap/render/viewer.hpp"

namespace spheremap {

std::string featured_property(const Globe& globe) {
  for (const char* name : {"electrostatics", "sequence_position", "hydrophobicity", "b_factor"})
    if (find_globe_property(globe, name) != nullptr) return name;
  return "";
}

const std::vector<std::string>& default_map_properties() {
  static const std::vector<std::string> names{"electrostatics", "hydrophobicity", "sequence_position", "octant"};
  return names;
}

std::vector<std::filesystem::path> write_map_pictures(const std::filesystem::path& folder, const Globe& globe,
                                                      const ViewerData& viewer, int threads) {
  const std::filesystem::path pictures = folder / kPicturesFolder;
  std::error_code error;
  std::filesystem::create_directories(pictures, error);
  if (error)
    throw InputError(fmt::format("{}: cannot create the pictures folder: {}", pictures.string(), error.message()));
  MapFigureOptions options;
  options.threads = threads;
  const SphereLocator locator = make_sphere_locator(globe.sphere, globe.triangles, threads);
  const auto size = map_image_size(options);
  // One sampling serves every property's map.
  const MapSamples samples = sample_map(locator, Projection::mollweide, size[0], size[1], threads);
  const MapSamples grid = sample_grid(locator, Projection::mollweide, 360, 180, threads);
  // The files, in the order they are returned: each drawn on its own (each picture's bytes do not depend on which
  // thread draws it), then written in order.
  std::vector<std::filesystem::path> paths;
  std::vector<std::function<std::string()>> draw;  // empty: drawn already
  std::vector<std::string> bytes;                  // of each file, when drawn
  const auto& drawn = default_map_properties();
  std::vector<const SurfaceProperty*> mapped;
  std::vector<std::size_t> grid_files;  // where each mapped property's grid is in `paths`
  for (const SurfaceProperty& property : globe.properties) {
    if (std::find(drawn.begin(), drawn.end(), property.info.name) == drawn.end()) continue;
    const std::string stem = property.info.name + "-mollweide";
    paths.push_back(pictures / (stem + ".png"));
    draw.emplace_back([&] { return map_figure(globe, property, samples, options); });
    grid_files.push_back(paths.size());
    paths.push_back(pictures / (stem + ".tsv"));
    draw.emplace_back();  // the grids are made together (below)
    mapped.push_back(&property);
  }
  // The hemisphere figures share their rasterization: drawn together first, on every thread.
  std::vector<const SurfaceProperty*> hemisphere_properties{find_globe_property(globe, "octant")};
  if (const std::string featured = featured_property(globe); !featured.empty())
    hemisphere_properties.push_back(find_globe_property(globe, featured));
  std::erase(hemisphere_properties, nullptr);
  HemisphereOptions hemispheres;
  hemispheres.threads = threads;
  std::vector<std::string> figures = hemisphere_figures(globe, hemisphere_properties, hemispheres);
  bytes.resize(draw.size());
  for (std::size_t f = 0; f < figures.size(); ++f) {
    paths.push_back(pictures / (hemisphere_properties[f]->info.name + "-hemispheres.png"));
    draw.emplace_back();
    bytes.push_back(std::move(figures[f]));
  }
  paths.push_back(folder / kViewerFile);
  draw.emplace_back([&] { return viewer_html(viewer); });
  bytes.emplace_back();
  // The slowest first, so that the threads end together: the viewer, then the maps.
  std::vector<std::size_t> order;
  const auto queue = [&](const auto& wanted) {
    for (std::size_t i = 0; i < draw.size(); ++i)
      if (draw[i] && wanted(paths[i])) order.push_back(i);
  };
  queue([](const std::filesystem::path& path) { return path.extension() == ".html"; });
  queue([](const std::filesystem::path& path) { return path.extension() == ".png"; });
  // The grids share each cell's position and residues: one task for all of them, last, its rows on threads of its
  // own, so that a core done with the other tasks works on them instead of waiting.
  std::vector<std::string> grids;
  detail::parallel_chunks(static_cast<std::int64_t>(order.size()) + 1, detail::surface_threads(threads),
                          [&](std::int64_t k, int) {
                            if (k == static_cast<std::int64_t>(order.size())) {
                              grids = map_grid_tsvs(globe, mapped, grid, threads);
                              return;
                            }
                            const std::size_t i = order[static_cast<std::size_t>(k)];
                            bytes[i] = draw[i]();
                          });
  for (std::size_t m = 0; m < mapped.size(); ++m) bytes[grid_files[m]] = std::move(grids[m]);
  for (std::size_t i = 0; i < paths.size(); ++i) {
    write_file_atomically(paths[i], bytes[i]);
    bytes[i] = std::string();
  }
  return paths;
}

}  // namespace spheremap
