#include "solver_section.hpp"

#include <omp.h>

namespace spheremap::detail {

namespace {

std::mutex& solver_mutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

SolverSection::SolverSection() : lock_(solver_mutex()), saved_active_levels_(omp_get_max_active_levels()) {
  // Debian's CHOLMOD opens an OpenMP parallel region (with a fixed thread count that OMP_NUM_THREADS does
  // not lower) for every supernode: a thread wake-up per supernode costs a large share of the
  // factorization's wall time, and a second busy core that a parallel batch needs. With no active level
  // every such region runs on the calling thread. (libgomp still makes a team of one and a barrier system
  // call per region: the command and the benchmarks link cli/serial_openmp.cpp, which runs regions
  // without them.)
  omp_set_max_active_levels(0);
}

SolverSection::~SolverSection() { omp_set_max_active_levels(saved_active_levels_); }

}  // namespace spheremap::detail
