#include "finish.hpp"

#include <cmath>
#include <utility>

namespace spheremap::detail {

Finished finish_map(const Mesh& mesh, InputStars& input, std::vector<Vec3> sphere, const MapOptions& options,
                    StageTimer* timer) {
  Finished finished;
  finished.superposition = superpose_sphere_on_surface(mesh.positions, sphere);
  for (auto& p : sphere) p = rotate(finished.superposition.rotation, p);
  if (timer) timer->lap("superpose");
  finished.certificate = certify_sphere_map(mesh, sphere, options.collapse_floor, &finished.solid_angles);
  if (options.repair && !finished.certificate.certified() && std::abs(finished.certificate.coverage - 1) < 1e-9) {
    finished.untangling_moves = untangle_on_sphere(mesh, input.rings(), input.untangling_frame(), sphere,
                                                   options.collapse_floor, options.max_untangling_sweeps);
    finished.untangled = true;
    if (timer) timer->lap("untangle");
    finished.certificate = certify_sphere_map(mesh, sphere, options.collapse_floor, &finished.solid_angles);
  }
  if (timer) timer->lap("certify");
  finished.sphere = std::move(sphere);
  return finished;
}

}  // namespace spheremap::detail
