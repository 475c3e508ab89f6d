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
  // The files, in the order they are returned: each drawn on its own (one picture per thread; each picture's
  // bytes do not depend on which thread draws it), then written in order.
  std::vector<std::filesystem::path> paths;
  std::vector<std::function<std::string()>> draw;
  const auto& drawn = default_map_properties();
  for (const SurfaceProperty& property : globe.properties) {
    if (std::find(drawn.begin(), drawn.end(), property.info.name) == drawn.end()) continue;
    const std::string stem = property.info.name + "-mollweide";
    paths.push_back(pictures / (stem + ".png"));
    draw.emplace_back([&] { return map_figure(globe, property, samples, options); });
    paths.push_back(pictures / (stem + ".tsv"));
    draw.emplace_back([&] { return map_grid_tsv(globe, property, grid, 1); });
  }
  HemisphereOptions hemispheres;
  hemispheres.threads = 1;  // the figures themselves run side by side
  std::vector<std::string> hemisphere_properties{"octant"};
  if (const std::string featured = featured_property(globe); !featured.empty())
    hemisphere_properties.push_back(featured);
  for (const std::string& name : hemisphere_properties)
    if (const SurfaceProperty* property = find_globe_property(globe, name)) {
      paths.push_back(pictures / (name + "-hemispheres.png"));
      draw.emplace_back([&globe, property, hemispheres] { return hemisphere_figure(globe, *property, hemispheres); });
    }
  paths.push_back(folder / kViewerFile);
  draw.emplace_back([&] { return viewer_html(viewer); });
  std::vector<std::string> bytes(draw.size());
  // The slowest first (the hemisphere figures and the viewer are last in the list), so that the threads end
  // together.
  detail::parallel_chunks(static_cast<std::int64_t>(draw.size()), detail::surface_threads(threads),
                          [&](std::int64_t k, int) {
                            const std::size_t i = draw.size() - 1 - static_cast<std::size_t>(k);
                            bytes[i] = draw[i]();
                          });
  for (std::size_t i = 0; i < paths.size(); ++i) {
    write_file_atomically(paths[i], bytes[i]);
    bytes[i] = std::string();
  }
  return paths;
}

}  // namespace spheremap
