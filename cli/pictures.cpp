// Pictures and viewer of a map job (see pictures.hpp).
#include "pictures.hpp"

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

void write_pictures(const std::filesystem::path& folder, const MapJobResult& result) {
  const Globe globe = globe_of(result);
  write_map_pictures(folder, globe, viewer_data_for_map(result.prepared.mesh, result.map.sphere, globe.name));
}

}  // namespace spheremap::cli
