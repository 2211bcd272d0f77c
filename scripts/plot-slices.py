#!/usr/bin/python3
"""(Debian's python3 and python3-matplotlib.) Plots 1-D NDF slices written by
`glintscope ndf ... --slice x --slice y -o NAME.exr` (NAME-slice-x.csv, NAME-slice-y.csv) for
several methods, on a log axis, as in Dong et al. 2015 Fig. 9.
Usage: plot-slices.py OUT.png TITLE LABEL=NAME [LABEL=NAME ...]"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_slice(path):
    with open(path, newline="") as stream:
        rows = list(csv.reader(stream))
    header, values = rows[0], rows[1:]
    # theta_deg and the first value column (NDFs are one layer, copied per wavelength).
    return [float(row[1]) for row in values], [float(row[2]) for row in values], header[2]


def main(target, title, series):
    figure, axes = plt.subplots(1, 2, figsize=(10, 3.8), sharey=True)
    for panel, direction, name in ((axes[0], "y", "across the brushing (h_y)"), (axes[1], "x", "along the brushing (h_x)")):
        for label, stem in series:
            theta, value, _ = read_slice(f"{stem}-slice-{direction}.csv")
            panel.semilogy(theta, [max(v, 1e-6) for v in value], label=label)
        panel.set_xlabel("theta_h along the slice [deg] (signed)")
        panel.set_title(name)
        panel.set_xlim(-30, 30)
        panel.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("D(h)")
    axes[0].set_ylim(1e-3, None)
    axes[1].legend()
    figure.suptitle(title)
    figure.tight_layout()
    figure.savefig(target, dpi=120)


if __name__ == "__main__":
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], [tuple(arg.split("=", 1)) for arg in sys.argv[3:]])
