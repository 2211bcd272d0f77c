#!/usr/bin/env bash
# Time-boxed fuzzing of every parser with libFuzzer (clang from Debian), AddressSanitizer and
# UndefinedBehaviorSanitizer: builds build-fuzz with clang and GLINTSCOPE_FUZZ=ON, then runs each
# target for SECONDS (default 60) on a working copy of its seed corpus (tests/fuzz/heightfield/, heightfields/ for recipes, figures/ for manifests).
# A crash leaves its input as build-fuzz/crash-*; add it to tests/fuzz/<target>/ once fixed, so
# the ctest replay (FuzzCorpus.<target>) keeps it fixed.
#   bash scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
build=${GLINTSCOPE_FUZZ_BUILD_DIR:-build-fuzz}
command -v clang++ > /dev/null || { echo "fuzz.sh: clang++ is missing (apt-get install clang)" >&2; exit 2; }
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGLINTSCOPE_FUZZ=ON \
  -DGLINTSCOPE_SANITIZE=ON -DGLINTSCOPE_BUILD_TESTS=OFF -DGLINTSCOPE_BUILD_BENCHMARKS=OFF > /dev/null
cmake --build "$build" -j"$(nproc)" --target heightfield_fuzzer recipe_fuzzer manifest_fuzzer
export ASAN_OPTIONS=detect_leaks=1:fast_unwind_on_malloc=0
export LSAN_OPTIONS=suppressions=$(pwd)/tests/sanitizer/lsan.supp:print_suppressions=0
status=0
for target in heightfield recipe manifest; do
  corpus="$build/corpus/$target"
  mkdir -p "$corpus"
  case "$target" in  # the seeds ctest replays (fuzz/CMakeLists.txt)
    heightfield) seeds=tests/fuzz/heightfield ;;
    recipe) seeds=heightfields ;;
    manifest) seeds=figures ;;
  esac
  cp -n "$seeds"/* "$corpus"/
  [ -d tests/fuzz/"$target" ] && cp -n tests/fuzz/"$target"/* "$corpus"/
  echo "== $target: ${seconds} s"
  (cd "$build" && "./fuzz/${target}_fuzzer" -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=65536 \
     "corpus/$target") || status=1
done
exit $status
