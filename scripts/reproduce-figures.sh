#!/usr/bin/env bash
# Reproduces, with our own surfaces, the Gabor paper's Fig. 10 (geometric vs wave optics) and
# Fig. 11 (Gabor vs FFT), and Dong 2015's Fig. 8-9 NDF comparisons (P-NDF, filtered NDF, D_K on
# 70 um patches of the brushed surface, with slices across and along the brushing), and Jakob
# 2014's discrete flakes converging to the smooth model with a glint map, and the Gabor paper's
# Fig. 12 (rendered patches: spectral, 0.4 um and geometric, render cells of batch), into OUT
# (default out/).
# Usage: scripts/reproduce-figures.sh [OUT] [fig10|fig11|dong|discrete|patch ...]
# patch renders 320 x 180 pixels at 4 spp, the central quarter of the paper's view (figures/patch.toml);
# GLINTSCOPE_PATCH_PAPER=1 renders the paper's whole 1280 x 720 view at 4 spp (far longer:
# docs/performance.md).
# Needs a build (scripts/setup.sh) and, for the slice plot, Debian's python3-matplotlib.
set -euo pipefail
cd "$(dirname "$0")/.."
glintscope=${GLINTSCOPE_BUILD_DIR:-build}/app/glintscope
out=${1:-out}
shift || true
which=("$@")
[ ${#which[@]} -gt 0 ] || which=(fig10 fig11 dong discrete patch)
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
    patch)
      cp figures/patch.toml "$out/"
      if [ "${GLINTSCOPE_PATCH_PAPER:-0}" = 1 ]; then  # the paper's size and 30 deg view
        sed -i -e 's/^size = "320x180"$/size = "1280x720"/' -e 's/^fov = 7.66$/fov = 30/' "$out/patch.toml"
        grep -q '^size = "1280x720"$' "$out/patch.toml" && grep -q '^fov = 30$' "$out/patch.toml" ||
          { echo "figures/patch.toml no longer has the size and fov lines GLINTSCOPE_PATCH_PAPER rewrites" >&2; exit 1; }
      fi
      "$glintscope" batch "$out/patch.toml"
      ;;
    *) echo "unknown figure '$figure' (fig10, fig11, dong, discrete, patch)" >&2; exit 2 ;;
  esac
done
