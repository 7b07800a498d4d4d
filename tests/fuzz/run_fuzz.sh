#!/usr/bin/env bash
# Builds the fuzz targets with clang (libFuzzer, ASan, UBSan) into build-fuzz/ and runs each for a
# bounded time from its committed corpus (tests/fuzz/corpus/<target>); new inputs go to a scratch
# copy, so the committed corpus only changes when someone copies findings in on purpose.
# Usage: run_fuzz.sh [SECONDS_PER_TARGET]   (default 30)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
seconds="${1:-30}"
build="$root/build-fuzz"
command -v clang++ >/dev/null || { echo "run_fuzz: clang++ is missing (scripts/install_deps.sh --tests installs it)"; exit 1; }
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DCULINARYCUT_FUZZ=ON \
  -DCULINARYCUT_BUILD_TESTS=OFF -DCULINARYCUT_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "${CULINARYCUT_JOBS:-$(nproc)}" --target fuzz_scene fuzz_snapshot fuzz_action
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
for target in fuzz_scene fuzz_snapshot fuzz_action; do
  mkdir -p "$scratch/$target"
  cp "$here/corpus/$target"/* "$scratch/$target/"
  echo "run_fuzz: $target for $seconds s from $(ls "$here/corpus/$target" | wc -l) corpus inputs"
  # A finding (crash, sanitizer report, uncaught exception, > 20 s on one input, > 2 GB) fails the run
  # and leaves the input in $build/findings.
  mkdir -p "$build/findings"
  "$build/tests/fuzz/$target" "$scratch/$target" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 \
    -max_len=262144 -artifact_prefix="$build/findings/$target-" -print_final_stats=1 2>&1 | tail -n 12
done
