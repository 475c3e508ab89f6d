// The folder of one batch run (stage: pipeline): where it is, and what it holds. The folders are the
// state of a batch: a run is complete when its folder has `report.json` (written last, atomically) or
// `error.json`, pending otherwise.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "spheremap/pipeline/batch_inputs.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/pipeline/report.hpp"
#include "spheremap/sphere/map.hpp"

namespace spheremap {

/// The folder of one run: root/name with one weighting, root/name/<weights> (uniform, cotan,
/// mean-value) with several. Precondition: weighting < weights.size() (else std::out_of_range).
std::filesystem::path batch_run_folder(const std::filesystem::path& root, const BatchInput& input,
                                       const std::vector<Weights>& weights, std::size_t weighting);

/// Every folder an input may have used, whatever the weightings of earlier batches: root/name and
/// root/name/<each weighting>.
std::vector<std::filesystem::path> all_input_folders(const std::filesystem::path& root, const BatchInput& input);

/// The state of a run folder.
enum class RunStatus {
  kPending,       // neither report.json nor error.json: not run yet (or interrupted)
  kOk,            // report.json, certified
  kNotCertified,  // report.json, not certified (exit code 3)
  kError,         // error.json: refused, unreadable or internal error (its exit code: 1, 2 or 4)
};
/// "pending", "ok", "not-certified", "error" (the summary's `status`). Does not throw.
const char* to_string(RunStatus status);

/// Files a run folder may hold besides the outputs of write_map_outputs. `error.json` is
/// {"status": "error", "exit_code", "message", "input"}; `resources.json` ({"peak_rss_mb": ...}) is
/// written after report.json by the process that mapped the input, and is optional.
inline constexpr const char* kRunErrorFile = "error.json";
inline constexpr const char* kRunReportFile = kReportFile;
inline constexpr const char* kRunResourcesFile = "resources.json";
/// Every file a run writes (the outputs, error.json, resources.json).
const std::vector<std::string>& run_file_names();

/// What a run folder holds.
struct RunFolder {
  RunStatus status = RunStatus::kPending;
  std::optional<ReportSummary> report;  // kOk and kNotCertified
  int exit_code = 0;                    // 3 for kNotCertified, error.json's for kError
  std::string message;                  // kError: error.json's message, or why a file is unreadable
  std::optional<double> peak_rss_mb;    // resources.json, when there is one with the report
};

/// Reads a run folder. Never throws (but std::bad_alloc): an unreadable report.json (or one that
/// read_report refuses) or error.json counts as kError (exit code 4) with a message saying so and how
/// to redo it; a missing folder is kPending.
RunFolder read_run_folder(const std::filesystem::path& folder);

/// read_run_folder(folder).status.
RunStatus run_status(const std::filesystem::path& folder);

/// Writes `error.json` into `folder` (created if missing), atomically. Throws InputError if it cannot.
void write_run_error(const std::filesystem::path& folder, const std::filesystem::path& input, int exit_code,
                     const std::string& message);

/// Writes `resources.json` ({"peak_rss_mb": ...}) into the existing `folder`, atomically. Throws
/// InputError if it cannot.
void write_run_resources(const std::filesystem::path& folder, double peak_rss_mb);

/// Removes the files `<name>.tmp-<digits>` of `folder` whose <name> is in `known`: what an atomic write
/// leaves behind when its process is killed. A missing folder is left alone. Does not throw.
void remove_leftover_temporaries(const std::filesystem::path& folder, const std::vector<std::string>& known);

/// Removes what a run writes (report.json first: from then on the folder is pending) and its
/// leftovers, so that the folder is pending; other files are left alone, a missing folder too.
/// Throws InputError naming the file if one cannot be removed.
void clear_run_folder(const std::filesystem::path& folder);

}  // namespace spheremap
