#!/usr/bin/env bash
# Reproduces, with our own surfaces, the Gabor paper's Fig. 10 (geometric vs wave optics) and
# Fig. 11 (Gabor vs FFT), and Dong 2015's Fig. 8-9 NDF comparisons (P-NDF, filtered NDF, D_K on
# 70 um patches of the brushed surface, with slices across and along the brushing), and Jakob
# 2014's discrete flakes converging to the smooth model with a glint map, into OUT (default out/).
# Usage: scripts/reproduce-figures.sh [OUT] [fig10|fig11|dong|discrete ...]
# Needs a build (scripts/setup.sh) and, for the slice plot, Debian's python3-matplotlib.
set -euo pipefail
cd "$(dirname "$0")/.."
glintscope=${GLINTSCOPE_BUILD_DIR:-build}/app/glintscope
out=${1:-out}
shift || true
which=("$@")
[ ${#which[@]} -gt 0 ] || which=(fig10 fig11 dong discrete)
mkdir -p "$out"

for figure in "${which[@]}"; do
  case "$figure" in
    fig10|fig11)
      cp "figures/$figure.toml" "$out/"
      "$glintscope" batch "$out/$figure.toml"
      ;;
    dong)
      cp figures/dong-ndf.toml "$out/"
      "$glintscope" batch "$out/dong-ndf.toml"
      for method in pndf filtered dk; do
        extra=()
        [ "$method" = dk ] && extra=(--supersample 2)
        "$glintscope" ndf builtin:brushed --method "$method" --box 70x53um --footprints grid:3 --res 256 \
          --slice x --slice y "${extra[@]}" -o "$out/dong-brushed-$method.exr" --png "$out/dong-brushed-$method.png" --log
      done
      /usr/bin/python3 scripts/plot-slices.py "$out/dong-slices.png" \
        "Brushed builtin, mean of 3 x 3 patches of 70 x 53 um (Dong 2015 Fig. 9)" \
        "P-NDF=$out/dong-brushed-pndf" "filtered, 1 um=$out/dong-brushed-filtered" "D_K, 555 nm=$out/dong-brushed-dk"
      echo "slices: $out/dong-slices.png"
      ;;
    discrete)
      cp figures/discrete.toml "$out/"
      "$glintscope" batch "$out/discrete.toml"
      for flakes in 1e4 1e6; do
        "$glintscope" glints --outgoing 10,180 --incident 10,0 --flakes "$flakes" --size 128 --spacing 1um \
          -o "$out/discrete-glints-$flakes.png"
      done
      ;;
    *) echo "unknown figure '$figure' (fig10, fig11, dong, discrete)" >&2; exit 2 ;;
  esac
done
