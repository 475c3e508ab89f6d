// Private to the sphere stage: held around every call into CHOLMOD's or UMFPACK's numeric work (see
// docs/library.md, "Thread safety").
#pragma once

#include <mutex>

namespace spheremap::detail {

/// Held around every call that can reach the BLAS: CHOLMOD's analysis, factorizations and solves, and
/// UMFPACK's (through Eigen). Debian 12's serial OpenBLAS (0.3.21) is not safe for concurrent callers:
/// blas_memory_alloc claims a scratch buffer from its table without holding its lock, so two threads in
/// level-3 routines (dgemm, dsyrk, dtrsm, dpotrf) at the same moment can be handed the same buffer and
/// mix each other's numbers. One process-wide mutex keeps the library's calls one at a time. While held,
/// the calling thread also has no active OpenMP level, so CHOLMOD's parallel regions run on it alone
/// (max-active-levels is a per-thread setting in libgomp); the caller's setting comes back afterwards.
/// Sections do not nest.
class SolverSection {
 public:
  SolverSection();
  ~SolverSection();
  SolverSection(const SolverSection&) = delete;
  SolverSection& operator=(const SolverSection&) = delete;

 private:
  std::unique_lock<std::mutex> lock_;
  int saved_active_levels_;
};

}  // namespace spheremap::detail
