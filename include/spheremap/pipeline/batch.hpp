// Batch runs: many inputs, several weightings, in parallel, resumable (stage: io; the `batch` command).
//
// The output root holds one folder per input (with several weightings, one subfolder per weighting),
// each with the outputs of `spheremap map` (write_map_outputs) or an `error.json`, plus `batch.json`
// (the options of the batch), `summary.csv` and `summary.jsonl`. The folders are the state: a run is
// complete when its folder has `report.json` (written last, atomically) or `error.json`; the summary is
// always rebuilt from the folders, so a resumed batch gives the same summary as an uninterrupted one
// (up to the measured timings of what was redone).
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spheremap/pipeline/map_job.hpp"

namespace spheremap {

/// True for the files a batch takes from a folder: meshes (.obj .off .ply .stl, any case) and
/// structures (is_structure_file: .pdb .ent .cif .mmcif .pqr, optionally .gz).
bool is_batch_input_file(const std::filesystem::path& path);

/// Expands command-line arguments into input files, in order, each file once (the first occurrence
/// wins; compared after std::filesystem::weakly_canonical):
/// - an existing folder: its mesh and structure files (is_batch_input_file), not recursive, hidden
///   files (name starting with '.') left out, sorted by file name (byte order);
/// - `@LIST`, or an existing file whose name ends in `.txt`: a list, one argument per line (blank lines
///   and lines starting with '#' ignored, surrounding spaces trimmed), each expanded by these same rules;
///   relative paths are relative to the list's folder; lists may include lists (8 levels at most);
/// - an argument that is not an existing path but contains `*`, `?` or `[`: a glob(3) pattern; its
///   matches, sorted (byte order), are expanded like arguments (as if the shell had expanded it:
///   files are taken whatever their extension, folders give their files);
/// - anything else: a file, taken as given, even if missing or of an unknown format (its run then
///   fails with the reader's message, like `spheremap map`).
/// Throws InputError if a list cannot be read, lists nest too deeply, or the result is empty.
std::vector<std::filesystem::path> expand_batch_inputs(const std::vector<std::string>& arguments);

struct BatchInput {
  std::filesystem::path path;
  std::string name;  // its output folder, under the output root
};

/// Output folder names, unique under the root: the file name without `.gz` and without its extension
/// (`1crn.cif.gz` -> `1crn`). Inputs whose names clash (compared case-insensitively, also with the
/// root's own files summary.csv, summary.jsonl and batch.json) all use their whole file name instead
/// (`1abc.pdb`, `1abc.cif`); if those still clash (the same file name in two folders), the second,
/// third, ... in input order get `~2`, `~3`, ... appended. Names therefore depend on the set of inputs,
/// not on their order, except for that last rule.
std::vector<BatchInput> name_batch_inputs(const std::vector<std::filesystem::path>& paths);

/// The folder of one run: root/name with one weighting, root/name/<weights> (uniform, cotan,
/// mean-value) with several.
std::filesystem::path batch_run_folder(const std::filesystem::path& root, const BatchInput& input,
                                       const std::vector<Weights>& weights, std::size_t weighting);

/// The state of a run folder.
enum class RunStatus {
  kPending,       // neither report.json nor error.json: not run yet (or interrupted)
  kOk,            // report.json, certified
  kNotCertified,  // report.json, not certified (exit code 3)
  kError,         // error.json: refused, unreadable or internal error (its exit code: 1, 2 or 4)
};
const char* to_string(RunStatus status);  // "pending", "ok", "not-certified", "error"

/// Files a run folder may hold; `error.json` is {"status": "error", "exit_code", "message", "input"}.
inline constexpr const char* kRunErrorFile = "error.json";
inline constexpr const char* kRunReportFile = "report.json";

/// The status of a run folder (never throws: an unreadable report.json or error.json counts as kError
/// with a message saying so; a missing folder is kPending).
RunStatus run_status(const std::filesystem::path& folder);

/// Writes `error.json` into `folder` (created if missing), atomically. Throws InputError if it cannot.
void write_run_error(const std::filesystem::path& folder, const std::filesystem::path& input, int exit_code,
                     const std::string& message);

/// The columns of summary.csv (and the keys of each summary.jsonl line), in order. See the README
/// ("Batch runs") for their meaning.
const std::vector<std::string>& summary_columns();

/// One row: an object with exactly summary_columns() as keys (null where not applicable), built from
/// the run folder only (report.json or error.json; status "pending" and nulls when neither exists).
nlohmann::ordered_json summary_row(const BatchInput& input, Weights weights, const std::filesystem::path& root,
                                   const std::filesystem::path& folder);

/// All rows: inputs in order, then weightings in order.
std::vector<nlohmann::ordered_json> build_summary(const std::filesystem::path& root,
                                                  const std::vector<BatchInput>& inputs,
                                                  const std::vector<Weights>& weights);

/// summary.csv text: a header line, then one line per row; RFC 4180 quoting (a field holding a comma,
/// a double quote, a line break or leading/trailing spaces is quoted, quotes doubled), LF line ends,
/// UTF-8; numbers as in JSON (shortest text that reads back the same double), null as an empty field.
std::string summary_csv(const std::vector<nlohmann::ordered_json>& rows);
/// summary.jsonl text: one JSON object per line (the same keys and values as the CSV).
std::string summary_jsonl(const std::vector<nlohmann::ordered_json>& rows);

/// Builds the summary from the folders and writes summary.csv and summary.jsonl into `root`, each
/// atomically. Returns the rows. Throws InputError if a file cannot be written.
std::vector<nlohmann::ordered_json> write_batch_summary(const std::filesystem::path& root,
                                                        const std::vector<BatchInput>& inputs,
                                                        const std::vector<Weights>& weights);

/// The exit code of a batch from its rows: the first of 4 (internal error), 1 (unreadable input),
/// 2 (refused mesh), 3 (not certified) that some row has, else 0. A pending row counts as 4 (a run
/// that could not record its result); an interrupted batch is the caller's business (130).
int batch_exit_code(const std::vector<nlohmann::ordered_json>& rows);

/// Holds an exclusive lock (flock on `root/.batch.lock`, created with `root` if missing) so that two
/// batches never write into the same root; released on destruction or when the process ends, however.
/// Throws InputError if the root cannot be created or another process holds the lock.
class BatchLock {
 public:
  explicit BatchLock(const std::filesystem::path& root);
  ~BatchLock();
  BatchLock(const BatchLock&) = delete;
  BatchLock& operator=(const BatchLock&) = delete;
  /// In a process forked while the lock is held: closes this process's copy of the lock's descriptor, so
  /// that the lock ends with the process that took it, not with the last of its children (a flock
  /// belongs to the open file, which a fork shares). Does not throw.
  void forget_in_child() const noexcept;

