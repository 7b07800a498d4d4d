#include "sim/mpm/kernel_instruction_set.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace culinarycut::mpm {
namespace {

// Set while this program starts itself again, so that a loader that ignores the mask cannot loop.
constexpr char kRestartMark[] = "CULINARYCUT_SIMD_RESTARTED";

// The CPU features whose absence makes the loader skip every level above `level` (glibc's names).
std::string MaskAbove(const std::string& level) {
  if (level == "x86-64") return "-SSE4_2,-AVX2,-AVX512F";  // v2 needs SSE4.2, v3 AVX2, v4 AVX-512F
  if (level == "x86-64-v2") return "-AVX2,-AVX512F";
  if (level == "x86-64-v3") return "-AVX512F";
  return "";
}

// GLIBC_TUNABLES with `mask` added to its glibc.cpu.hwcaps entry (the last entry of a name wins, so a second
// one would drop the user's own mask).
std::string WithHwcapsMask(const char* tunables, const std::string& mask) {
  const std::string key = "glibc.cpu.hwcaps=";
  std::string text = tunables ? tunables : "";
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return text.empty() ? key + mask : text + ":" + key + mask;
  const std::size_t end = text.find(':', at);
  return text.insert(end == std::string::npos ? text.size() : end, "," + mask);
}

std::string Listed(const std::vector<std::string>& levels) {
  std::ostringstream text;
  for (std::size_t i = 0; i < levels.size(); ++i) text << (i ? ", " : "") << levels[i];
  return text.str();
}

}  // namespace

// What the compiler was told to target, so that the name cannot disagree with the code.
std::string KernelInstructionSet() {
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512DQ__) && defined(__AVX512VL__)
  return "x86-64-v4";
#elif defined(__AVX2__) && defined(__FMA__)
  return "x86-64-v3";
#elif defined(__SSE4_2__) && defined(__POPCNT__)
  return "x86-64-v2";
#elif defined(__x86_64__)
  return "x86-64";
#else
  return CULINARYCUT_MPM_PROCESSOR;
#endif
}

std::vector<std::string> BuiltInstructionSets() {
  std::vector<std::string> levels;
  std::stringstream list(CULINARYCUT_MPM_LEVELS);
  for (std::string level; std::getline(list, level, ',');) {
    if (!level.empty()) levels.push_back(level);
  }
  if (levels.empty()) levels.push_back(KernelInstructionSet());  // a single build (no glibc-hwcaps levels)
  return levels;
}

void RequireInstructionSet(const std::string& level, char** argv) {
  const std::vector<std::string> built = BuiltInstructionSets();
  if (level == "auto" || level == KernelInstructionSet()) {
    unsetenv(kRestartMark);  // a program this one starts may restart itself in turn
    return;
  }
  const auto wanted = std::find(built.begin(), built.end(), level);
  if (wanted == built.end()) {
    throw std::invalid_argument("--simd must be auto or a level this build has (" + Listed(built) + "), got \"" +
                                level + "\"");
  }
  const auto loaded = std::find(built.begin(), built.end(), KernelInstructionSet());
  if (wanted > loaded) {
    throw std::invalid_argument("--simd " + level + ": this CPU (or GLIBC_TUNABLES) does not run it; the loader chose " +
                                KernelInstructionSet());
  }
  if (std::getenv(kRestartMark)) {
    throw std::runtime_error("--simd " + level + ": started again with the wider levels masked, the loader still chose " +
                             KernelInstructionSet() + " (is glibc older than 2.33?)");
  }
  setenv("GLIBC_TUNABLES", WithHwcapsMask(std::getenv("GLIBC_TUNABLES"), MaskAbove(level)).c_str(), 1);
  setenv(kRestartMark, "1", 1);
  execv("/proc/self/exe", argv);
  throw std::runtime_error(std::string("--simd ") + level + ": could not start again: " + std::strerror(errno));
}

}  // namespace culinarycut::mpm
