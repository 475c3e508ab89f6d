// Private to src/pipeline: root/batch.json, the options a batch root was made with.
#pragma once

#include <filesystem>

#include "spheremap/pipeline/batch.hpp"

namespace spheremap::pipeline_detail {

/// Throws InputError unless root/batch.json is absent, or holds the same options (batch_options_json),
/// or options.force (the message lists the options that differ). Returns whether batch.json must be
/// (re)written, which run_batch does only after --force has cleared the old outputs: a batch killed in
/// between must not find old outputs under new options.
bool check_batch_manifest(const std::filesystem::path& root, const BatchOptions& options);

/// Writes root/batch.json atomically. Throws InputError if it cannot.
void write_batch_manifest(const std::filesystem::path& root, const BatchOptions& options);

}  // namespace spheremap::pipeline_detail
