// root/batch.json: the options that decide a batch's outputs, written once and checked on every resume.
#include "batch_manifest.hpp"

#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "detail.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/atomic_file.hpp"

namespace spheremap {
namespace {

using namespace pipeline_detail;

Json component_json(const ComponentChoice& choice) {
  switch (choice.mode) {
    case ComponentChoice::Mode::kLargest: return "largest";
    case ComponentChoice::Mode::kRefuse: return "refuse";
    case ComponentChoice::Mode::kNumbered: return choice.number;
  }
  return nullptr;
}

// "grid 0.5 (was 2.5), weights [...] (was [...])": the options that differ, for the refusal message.
std::string option_differences(const Json& now, const Json& before, const std::string& prefix = "") {
  std::string text;
  auto add = [&](const std::string& part) { text += (text.empty() ? "" : ", ") + part; };
  if (!now.is_object() || !before.is_object()) {
    if (now != before) add(fmt::format("{} {} (was {})", prefix.empty() ? "options" : prefix, dump(now), dump(before)));
    return text;
  }
  for (const auto& [key, value] : now.items()) {
    const std::string name = prefix.empty() ? key : prefix + "." + key;
    const auto it = before.find(key);
    if (it == before.end())
      add(fmt::format("{} {} (not set before)", name, dump(value)));
    else if (value.is_object() && it->is_object()) {
      const auto inner = option_differences(value, *it, name);
      if (!inner.empty()) add(inner);
    } else if (value != *it)
      add(fmt::format("{} {} (was {})", name, dump(value), dump(*it)));
  }
  for (const auto& [key, value] : before.items())
    if (now.find(key) == now.end())
      add(fmt::format("{} no longer set (was {})", prefix.empty() ? key : prefix + "." + key, dump(value)));
  return text;
}

}  // namespace

nlohmann::ordered_json batch_options_json(const BatchOptions& options) {
  const auto& job = options.job;
  Json weights = Json::array();
  for (const Weights w : options.weights) weights.push_back(to_string(w));
  Json radii = nullptr;
  if (job.structure.radii) {
    radii = Json::object();
    for (const auto& [element, radius] : *job.structure.radii) radii[element] = radius;
  }
  nlohmann::ordered_json json = {
      {"weights", weights},
      {"solver", to_string(job.map.solver)},
      {"repair", job.map.repair},
      {"collapse_floor", job.map.collapse_floor},
      {"max_equalizing_rounds", job.map.max_equalizing_rounds},
      {"weld_tolerance", job.prepare.weld_tolerance},
      {"component", component_json(job.prepare.component)},
      {"ascii", job.ascii},
      {"structure",
       {{"model", job.structure.model},
        {"chains", job.structure.chains},
        {"keep_hydrogens", job.structure.keep_hydrogens ? Json(*job.structure.keep_hydrogens) : Json(nullptr)},
        {"keep_waters", job.structure.keep_waters},
        {"keep_hetero", job.structure.keep_hetero},
        {"radii", radii}}},
      {"surface",
       {{"probe", job.surface.probe},
        {"grid", job.surface.grid},
        {"carve_cavities", job.surface.carve_cavities},
        {"contour_minimum_fraction", job.surface.contour_minimum_fraction}}},
      {"keep_topology", job.keep_topology},
      {"simplify",
       {{"target_edge_length", job.simplify.target_edge_length},
        {"max_error", job.simplify.max_error},
        {"mesh_files", job.simplify_mesh_files}}},
  };
  // Only an objective other than the paper's map is written, so that batches made before it resume.
  if (job.map.objective != MapObjective::kPaper) {
    json["objective"] = to_string(job.map.objective);
    json["objective_max_iterations"] = job.map.objective_max_iterations;
  }
  // Only when set: a batch.json written before --strict existed still matches the same options.
  if (job.structure.strict) json["structure"]["strict"] = true;
  // Only without pictures: a batch.json written before batches drew pictures matches the default.
  if (!options.write_pictures) json["pictures"] = false;
  return json;
}

namespace pipeline_detail {

bool check_batch_manifest(const fs::path& root, const BatchOptions& options) {
  const fs::path path = root / kBatchManifestFile;
  const Json options_now = batch_options_json(options);
  std::error_code ec;
  if (fs::exists(path, ec)) {
    std::string differences;
    try {
      const auto text = read_text(path);
      if (!text) throw std::runtime_error("cannot read it");
      const Json before = Json::parse(*text);
      if (before.value("options", Json()) == options_now) return false;  // same options: nothing to write
      differences = option_differences(options_now, before.value("options", Json::object()));
    } catch (const std::exception& e) {
      differences = fmt::format("its batch.json is unreadable ({})", e.what());
    }
    if (!options.force)
      throw InputError(
          fmt::format("{}: this folder holds a batch made with other options: {}. Use another -o folder, "
                      "or --force to redo every input with the new options",
                      root.string(), differences));
  }
  return true;
}

void write_batch_manifest(const fs::path& root, const BatchOptions& options) {
  const Json manifest = {{"spheremap_version", "0.1.0"}, {"options", batch_options_json(options)}};
  write_file_atomically(root / kBatchManifestFile, dump(manifest, 2) + "\n");
}

}  // namespace pipeline_detail
}  // namespace spheremap
