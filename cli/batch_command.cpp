// spheremap batch: many inputs (files, folders, globs, lists), several weightings, in parallel,
// resumable; a progress bar on a terminal, one line per input otherwise (see
// include/spheremap/pipeline/batch.hpp).
#include <sched.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <set>
#include <thread>

#include <fmt/format.h>

#include "commands.hpp"
#include "pictures.hpp"
#include "spheremap/error.hpp"
#include "spheremap/pipeline/batch.hpp"
#include "spheremap/text.hpp"

namespace spheremap::cli {
namespace {

// Set by the signal handler, read by the batch's callbacks (polled about every 0.2 s).
volatile std::sig_atomic_t g_signals = 0;
volatile std::sig_atomic_t g_last_signal = 0;

extern "C" void on_signal(int signal) {
  g_last_signal = signal;
  g_signals = g_signals + 1;
}

void install_signal_handlers() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int available_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

int terminal_columns() {
  winsize size{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col >= 40) return size.ws_col;
  return 80;
}

std::string duration_text(double seconds) {
  if (!(seconds >= 0) || seconds > 1e7) return "?";
  const auto s = static_cast<long>(seconds + 0.5);
  if (s < 60) return fmt::format("{}s", s);
  if (s < 3600) return fmt::format("{}m{:02}s", s / 60, s % 60);
  return fmt::format("{}h{:02}m", s / 3600, (s % 3600) / 60);
}

struct BatchCommand {
  static constexpr const char* kName = "batch";
  static constexpr const char* kDescription =
      "Map many meshes and structures (files, folders, glob patterns, @lists) in parallel into one folder each, "
      "with a summary (summary.csv, summary.jsonl); re-running resumes";

  std::vector<std::string> inputs;
  std::string output;
  int jobs = 0;
  MapCliOptions map;
  bool quiet = false, force = false, retry_errors = false, no_pictures = false;
  void add(CLI::App* command);
  int run();
};

class Reporter {
 public:
  Reporter(const std::vector<BatchInput>& inputs, const std::vector<Weights>& weights, bool quiet)
      : inputs_(inputs), weights_(weights), quiet_(quiet), terminal_(::isatty(STDERR_FILENO) == 1) {}

  void finished(const BatchInputOutcome& outcome, const BatchProgress& progress) {
    const bool problem = !outcome.warnings.empty() || std::any_of(outcome.statuses.begin(), outcome.statuses.end(),
                                                                  [](RunStatus s) { return s != RunStatus::kOk; });
    if (quiet_ && !problem) return;
    if (terminal_ && !problem) {
      tick(progress);
      return;
    }
    std::string line =
        fmt::format("[{}/{}] {} -> {}: ", progress.already_done + progress.finished, progress.inputs,
                    valid_utf8(inputs_[outcome.index].path.string()), valid_utf8(inputs_[outcome.index].name));
    std::set<RunStatus> distinct(outcome.statuses.begin(), outcome.statuses.end());
    if (distinct.size() == 1) {
      line += to_string(outcome.statuses.front());
    } else {
      for (std::size_t k = 0; k < weights_.size(); ++k)
        line += fmt::format("{}{} {}", k ? ", " : "", to_string(weights_[k]), to_string(outcome.statuses[k]));
    }
    if (!outcome.message.empty())
      line += fmt::format(" (exit {}): {}", outcome.exit_code, valid_utf8(outcome.message));
    else if (distinct.count(RunStatus::kNotCertified))
      line += " — NOT CERTIFIED, written anyway (see report.json)";
    for (const auto& warning : outcome.warnings) line += fmt::format("; warning: {}", valid_utf8(warning));
    line += fmt::format(" [{:.1f} s]", outcome.seconds);
    clear_bar();
    std::cerr << line << "\n";
    if (terminal_ && !quiet_) tick(progress);
  }

