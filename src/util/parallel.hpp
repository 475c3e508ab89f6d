// Private to the library (util/: every layer may use it): a tiny deterministic work-sharing loop on
// std::thread, and the mapping of large arrays' pages from several threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#if __has_include(<sys/mman.h>)
#include <sys/mman.h>
#include <unistd.h>
#endif

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

/// parallel_chunks over the items [0, count) in consecutive ranges of `size` items (the last may be
/// shorter): task(first, last) for each range [first, last). The same rules for outputs.
template <typename Task>
void parallel_ranges(std::int64_t count, std::int64_t size, int threads, Task&& task) {
  parallel_chunks((count + size - 1) / size, threads, [&](std::int64_t chunk, int) {
    const std::int64_t first = chunk * size;
    task(first, std::min(count, first + size));
  });
}

/// Reserves `count` elements of `values` and has the kernel map their pages from `threads` threads at
/// once (MADV_POPULATE_WRITE, Linux 5.14): arrays of hundreds of megabytes (the grid, the contour's
/// vertices and triangles) otherwise spend a tenth of a second in page faults on the one thread that
/// first writes them. Where the kernel lacks it, nothing happens and the first write maps the pages.
template <typename T>
void reserve_mapped(std::vector<T>& values, std::size_t count, int threads) {
  values.reserve(count);
#if defined(MADV_POPULATE_WRITE)
  static const long page_size = sysconf(_SC_PAGESIZE);
  if (page_size <= 0) return;
  const auto page = static_cast<std::uintptr_t>(page_size);
  const auto begin = reinterpret_cast<std::uintptr_t>(values.data());
  const std::uintptr_t first = (begin + page - 1) / page * page, end = (begin + count * sizeof(T)) / page * page;
  if (threads <= 1 || end <= first + page * 1024) return;  // small: not worth threads
  const std::uintptr_t pages = (end - first) / page;
  parallel_chunks(threads, threads, [&](std::int64_t chunk, int) {
    const auto from =
        first + page * (pages * static_cast<std::uintptr_t>(chunk) / static_cast<std::uintptr_t>(threads));
    const auto to =
        first + page * (pages * static_cast<std::uintptr_t>(chunk + 1) / static_cast<std::uintptr_t>(threads));
    if (to > from) madvise(reinterpret_cast<void*>(from), to - from, MADV_POPULATE_WRITE);
  });
#else
  (void)threads;
#endif
}

}  // namespace spheremap::detail
