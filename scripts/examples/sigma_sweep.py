"""A sweep of the coherence footprint sigma_c: the lobe's energy (albedo) and its peak. The albedo,
the energy reflected, stays 1 at every size (the FFT lobe conserves it). The peak does not grow
monotonically: the smallest footprint blurs the lobe by lambda/(2 pi sigma_c); a larger one sees a
few facets and resolves their sharp glints; larger still, it averages ever more facets and the
peak falls toward the smooth mean lobe of the surface.

Usage: python3 scripts/examples/sigma_sweep.py [OUTPUT_DIR]   (writes sigma_sweep.png)
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import glintscope

out_dir = sys.argv[1] if len(sys.argv) > 1 else "."
field = glintscope.generate("gaussian", size=256, sigma_h=0.1, correlation_length_x=8, correlation_length_y=8)
sigmas = [2, 4, 8, 16, 32]
energies, peaks = [], []
for sigma in sigmas:
    lobe = glintscope.lobe(field, res=64, sigma_c=sigma, incident=(10, 0))
    energies.append(lobe.disk_sum())
    peaks.append(float(lobe.values.max()))
    print(f"sigma_c {sigma:>3} um: albedo {energies[-1]:.4f}, peak {peaks[-1]:.2f} 1/sr")

figure, energy_axis = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
energy_axis.plot(sigmas, energies, "o-", color="tab:blue")
energy_axis.set_xscale("log", base=2)
energy_axis.set_xlabel("sigma_c [um]")
energy_axis.set_ylabel("albedo (sum of f_r (2/N)^2)", color="tab:blue")
energy_axis.set_ylim(0, 1.2)
peak_axis = energy_axis.twinx()
peak_axis.plot(sigmas, peaks, "s--", color="tab:red")
peak_axis.set_yscale("log")
peak_axis.set_ylabel("peak f_r [1/sr]", color="tab:red")
energy_axis.set_title("FFT lobe vs footprint (Gaussian field, Sq 0.1 um, T 8 um, 10 deg)", fontsize=10)
path = os.path.join(out_dir, "sigma_sweep.png")
figure.savefig(path, dpi=90)
print(path)