  void tick(const BatchProgress& progress) {
    if (!terminal_ || quiet_) return;
    const std::size_t done = progress.already_done + progress.finished;
    std::string tail = fmt::format(" {}/{}", done, progress.inputs);
    if (progress.errors) tail += fmt::format("  {} failed", progress.errors);
    if (progress.not_certified) tail += fmt::format("  {} not certified", progress.not_certified);
    if (progress.running) tail += fmt::format("  {} running", progress.running);
    const std::size_t remaining = progress.inputs - done;
    if (progress.finished > 0 && progress.elapsed_seconds > 0) {
      const double per_second = static_cast<double>(progress.finished) / progress.elapsed_seconds;
      tail += per_second >= 1.0 / 60 ? fmt::format("  {:.1f}/min", per_second * 60)
                                     : fmt::format("  {:.1f}/h", per_second * 3600);
      if (remaining > 0 && !progress.stopping)
        tail += fmt::format("  ETA {}", duration_text(static_cast<double>(remaining) / per_second));
    } else {
      tail += fmt::format("  {}", duration_text(progress.elapsed_seconds));
    }
    if (progress.stopping) tail += "  stopping: finishing the running inputs (Ctrl-C again to abandon them)";
    const int width = std::clamp(terminal_columns() - static_cast<int>(tail.size()) - 3, 10, 40);
    const int filled = progress.inputs ? static_cast<int>(width * done / progress.inputs) : width;
    std::string bar = "[" + std::string(static_cast<std::size_t>(filled), '#') +
                      std::string(static_cast<std::size_t>(width - filled), '.') + "]";
    std::cerr << "\r" << bar << tail << "\x1b[K" << std::flush;
    bar_shown_ = true;
  }

  void clear_bar() {
    if (bar_shown_) std::cerr << "\r\x1b[K" << std::flush;
    bar_shown_ = false;
  }

