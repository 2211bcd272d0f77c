"""Gabor kernels (Yan 2018 §4-5) against the FFT ground truth (Yan 2018 eq. 6) on one footprint:
the two lobes, their difference and the compare numbers in one matplotlib figure.

Usage: python3 scripts/examples/gabor_vs_fft.py [OUTPUT_DIR]   (writes gabor_vs_fft.png)
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import glintscope

out_dir = sys.argv[1] if len(sys.argv) > 1 else "."
field = glintscope.generate("gaussian", size=256, sigma_h=0.3, correlation_length_x=4, correlation_length_y=4)
query = dict(res=96, sigma_c="8um", incident=(20, 0), lambda_="0.5um")
fft = glintscope.lobe(field, "fft", **query)
gabor = glintscope.lobe(field, "gabor", **query)
numbers = glintscope.compare(gabor, fft)[0]
difference = glintscope.difference(gabor, fft).values[0]

figure, axes = plt.subplots(1, 3, figsize=(13, 4.4), constrained_layout=True)
top = float(fft.values.max())
extent = (-1, 1, -1, 1)  # the projected disk, row 0 at the top (largest y)
for axis, lobe, name in ((axes[0], fft, "FFT (ground truth)"), (axes[1], gabor, "Gabor kernels")):
    image = axis.imshow(lobe.values[0], extent=extent, cmap="inferno", vmin=0, vmax=top)
    axis.set_title(f"{name}\nalbedo {lobe.disk_sum():.4f}")
figure.colorbar(image, ax=axes[:2], label="f_r [1/sr]", shrink=0.8)
span = float(np.abs(difference).max())
image = axes[2].imshow(difference, extent=extent, cmap="RdBu_r", vmin=-span, vmax=span)
axes[2].set_title(f"Gabor - FFT: relative L2 {numbers['relative_l2']:.3f}\n"
                  f"peak error {numbers['peak_relative_error']:.3f}, energy ratio {numbers['energy_ratio']:.4f}")
figure.colorbar(image, ax=axes[2], label="difference [1/sr]", shrink=0.8)
for axis in axes:
    axis.set_xlabel("omega_o x")
    axis.set_ylabel("omega_o y")
figure.suptitle(f"sigma_c {query['sigma_c']}, lambda {query['lambda_']}, incidence 20 deg; "
                f"{field.rows}x{field.cols} Gaussian field, Sq 0.3 um, T 4 um")
path = os.path.join(out_dir, "gabor_vs_fft.png")
figure.savefig(path, dpi=90)
print(f"{path}: relative L2 {numbers['relative_l2']:.4f}, energy ratio {numbers['energy_ratio']:.4f}")
