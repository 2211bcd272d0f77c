#!/usr/bin/env bash
# The main job: set up and build, then reproduce the Gabor paper's Fig. 10 with our surfaces —
# geometric optics beside wave optics at 0.5 um and over the spectrum, for the isotropic,
# brushed and scratched builtins (1024² at 1 um, 256² panels, 20 degree incidence) — into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/reproduce-figures.sh out fig10
echo "figure: $(pwd)/out/fig10.png (panels and their queries in out/fig10.panels/, record out/fig10.json)"
