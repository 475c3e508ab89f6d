// The batch runner (see include/spheremap/pipeline/batch.hpp): the root prepared (lock, batch.json,
// leftovers, what --force/--retry-errors redo), then the inputs with a pending run mapped by worker
// threads while the calling thread reports progress and rewrites the summary.
#include "spheremap/pipeline/batch.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "../util/stage_timer.hpp"
#include "batch_manifest.hpp"
#include "batch_worker.hpp"
#include "detail.hpp"

namespace spheremap {
namespace {

using namespace pipeline_detail;

void check_preconditions(const std::vector<BatchInput>& inputs, const BatchOptions& options) {
  const auto& weights = options.weights;
  if (weights.empty()) throw std::invalid_argument("run_batch: no weights");
  for (std::size_t a = 0; a < weights.size(); ++a)
    for (std::size_t b = a + 1; b < weights.size(); ++b)
      if (weights[a] == weights[b])
        throw std::invalid_argument(fmt::format("run_batch: weights {} twice", to_string(weights[a])));
  if (options.jobs < 1) throw std::invalid_argument("run_batch: jobs < 1");
  std::set<std::string> names;
  for (const auto& input : inputs)
    if (!names.insert(pipeline_detail::lower(input.name)).second)
      throw std::invalid_argument(fmt::format("run_batch: output name '{}' twice", input.name));
}

// Under the lock: batch.json checked, leftovers of interrupted runs removed, what --force and
// --retry-errors redo cleared, then batch.json (re)written.
void prepare_root(const fs::path& root, const std::vector<BatchInput>& inputs, const BatchOptions& options) {
  const bool new_manifest = pipeline_detail::check_batch_manifest(root, options);
  remove_leftover_temporaries(root, batch_root_file_names());
  for (const auto& input : inputs)
    for (const auto& folder : all_input_folders(root, input)) remove_leftover_temporaries(folder, run_file_names());
  if (options.force) {
    for (const auto& input : inputs)
      for (const auto& folder : all_input_folders(root, input)) clear_run_folder(folder);
  } else if (options.retry_errors) {
    for (const auto& input : inputs)
      for (std::size_t k = 0; k < options.weights.size(); ++k) {
        const auto folder = batch_run_folder(root, input, options.weights, k);
        if (run_status(folder) == RunStatus::kError) clear_run_folder(folder);
      }
  }
  if (new_manifest) pipeline_detail::write_batch_manifest(root, options);
}

// The inputs with a pending run, in order; the others counted in `progress` as done before.
std::vector<std::size_t> pending_inputs(const fs::path& root, const std::vector<BatchInput>& inputs,
                                        const std::vector<Weights>& weights, BatchProgress& progress) {
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    bool pending = false, error = false, not_certified = false;
    for (std::size_t k = 0; k < weights.size(); ++k) {
      const auto status = run_status(batch_run_folder(root, inputs[i], weights, k));
      pending |= status == RunStatus::kPending;
      error |= status == RunStatus::kError;
      not_certified |= status == RunStatus::kNotCertified;
    }
    if (pending) {
      todo.push_back(i);
    } else {
      ++progress.already_done;
      progress.errors += error;
      progress.not_certified += not_certified;
    }
  }
  return todo;
}

// Worker threads pull the pending inputs in order; the calling thread waits for their outcomes.
class WorkerPool {
 public:
  WorkerPool(const fs::path& root, const std::vector<BatchInput>& inputs, const std::vector<std::size_t>& todo,
             const BatchOptions& options, const BatchLock& lock)
      : root_(root),
        inputs_(inputs),
        todo_(todo),
        options_(options),
        lock_(lock),
        worker_count_(std::min<std::size_t>(static_cast<std::size_t>(options.jobs), todo.size())) {}
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  ~WorkerPool() { join(); }

  void start() {
    threads_.reserve(worker_count_);
    for (std::size_t t = 0; t < worker_count_; ++t) threads_.emplace_back([this] { work(); });
    // A new thread's start allocates (the sanitizers' thread state): done before the first fork.
    while (started_.load() < worker_count_) std::this_thread::yield();
  }
  // No new input is started; the running ones finish.
  void stop() { stopping_.store(true); }
  bool stopping() const { return stopping_.load(); }
  void join() {
    for (auto& thread : threads_)
      if (thread.joinable()) thread.join();
  }
  // Waits at most `tick` for an outcome; returns those that arrived, the number running, and whether
  // every worker has ended.
  std::deque<BatchInputOutcome> wait(std::chrono::duration<double> tick, std::size_t& running, bool& all_done) {
    std::deque<BatchInputOutcome> ready;
    {
      // The caller holds the batch gate when isolating (run_batch): not while it waits. Taken back after
      // mutex_ is released, in the workers' order (gate, then mutex_).
      if (options_.isolate) pipeline_detail::batch_gate().unlock();
      std::unique_lock guard(mutex_);
      changed_.wait_for(guard, tick, [&] { return !finished_.empty() || workers_done_ == worker_count_; });
      ready.swap(finished_);
      running = running_;
      all_done = workers_done_ == worker_count_;
    }
    if (options_.isolate) pipeline_detail::batch_gate().lock();
    return ready;
  }

