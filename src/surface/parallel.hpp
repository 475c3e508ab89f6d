// Private to the surface stage: a tiny deterministic work-sharing loop on std::thread.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace spheremap::detail {

/// The number of threads to use for `requested` (0: one per hardware thread).
inline int surface_threads(int requested) {
  if (requested > 0) return requested;
  const unsigned hardware = std::thread::hardware_concurrency();
  return hardware == 0 ? 1 : static_cast<int>(std::min(hardware, 64u));
}

/// Calls task(chunk, worker) for every chunk in [0, chunks), on up to `threads` threads (worker in
/// [0, threads)), chunks handed out in increasing order. Outputs must depend only on the chunk, never on
/// the worker or the order, for results to be the same whatever the thread count. Rethrows the first
/// exception a task threw (after every thread stopped).
template <typename Task>
void parallel_chunks(std::int64_t chunks, int threads, Task&& task) {
  const int workers = static_cast<int>(std::min<std::int64_t>(std::max(threads, 1), std::max<std::int64_t>(chunks, 1)));
  if (workers <= 1) {
    for (std::int64_t c = 0; c < chunks; ++c) task(c, 0);
    return;
  }
  std::atomic<std::int64_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&](int worker) {
    try {
      for (std::int64_t c = next++; c < chunks && !failed; c = next++) task(c, worker);
    } catch (...) {
      const std::lock_guard lock(error_mutex);
      if (!error) error = std::current_exception();
      failed = true;
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(workers - 1));
  for (int w = 1; w < workers; ++w) {
    try {
      pool.emplace_back(work, w);
    } catch (const std::system_error&) {
      break;  // no more threads: the ones running (at least this one) take every chunk
    }
  }
  work(0);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace spheremap::detail
