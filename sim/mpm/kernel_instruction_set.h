// Which build of the MPM kernels this process runs. On x86-64 the library is built once per
// microarchitecture level (x86-64: SSE2; x86-64-v3: AVX2 and FMA; x86-64-v4: AVX-512) and the dynamic
// loader loads the best one the CPU runs (glibc-hwcaps). Results are the same bits for the same seed
// and thread count within one level, not across levels: wider vectors and fused multiply-adds round
// differently.
#pragma once

#include <string>
#include <vector>

namespace culinarycut::mpm {

// The level the loaded library was compiled for, e.g. "x86-64-v3".
std::string KernelInstructionSet();

// Every level this build ships, the baseline first.
std::vector<std::string> BuiltInstructionSets();

// Makes this process run the kernels at `level` ("auto": whatever the loader picked). A level below
// the loaded one is reached by starting this program again (argv, from /proc/self/exe) with the
// wider levels masked from the loader (GLIBC_TUNABLES glibc.cpu.hwcaps); returns only when the
// loaded level is `level`. Throws std::invalid_argument for a level the build lacks or the CPU
// does not run, and std::runtime_error if the restart fails.
void RequireInstructionSet(const std::string& level, char** argv);

}  // namespace culinarycut::mpm
