#!/usr/bin/env bash
# The test command: the same set-up as the main job, then every test through ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --test-dir "${GLINTSCOPE_BUILD_DIR:-build}" --output-on-failure -j"$(nproc)"
