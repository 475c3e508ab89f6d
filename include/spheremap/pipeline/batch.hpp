// Batch runs: many inputs, several weightings, in parallel, resumable (stage: pipeline; the `batch`
// command). The parts: batch_inputs.hpp (inputs and their names), run_folder.hpp (the state of each run),
// summary.hpp (summary.csv, summary.jsonl, exit code), batch_lock.hpp; this header runs them.
//
// The output root holds one folder per input (with several weightings, one subfolder per weighting),
// each with the outputs of `spheremap map` (write_map_outputs) or an `error.json`, plus `batch.json`
// (the options of the batch), `summary.csv` and `summary.jsonl`. The folders are the state: a run is
// complete when its folder has `report.json` (written last, atomically) or `error.json`; the summary is
// always rebuilt from the folders, so a resumed batch gives the same summary as an uninterrupted one
// (up to the measured timings of what was redone).
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spheremap/pipeline/batch_inputs.hpp"
#include "spheremap/pipeline/batch_lock.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/pipeline/run_folder.hpp"
#include "spheremap/pipeline/summary.hpp"

namespace spheremap {

struct BatchOptions {
  MapJobOptions job;                                   // job.map.weights is ignored: see weights
  std::vector<Weights> weights = {Weights::kUniform};  // at least one, no repeats
  int jobs = 1;               // worker threads (at least 1; no more are started than inputs to run)
  bool force = false;         // redo every input: every run folder is cleared first
  bool retry_errors = false;  // redo runs with error.json (cleared first)
  /// Map each input in a child process (fork) supervised by its worker thread, instead of in the worker
  /// thread itself. Concurrent maps in one process are NOT reproducible with Debian 12's CHOLMOD and
  /// serial OpenBLAS, while separate processes are; a crash or an out-of-memory kill then also costs one
  /// input, not the batch.
  bool isolate = true;
  /// Extra outputs of each run (the CLI's pictures and viewer: pipeline/ draws nothing), written into the run's
  /// folder before its map outputs, so that report.json, written last, still marks a complete run. A throw
  /// fails the run like a map error (error.json). Unset: none; batch.json then records "pictures": false.
  std::function<void(const std::filesystem::path& folder, const MapJobResult& result)> write_pictures;
};

/// The options that decide the outputs, as stored in root/batch.json (weights, solver, repair, collapse
/// floor, welding, component, ASCII, structure selection, radii, strict, probe, grid, keep_topology,
/// simplification, and "pictures": false when write_pictures is unset). Does not throw (but std::bad_alloc).
nlohmann::ordered_json batch_options_json(const BatchOptions& options);

/// What happened to one input in this session.
struct BatchInputOutcome {
  std::size_t index = 0;              // into the inputs
  std::vector<RunStatus> statuses;    // per weighting (all of them, including runs done earlier)
  int exit_code = 0;                  // of the error, when an error happened
  std::string message;                // the error's message
  std::vector<std::string> warnings;  // about the input file (report.json's structure.warnings)
  double seconds = 0;                 // wall clock of this input in this session
};

struct BatchProgress {
  std::size_t inputs = 0;        // all inputs
  std::size_t already_done = 0;  // complete before this session started (skipped)
  std::size_t finished = 0;      // finished in this session
  std::size_t running = 0;
  std::size_t errors = 0;         // inputs with an error run (this session and before)
  std::size_t not_certified = 0;  // inputs with a run not certified (this session and before)
  double elapsed_seconds = 0;     // of this session
  bool stopping = false;          // a stop was requested: no new input is started
};

enum class BatchStop {
  kContinue,
  kFinishRunning,  // start no new input; the running ones finish and write their outputs
};

struct BatchCallbacks {
  /// Called on the calling thread when an input finishes (in completion order).
  std::function<void(const BatchInputOutcome&, const BatchProgress&)> on_finished;
  /// Called on the calling thread about every `tick_seconds` while inputs run, and once at the start.
  std::function<void(const BatchProgress&)> on_tick;
  /// Polled on the calling thread (with on_tick and after each finished input).
  std::function<BatchStop()> stop;
  double tick_seconds = 0.2;
};

struct BatchResult {
  std::vector<nlohmann::ordered_json> rows;  // the summary as written
  int exit_code = 0;                         // batch_exit_code(rows), or 0 for an empty batch
  bool stopped = false;                      // a stop was requested and some input was left pending
  BatchProgress progress;                    // at the end
};

/// Runs a batch into `root`: locks it (BatchLock), checks root/batch.json (if present and made with other
/// options, throws InputError unless options.force; writes it otherwise), removes leftover temporary
/// files (`*.tmp-<pid>`) of earlier interrupted runs, clears what --force/--retry-errors redo, then maps
/// every input that has a pending run with run_map_jobs (its pending weightings only), in
/// `options.jobs` threads pulling inputs in order from a queue. A failing input never stops the others:
/// its error (spheremap::Error: its exit code; any other exception: "internal error: ...", exit code 4)
/// goes to error.json in each of its pending run folders; with options.isolate, so does a child process
/// that crashes or is killed (SIGKILL: out of memory), while one ended by SIGTERM, SIGINT, SIGHUP or
/// SIGQUIT leaves its runs pending. Before an input runs, its pending folders are
/// cleared of stale outputs. The summary is rewritten from the folders at the end (and at most every 30 s
/// while running). Preconditions: options.weights non-empty without repeats, options.jobs >= 1, input
/// names unique (name_batch_inputs). Throws InputError (root not writable, locked, options differ) and
/// std::invalid_argument (preconditions) before anything runs.
BatchResult run_batch(const std::filesystem::path& root, const std::vector<BatchInput>& inputs,
                      const BatchOptions& options, const BatchCallbacks& callbacks = {});

}  // namespace spheremap
