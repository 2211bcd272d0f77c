#!/usr/bin/env bash
# The main job: set up and build, then generate an isotropic bumpy-metal heightfield and show
# how it reflects light — its statistics, a height preview, and the spectral wave-optics lobe
# by the Gabor-kernel method and by the FFT ground truth, side by side in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
glintscope=${GLINTSCOPE_BUILD_DIR:-build}/app/glintscope
mkdir -p out

"$glintscope" generate isotropic --size 1024 --seed 7 -o out/isotropic.exr
"$glintscope" info out/isotropic.exr
"$glintscope" preview out/isotropic.exr -o out/isotropic-heights.png
for method in gabor fft; do
  "$glintscope" lobe out/isotropic.exr --method "$method" --incident 20,0 --spectral 16 --res 256 \
    -o "out/lobe-$method.exr" --png "out/lobe-$method.png" --json "out/lobe-$method.json"
done
echo "figures: out/isotropic-heights.png out/lobe-gabor.png out/lobe-fft.png"
