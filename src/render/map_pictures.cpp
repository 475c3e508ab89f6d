// The default pictures of a map job (see map_pictures.hpp).
#include "spheremap/render/map_pictures.hpp"

#include <algorithm>
#include <system_error>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/io/atomic_file.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/render/hemispheres.hpp"
#include "spheremap/render/map_picture.hpp"

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
  std::vector<std::filesystem::path> written;
  const auto write = [&](const std::filesystem::path& path, const std::string& bytes) {
    write_file_atomically(path, bytes);
    written.push_back(path);
  };
  MapFigureOptions options;
  options.threads = threads;
  const SphereLocator locator = make_sphere_locator(globe.sphere, globe.triangles);
  const auto size = map_image_size(options);
  // One sampling serves every property's map.
  const MapSamples samples = sample_map(locator, Projection::mollweide, size[0], size[1], threads);
  const MapSamples grid = sample_grid(locator, Projection::mollweide, 360, 180, threads);
  const auto& drawn = default_map_properties();
  for (const SurfaceProperty& property : globe.properties) {
    if (std::find(drawn.begin(), drawn.end(), property.info.name) == drawn.end()) continue;
    const std::string stem = property.info.name + "-mollweide";
    write(pictures / (stem + ".png"), map_figure(globe, property, samples, options));
    write(pictures / (stem + ".tsv"), map_grid_tsv(globe, property, grid));
  }
  HemisphereOptions hemispheres;
  hemispheres.threads = threads;
  std::vector<std::string> hemisphere_properties{"octant"};
  if (const std::string featured = featured_property(globe); !featured.empty())
    hemisphere_properties.push_back(featured);
  for (const std::string& name : hemisphere_properties)
    if (const SurfaceProperty* property = find_globe_property(globe, name))
      write(pictures / (name + "-hemispheres.png"), hemisphere_figure(globe, *property, hemispheres));
  write_viewer_html(folder / kViewerFile, viewer);
  written.push_back(folder / kViewerFile);
  return written;
}

}  // namespace spheremap
