// One input of a batch: its pending runs mapped and written (or error.json in each), in the calling
// thread or in a child process that the calling thread supervises.
#include "batch_worker.hpp"

#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>

#include "../util/stage_timer.hpp"
#include "detail.hpp"

namespace spheremap::pipeline_detail {
namespace {

// The runs of `input` under `root`, by weighting.
struct InputRuns {
  const fs::path& root;
  const BatchInput& input;
  const std::vector<Weights>& weights;
  fs::path folder(std::size_t k) const { return batch_run_folder(root, input, weights, k); }
  // If even error.json cannot be written, the run stays pending (and the batch exits 4).
  void record_error(std::size_t k, const Failure& f) const {
    capture([&] { write_run_error(folder(k), input.path, f.exit_code, f.message); });
  }
};

// Peak memory of the process that mapped this input (meaningful with isolation: one input per process),
// beside each run that wrote a report.
void record_peak_memory(const InputRuns& runs, const std::vector<std::size_t>& pending) {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  const double megabytes = std::round(static_cast<double>(usage.ru_maxrss) / 1024.0 * 10) / 10;
  for (const auto k : pending) {
    const auto status = run_status(runs.folder(k));
    if (status == RunStatus::kPending || status == RunStatus::kError) continue;
    capture([&] { write_run_resources(runs.folder(k), megabytes); });
  }
}

// The work of one input: its pending runs mapped and written, or error.json in each. Never throws;
// what happened is on disk (the parent of an isolated run reads it from there).
void map_input(const InputRuns& runs, const std::vector<std::size_t>& pending, const BatchOptions& options) {
  std::vector<Weights> pending_weights;
  for (const auto k : pending) pending_weights.push_back(runs.weights[k]);
  std::optional<Failure> failure = capture([&] {
    for (const auto k : pending) clear_run_folder(runs.folder(k));
  });
  std::vector<MapJobResult> results;
  if (!failure) failure = capture([&] { results = run_map_jobs(runs.input.path, options.job, pending_weights); });
  for (std::size_t j = 0; j < pending.size(); ++j) {
    if (failure) {
      runs.record_error(pending[j], *failure);
      continue;
    }
    MapJobOptions weighted = options.job;
    weighted.map.weights = pending_weights[j];
    const auto written = capture([&] {
      if (options.write_pictures) options.write_pictures(runs.folder(pending[j]), results[j]);
      write_map_outputs(runs.folder(pending[j]), results[j], weighted);
    });
    results[j] = MapJobResult{};  // free the mesh and the map early
    if (written) {
      capture([&] { clear_run_folder(runs.folder(pending[j])); });  // no partial output: pictures written first go
      runs.record_error(pending[j], *written);
    }
  }
  if (!failure && options.isolate) record_peak_memory(runs, pending);
}

// After a child died of `signal`: a crash, or the out-of-memory killer (SIGKILL), is this input's
// error; a termination or interrupt sent to the process group leaves its runs pending, to be redone
// on resume.
void record_child_death(const InputRuns& runs, const std::vector<std::size_t>& pending, int signal) {
  if (signal == SIGTERM || signal == SIGINT || signal == SIGHUP || signal == SIGQUIT) return;
  const Failure f{4, fmt::format("internal error: the process mapping this input died of signal {} ({}){}", signal,
                                 ::strsignal(signal),
                                 signal == SIGKILL ? "; out of memory? run fewer inputs at once (--jobs) or use a "
                                                     "coarser --grid"
                                                   : "")};
  for (const auto k : pending)
    if (run_status(runs.folder(k)) == RunStatus::kPending) runs.record_error(k, f);
}

// In a child process: the forked image has only this thread; it maps, writes and leaves with _exit
// (no atexit handlers, no flushing of the parent's buffers). It dies with the batch (PDEATHSIG), and
// ignores Ctrl-C, which the terminal sends to the whole process group: the batch decides.
void map_input_in_child(const InputRuns& runs, const std::vector<std::size_t>& pending, const BatchOptions& options,
                        const BatchLock& lock) {
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    // A batch killed at once is resumed at once: its lock must not outlive it in a child still dying.
    lock.forget_in_child();
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(0);
    ::signal(SIGINT, SIG_IGN);
    ::signal(SIGTERM, SIG_DFL);
    map_input(runs, pending, options);
    ::_exit(0);
  }
  if (pid < 0) {
    const Failure f{4, fmt::format("internal error: cannot start a process for this input ({})", std::strerror(errno))};
    for (const auto k : pending) runs.record_error(k, f);
    return;
  }
  int status = 0;
  batch_gate().unlock();  // held by the caller (run_batch_input's contract) since before the fork
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  batch_gate().lock();
  if (WIFSIGNALED(status)) record_child_death(runs, pending, WTERMSIG(status));
}

}  // namespace

std::mutex& batch_gate() {
  static std::mutex gate;
  return gate;
}

BatchInputOutcome run_batch_input(const fs::path& root, const BatchInput& input, std::size_t index,
                                  const BatchOptions& options, const BatchLock& lock) {
  const InputRuns runs{root, input, options.weights};
  BatchInputOutcome outcome;
  outcome.index = index;
  const detail::StageTimer timer("batch input");
  std::vector<std::size_t> pending;
  for (std::size_t k = 0; k < options.weights.size(); ++k)
    if (run_status(runs.folder(k)) == RunStatus::kPending) pending.push_back(k);
  if (options.isolate)
    map_input_in_child(runs, pending, options, lock);
  else
    map_input(runs, pending, options);
  for (std::size_t k = 0; k < options.weights.size(); ++k) {
    const RunFolder state = read_run_folder(runs.folder(k));
    outcome.statuses.push_back(state.status);
    if (state.status == RunStatus::kError && outcome.message.empty()) {
      outcome.exit_code = state.exit_code;
      outcome.message = state.message;
    }
    if (outcome.warnings.empty() && state.report && state.report->structure)
      outcome.warnings = state.report->structure->warnings;
  }
  outcome.seconds = timer.seconds();
  return outcome;
}

}  // namespace spheremap::pipeline_detail
