#!/usr/bin/python3
"""Plot the output of `ibvalve fit ... --curves FIT.csv`: measured (dots) and fitted (lines) Cauchy
stresses against stretch, one panel per sample.

    /usr/bin/python3 examples/biaxial/plot_fit.py FIT.csv [-o fit.png]
"""
import argparse
import csv
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("curves", help="CSV written by ibvalve fit --curves")
    parser.add_argument("-o", "--output", default="fit.png", help="image to write (default fit.png)")
    args = parser.parse_args()

    samples = OrderedDict()
    with open(args.curves) as f:
        for row in csv.DictReader(f):
            samples.setdefault(row["sample"], []).append({k: (v if k == "sample" else float(v)) for k, v in row.items()})

    fig, axes = plt.subplots(1, len(samples), figsize=(4.5 * len(samples), 4), squeeze=False)
    for ax, (name, rows) in zip(axes[0], samples.items()):
        for stretch, data, model, colour, label in (
            ("lambda1", "sigma11_kPa", "model_sigma11_kPa", "tab:red", "11 (fiber)"),
            ("lambda2", "sigma22_kPa", "model_sigma22_kPa", "tab:blue", "22 (cross-fiber)"),
        ):
            ax.plot([r[stretch] for r in rows], [r[data] for r in rows], ".", color=colour, label=f"data {label}")
            ax.plot([r[stretch] for r in rows], [r[model] for r in rows], "x", color=colour, ms=4,
                    label=f"model {label}")
        ax.set_title(name)
        ax.set_xlabel("stretch")
        ax.set_ylabel("Cauchy stress [kPa]")
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