 private:
  const std::vector<BatchInput>& inputs_;
  const std::vector<Weights>& weights_;
  bool quiet_, terminal_;
  bool bar_shown_ = false;
};

// Ctrl-C once: no new input is started; twice: the running ones are abandoned, the summary written.
BatchCallbacks interrupt_callbacks(const BatchCommand& s, const BatchOptions& batch,
                                   const std::vector<BatchInput>& inputs, Reporter& reporter) {
  BatchCallbacks callbacks;
  auto announced = std::make_shared<bool>(false);
  callbacks.on_tick = [&s, &batch, &inputs, &reporter, announced](const BatchProgress& progress) {
    if (!*announced && !s.quiet) {
      *announced = true;
      std::cerr << fmt::format(
          "spheremap batch: {} input(s) x {} weighting(s) into {}: {} already complete, "
          "{} to run, {} at a time\n",
          progress.inputs, batch.weights.size(), s.output, progress.already_done,
          progress.inputs - progress.already_done,
          std::min<std::size_t>(static_cast<std::size_t>(batch.jobs), progress.inputs - progress.already_done));
    }
    if (g_signals >= 2) {
      // Abandon the running inputs: they leave no report.json (so they rerun on resume) and at
      // most temporary files (removed on resume). Record what is complete, then end now.
      reporter.clear_bar();
      std::cerr << "spheremap batch: interrupted again: abandoning the running inputs\n";
      try {
        write_batch_summary(s.output, inputs, batch.weights);
      } catch (const std::exception& e) {
        std::cerr << "spheremap batch: " << e.what() << "\n";
      }
      std::cerr << std::flush;
      std::_Exit(128 + static_cast<int>(g_last_signal));
    }
    reporter.tick(progress);
  };
  callbacks.on_finished = [&reporter](const BatchInputOutcome& outcome, const BatchProgress& progress) {
    reporter.finished(outcome, progress);
  };
  auto stop_announced = std::make_shared<bool>(false);
  callbacks.stop = [&reporter, stop_announced]() {
    if (g_signals == 0) return BatchStop::kContinue;
    if (!*stop_announced) {
      *stop_announced = true;
      reporter.clear_bar();
      std::cerr << "spheremap batch: interrupted: no new input is started; the running ones finish "
                   "(interrupt again to abandon them)\n";
    }
    return BatchStop::kFinishRunning;
  };
  return callbacks;
}

// The last line: counts by status, where the summary is; the exit code (128 + signal when interrupted).
int report_end(const BatchCommand& s, const BatchOptions& batch, const BatchResult& result, std::size_t inputs) {
  std::size_t counts[4] = {0, 0, 0, 0};
  for (const auto& row : result.rows) {
    const auto status = row.at("status").get<std::string>();
    ++counts[status == "ok" ? 0 : status == "not-certified" ? 1 : status == "error" ? 2 : 3];
  }
  const bool interrupted = g_signals > 0;
  const int code = interrupted ? 128 + static_cast<int>(g_last_signal) : result.exit_code;
  if (!s.quiet || code != 0) {
    std::string text = fmt::format("{} input(s) x {} weighting(s): {} ok, {} not certified, {} error(s)", inputs,
                                   batch.weights.size(), counts[0], counts[1], counts[2]);
    if (counts[3]) text += fmt::format(", {} pending", counts[3]);
    text += fmt::format(" ({} run now, {} already complete, {:.1f} s); summary: {}", result.progress.finished,
                        result.progress.already_done, result.progress.elapsed_seconds,
                        (std::filesystem::path(s.output) / kSummaryCsvFile).string());
    if (interrupted) text += "; interrupted: run the same command again to resume";
    std::cout << text << "\n";
  }
  return code;
}

void BatchCommand::add(CLI::App* command) {
  command
      ->add_option("inputs", inputs,
                   "Inputs: files; folders (their .obj .off .ply .stl .pdb .ent .cif .mmcif .pqr (.gz) files, not "
                   "recursive); glob patterns ('data/*.pdb', quoted or expanded by the shell); @LIST or LIST.txt "
                   "(one input per line, relative to the list's folder)")
      ->required();
  add_output_option(command, output,
                    "Output root: one folder per input (per weighting with several), summary.csv, summary.jsonl");
  command->add_option("--jobs", jobs, "Inputs mapped at once (default: all cores; each needs its own memory)")
      ->check(CLI::PositiveNumber);
  command->add_flag("--force", force, "Redo every input, even those already complete (also when options changed)");
  command->add_flag("--retry-errors", retry_errors, "Redo the inputs that failed before (error.json)");
  command->add_flag("--no-pictures", no_pictures,
                    "Write no pictures/ and no index.html in the inputs' folders (only the maps and reports)");
  add_quiet_flag(command, quiet, "No progress; print only the inputs that fail or are not certified");
  map.add(command, WeightingCount::kSeveral);
}

int BatchCommand::run() {
  map.apply();
  BatchOptions batch;
  batch.weights = map.weightings();
  batch.job = map.job;
  batch.jobs = jobs > 0 ? jobs : available_cores();
  batch.force = force;
  batch.retry_errors = retry_errors;
  if (!no_pictures) {
    // Several inputs at once already share the cores: then each draws on one thread.
    const int picture_threads = batch.jobs > 1 ? 1 : 0;
    batch.write_pictures = [picture_threads](const std::filesystem::path& folder, const MapJobResult& result) {
      write_pictures(folder, result, picture_threads);
    };
  }
  const auto named = name_batch_inputs(expand_batch_inputs(inputs));
  Reporter reporter(named, batch.weights, quiet);
  install_signal_handlers();
  const BatchResult result = run_batch(output, named, batch, interrupt_callbacks(*this, batch, named, reporter));
  reporter.clear_bar();
  return report_end(*this, batch, result, named.size());
}

}  // namespace

Command add_batch_command(CLI::App& app) { return make_command<BatchCommand>(app); }

}  // namespace spheremap::cli
