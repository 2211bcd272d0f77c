#!/usr/bin/python3
"""(Debian's python3 and python3-matplotlib.) Plots `glintscope validate --convergence OUT.csv`: Gabor's error against the kernels per texel,
and the FFT's against its step, on log axes.  Usage: plot-convergence.py IN.csv OUT.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(source, target):
    series = {}
    with open(source, newline="") as stream:
        for row in csv.DictReader(stream):
            series.setdefault(row["series"], []).append((float(row["parameter"]), float(row["relative_l2"])))
    figure, (gabor, fft) = plt.subplots(1, 2, figsize=(9, 3.6))
    for order, marker in ((1, "o-"), (2, "D-")):
        k, error = zip(*series[f"gabor_order_{order}_kernels_per_texel"])
        label = "first order (Yan 2018 eq. 12-15)" if order == 1 else "second order (chirped)"
        gabor.loglog(k, [100 * e for e in error], marker, label=label)
    gabor.set_xticks(k, [str(int(x)) for x in k])
    gabor.legend(fontsize="small")
    gabor.set_xlabel("Gabor kernels per texel K")
    gabor.set_ylabel("relative L2 against FFT [%]")
    gabor.set_title("Gabor kernels vs FFT ground truth")
    step, error = zip(*series["fft_step_um"])
    fft.loglog(step, [100 * e for e in error], "s-", color="tab:orange")
    fft.set_xlabel("FFT grid step [um]")
    fft.set_ylabel("relative L2 against 1/4 of the auto step [%]")
    fft.set_title("FFT ground truth vs its step")
    for axes in (gabor, fft):
        axes.grid(True, which="both", alpha=0.3)
    figure.tight_layout()
    figure.savefig(target, dpi=120)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
