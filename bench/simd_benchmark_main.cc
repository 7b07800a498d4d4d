// Google Benchmark's main, plus --simd=LEVEL (auto, x86-64, x86-64-v3, ...): the MPM kernels' instruction set,
// as the server's and cc-cut's --simd choose it; the JSON's context says which ran ("simd"). Shared by the MPM
// benchmarks (bench_mpm_throughput, bench_mpm_falling_block).
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "sim/mpm/kernel_instruction_set.h"

int main(int argc, char** argv) {
  std::string simd = "auto";
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--simd=", 0) == 0) {
      simd = arg.substr(7);
    } else {
      rest.push_back(argv[i]);
    }
  }
  try {
    culinarycut::mpm::RequireInstructionSet(simd, argv);  // may start the benchmark again
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s: %s\n", argv[0], error.what());
    return 2;
  }
  benchmark::AddCustomContext("simd", culinarycut::mpm::KernelInstructionSet());
  int count = static_cast<int>(rest.size());
  benchmark::Initialize(&count, rest.data());
  if (benchmark::ReportUnrecognizedArguments(count, rest.data())) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
