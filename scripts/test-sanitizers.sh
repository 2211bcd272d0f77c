#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (with LeakSanitizer),
# in its own build folder (build-asan, or $GLINTSCOPE_ASAN_BUILD_DIR). .ci/run calls it after the
# normal tests. Suppressions for leaks inside the image libraries (not ours) are in
# tests/sanitizer/lsan.supp, each with its reason.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${GLINTSCOPE_ASAN_BUILD_DIR:-build-asan}
launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGLINTSCOPE_SANITIZE=ON \
  -DGLINTSCOPE_BUILD_BENCHMARKS=OFF "${launcher[@]}" > /dev/null
cmake --build "$build" -j"$(nproc)"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export LSAN_OPTIONS=suppressions=$(pwd)/tests/sanitizer/lsan.supp:print_suppressions=0
ctest --test-dir "$build" --output-on-failure -j"$(nproc)" --timeout 1200
