// Private to src/pipeline: the work of one batch input, and the capture of what it throws.
#pragma once

#include <cstddef>
#include <filesystem>
#include <mutex>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/pipeline/batch.hpp"

namespace spheremap::pipeline_detail {

/// An error that a batch records in error.json instead of stopping.
struct Failure {
  int exit_code = 0;
  std::string message;
};

/// Runs `f`, turning every exception into a Failure (the batch never stops for one input).
template <typename F>
std::optional<Failure> capture(F&& f) {
  try {
    f();
    return std::nullopt;
  } catch (const Error& e) {
    return Failure{static_cast<int>(e.code()), e.what()};
  } catch (const std::bad_alloc&) {
    return Failure{4, "internal error: out of memory; run fewer inputs at once (--jobs) or use a coarser --grid"};
  } catch (const std::exception& e) {
    return Failure{4, fmt::format("internal error: {}", e.what())};
  } catch (...) {
    return Failure{4, "internal error: unknown exception"};
  }
}

/// Held by every thread of a batch that isolates its inputs (options.isolate) while it runs, and released
/// only while it blocks (waiting for a child or for an outcome): so a child is forked while no other thread
/// of the process is in the middle of anything (an allocation holding the allocator's lock, which the child
/// would inherit locked: AddressSanitizer's allocator does not take its locks across fork as glibc's does).
std::mutex& batch_gate();

/// Maps the pending runs of `input` (options.weights; in a child process with options.isolate, which
/// forgets `lock` there) and returns what its run folders say afterwards. With options.isolate the caller
/// holds batch_gate(), which is released while the child runs. Never throws: what happened is on disk, in
/// each run folder.
BatchInputOutcome run_batch_input(const std::filesystem::path& root, const BatchInput& input, std::size_t index,
                                  const BatchOptions& options, const BatchLock& lock);

}  // namespace spheremap::pipeline_detail