 private:
  void work() {
    started_.fetch_add(1);
    std::unique_lock gate(pipeline_detail::batch_gate(), std::defer_lock);
    if (options_.isolate) gate.lock();  // released while a child maps (run_batch_input)
    for (;;) {
      if (stopping_.load()) break;
      const std::size_t slot = next_.fetch_add(1);
      if (slot >= todo_.size()) break;
      {
        const std::lock_guard guard(mutex_);
        ++running_;
      }
      const std::size_t index = todo_[slot];
      BatchInputOutcome outcome = pipeline_detail::run_batch_input(root_, inputs_[index], index, options_, lock_);
      {
        const std::lock_guard guard(mutex_);
        --running_;
        finished_.push_back(std::move(outcome));
      }
      changed_.notify_all();
    }
    std::unique_lock guard(mutex_);
    ++workers_done_;
    changed_.notify_all();
    if (!gate.owns_lock()) return;
    // A thread's exit frees its allocator cache: this one ends only when no worker will fork again.
    gate.unlock();
    changed_.wait(guard, [&] { return workers_done_ == worker_count_; });
  }

  const fs::path& root_;
  const std::vector<BatchInput>& inputs_;
  const std::vector<std::size_t>& todo_;
  const BatchOptions& options_;
  const BatchLock& lock_;
  const std::size_t worker_count_;
  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<BatchInputOutcome> finished_;
  std::size_t running_ = 0, workers_done_ = 0;
  std::atomic<std::size_t> next_{0}, started_{0};
  std::atomic<bool> stopping_{false};
};

void count_outcome(const BatchInputOutcome& outcome, BatchProgress& progress) {
  const auto has = [&](RunStatus s) { return std::count(outcome.statuses.begin(), outcome.statuses.end(), s) > 0; };
  ++progress.finished;
  progress.errors += has(RunStatus::kError);
  progress.not_certified += has(RunStatus::kNotCertified);
}

// The calling thread while the pool runs: outcomes and ticks to the callbacks, stop requests to the
// pool, the summary rewritten at most every 30 s when something finished.
void supervise(WorkerPool& pool, const fs::path& root, const std::vector<BatchInput>& inputs,
               const std::vector<Weights>& weights, const BatchCallbacks& callbacks, BatchProgress& progress,
               const detail::StageTimer& started) {
  detail::StageTimer since_summary("batch summary");
  bool finished_since_summary = false;
  const auto tick = std::chrono::duration<double>(std::max(0.01, callbacks.tick_seconds));
  if (callbacks.on_tick) callbacks.on_tick(progress);
  for (;;) {
    bool all_done = false;
    const auto ready = pool.wait(tick, progress.running, all_done);
    progress.elapsed_seconds = started.seconds();
    for (const auto& outcome : ready) {
      count_outcome(outcome, progress);
      finished_since_summary = true;
      if (callbacks.on_finished) callbacks.on_finished(outcome, progress);
    }
    if (!pool.stopping() && callbacks.stop && callbacks.stop() == BatchStop::kFinishRunning) {
      pool.stop();
      progress.stopping = true;
    }
    if (all_done) break;
    if (callbacks.on_tick) callbacks.on_tick(progress);
    if (finished_since_summary && since_summary.seconds() >= 30) {
      capture([&] { write_batch_summary(root, inputs, weights); });
      since_summary.lap("summary");
      finished_since_summary = false;
    }
  }
}

}  // namespace

BatchResult run_batch(const fs::path& root, const std::vector<BatchInput>& inputs, const BatchOptions& options,
                      const BatchCallbacks& callbacks) {
  check_preconditions(inputs, options);
  const BatchLock lock(root);
  prepare_root(root, inputs, options);

  // From here on the folders say what is to do: the inputs with a pending run.
  const detail::StageTimer started("batch");
  BatchResult result;
  BatchProgress& progress = result.progress;
  progress.inputs = inputs.size();
  const std::vector<std::size_t> todo = pending_inputs(root, inputs, options.weights, progress);
  bool stopping = false;
  {
    WorkerPool pool(root, inputs, todo, options, lock);
    // Isolating, this thread holds the batch gate while it works (pipeline_detail::batch_gate); destroyed
    // before the pool, so that the workers can end.
    std::unique_lock gate(pipeline_detail::batch_gate(), std::defer_lock);
    if (options.isolate) gate.lock();
    try {
      pool.start();
      supervise(pool, root, inputs, options.weights, callbacks, progress, started);
    } catch (...) {
      pool.stop();
      throw;  // ~WorkerPool joins the threads
    }
    if (gate.owns_lock()) gate.unlock();
    pool.join();
    stopping = pool.stopping();
  }
  progress.running = 0;
  progress.elapsed_seconds = started.seconds();

  result.rows = write_batch_summary(root, inputs, options.weights);
  result.exit_code = batch_exit_code(result.rows);
  result.stopped = stopping && std::any_of(result.rows.begin(), result.rows.end(),
                                           [](const Json& row) { return row.at("status") == "pending"; });
  return result;
}

}  // namespace spheremap
