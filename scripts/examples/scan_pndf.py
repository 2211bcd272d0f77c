"""A measured scan, levelled, and its P-NDF (Yan 2014 / Dong 2015) beside fitted Beckmann and GGX
NDFs: the images and a slice through them along x.

Usage: python3 scripts/examples/scan_pndf.py [OUTPUT_DIR [SCAN]]   (writes scan_pndf.png)
SCAN is any heightfield glintscope reads (.x3p, .exr, .npy, ...). Without one, a stand-in scan is
written first: a rough Gaussian field tilted by 2 degrees with 1% drop-outs, saved as X3P, so the
example runs the full path (load, fill, level) anywhere.
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import glintscope

out_dir = sys.argv[1] if len(sys.argv) > 1 else "."
scan_path = sys.argv[2] if len(sys.argv) > 2 else os.path.join(out_dir, "stand_in_scan.x3p")
if len(sys.argv) <= 2:
    rough = glintscope.generate("gaussian", size=192, texel="0.5um", sigma_h=0.2, correlation_length_x=3,
                                correlation_length_y=3).heights.astype(float)
    y, x = np.mgrid[0:rough.shape[0], 0:rough.shape[1]] * 0.5
    scan = rough + np.tan(np.radians(2)) * x  # a tilted sample
    scan[np.random.default_rng(1).random(scan.shape) < 0.01] = np.nan  # profilometer drop-outs
    glintscope.Heightfield(scan, texel="0.5um", allow_missing=True).save(scan_path)

raw = glintscope.load(scan_path)
levelled = raw.fill().remove_form("plane")
pndf = glintscope.ndf(levelled, "pndf", footprint="whole", res=64)
fits = {name: glintscope.fit_ndf(pndf, name) for name in ("beckmann", "ggx")}
for name, fit in fits.items():
    print(f"{name}: alpha_x {fit['alpha_x']:.4f}, alpha_y {fit['alpha_y']:.4f}, relative error {fit['relative_error']:.3f}")

figure, axes = plt.subplots(1, 4, figsize=(16, 4), constrained_layout=True)
top = float(pndf.values.max())
panels = [("P-NDF of the levelled scan", pndf.values[0])]
panels += [(f"{name} fit, alpha {fit['alpha_x']:.3f}/{fit['alpha_y']:.3f}\nrelative error {fit['relative_error']:.3f}",
            fit["image"].values[0]) for name, fit in fits.items()]
for axis, (title, values) in zip(axes, panels):
    image = axis.imshow(values, extent=(-1, 1, -1, 1), cmap="viridis", vmin=0, vmax=top)
    axis.set_title(title, fontsize=9)
    axis.set_xlabel("h x")
figure.colorbar(image, ax=axes[:3], label="D(h)", shrink=0.8)
n = pndf.resolution
h = (np.arange(n) + 0.5) / n * 2 - 1
axes[3].semilogy(h, pndf.values[0][n // 2], "k.", label="P-NDF")
for name, fit in fits.items():
    axes[3].semilogy(h, fit["image"].values[0][n // 2], label=name)
axes[3].set_ylim(top * 1e-4, top * 2)
axes[3].set_xlabel("h x (slice through the centre)")
axes[3].legend()
stats = levelled.iso_parameters()
figure.suptitle(f"{os.path.basename(scan_path)}: {raw.missing} points filled, plane removed; Sq {stats['Sq_um']:.3f} um, "
                f"Sdq {stats['Sdq']:.3f}")
path = os.path.join(out_dir, "scan_pndf.png")
figure.savefig(path, dpi=90)
print(path)
