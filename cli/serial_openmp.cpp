// Linked into the spheremap command and the benchmarks (CMake target spheremap_serial_openmp), not into
// the library: it replaces libgomp's entry point for every library of the process, so only a program
// that uses no OpenMP of its own may link it.
//
// Debian's CHOLMOD opens an OpenMP parallel region for every supernode. The library makes them inactive
// (SolverSection in src/sphere/solver_section.cpp), but libgomp still allocates a team of one for each and
// ends it with a barrier whose futex wake is a system call: 1.2 million of them in one default map of an
// 8.7k-atom protein (5hr7), about a fifth of the map stage's time. CHOLMOD imports only GOMP_parallel,
// omp_get_num_threads and omp_get_thread_num (its loops have static schedules, split inline), so running
// the region's body once on the calling thread, outside any team (one thread, number 0), does what the
// inactive region did, to the last bit (test Cli.TheCommandMapsAMeshExactlyAsTheLibraryDoes).
// A definition in the executable takes precedence over libgomp's for every library it loads.
extern "C" void GOMP_parallel(void (*fn)(void*), void* data, unsigned /*num_threads*/, unsigned /*flags*/) { fn(data); }

// Likewise for the whole process: CHOLMOD reads the clock (SuiteSparse_time) around every BLAS call of its
// supernodal factorization to fill timing statistics of cholmod_common that spheremap never reads, and
// UMFPACK times its phases for its Info array, which Eigen's UmfPackLU does not read either; those reads are
// a measurable part of the re-weighting stage. Neither library decides anything by the time, so a clock that
// never moves changes no result (the same test compares the command's map with the library's, which reads
// the real clock).
extern "C" double SuiteSparse_time(void) { return 0; }
