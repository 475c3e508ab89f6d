// Picks OpenBLAS's kernels for this CPU when OpenBLAS itself could not (see blas_kernels.cpp).
#pragma once

namespace spheremap::cli {

/// On a virtual machine that hides its CPU model, OpenBLAS's runtime dispatch falls back to its generic
/// "Prescott" (SSE3) kernels, which makes CHOLMOD's factorizations about 1.5x slower (measured on this
/// project's Debian 12 VM: `spheremap map` of 5hr7's surface 8.9-10.0 s user time, 5.9-6.7 s with the
/// AVX-512 kernels). OpenBLAS reads its choice only when it is loaded, from OPENBLAS_CORETYPE: when that is
/// unset, the loaded BLAS is OpenBLAS, its choice is Prescott and the CPU has AVX-512 (or AVX2 + FMA),
/// this sets OPENBLAS_CORETYPE to SkylakeX (Haswell) and restarts the program with the same arguments.
/// Otherwise, or if the restart fails, it returns and nothing changes. `argv` is main's argv.
void use_blas_kernels_for_this_cpu(char** argv);

}  // namespace spheremap::cli