 private:
  int descriptor_ = -1;
};

struct BatchOptions {
  MapJobOptions job;  // job.map.weights is ignored: see weights
  std::vector<Weights> weights = {Weights::kUniform};  // at least one, no repeats
  int jobs = 1;                // worker threads (at least 1; no more are started than inputs to run)
  bool force = false;          // redo every input: every run folder is cleared first
  bool retry_errors = false;   // redo runs with error.json (cleared first)
  /// Map each input in a child process (fork) supervised by its worker thread, instead of in the worker
  /// thread itself. Concurrent maps in one process are NOT reproducible with Debian 12's CHOLMOD and
  /// serial OpenBLAS (measured: 22 of 470 runs mapped differently, 3 of them not certified), while
  /// separate processes are; a crash or an out-of-memory kill then also costs one input, not the batch.
  bool isolate = true;
};

/// The options that decide the outputs, as stored in root/batch.json (weights, solver, repair, collapse
/// floor, welding, component, ASCII, structure selection, radii, probe, grid, keep_topology).
nlohmann::ordered_json batch_options_json(const BatchOptions& options);

/// What happened to one input in this session.
struct BatchInputOutcome {
  std::size_t index = 0;                    // into the inputs
  std::vector<RunStatus> statuses;          // per weighting (all of them, including runs done earlier)
  int exit_code = 0;                        // of the error, when an error happened
  std::string message;                      // the error's message
  double seconds = 0;                       // wall clock of this input in this session
};

struct BatchProgress {
  std::size_t inputs = 0;          // all inputs
  std::size_t already_done = 0;    // complete before this session started (skipped)
  std::size_t finished = 0;        // finished in this session
  std::size_t running = 0;
  std::size_t errors = 0;          // inputs with an error run (this session and before)
  std::size_t not_certified = 0;   // inputs with a run not certified (this session and before)
  double elapsed_seconds = 0;      // of this session
  bool stopping = false;           // a stop was requested: no new input is started
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
