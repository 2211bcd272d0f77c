#!/usr/bin/env bash
# Set-up for a fresh Debian machine (run as root, or with sudo available): installs only the
# Debian packages that are missing, then configures and builds glintscope (Release) in build/.
# Idempotent: a second run installs nothing and only rebuilds what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  g++ make cmake pkg-config
  libopenimageio-dev libopenexr-dev libfftw3-dev libcli11-dev libopencolorio-dev
  libzip-dev libpugixml-dev nlohmann-json3-dev libtomlplusplus-dev parallel python3-matplotlib libgtest-dev libgmock-dev libbenchmark-dev
  libnlopt-dev
  # the Python module (python/, docs/python.md) and its tests, for Debian's /usr/bin/python3
  pybind11-dev python3-pybind11 python3-numpy python3-pytest
  # Gwyddion: the tests' independent implementation; the reader it offers is opt-in
  # (GLINTSCOPE_CMAKE_ARGS=-DGLINTSCOPE_GWYDDION=ON, GPL-2+: docs/dependencies.md)
  libgwyddion20-dev gwyddion libgtk2.0-dev libgtkglext1-dev
  fonts-dejavu-core
  # render --light-sweep's MP4 (a program called without a shell, not linked) and its test's ffprobe
  ffmpeg
)

missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -q
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

build_dir=${GLINTSCOPE_BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release ${GLINTSCOPE_CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" -j"$(nproc)"
