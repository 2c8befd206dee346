"""Overlaid curves of an ibvalve comparison (run by `ibvalve compare` with Debian's /usr/bin/python3).

usage: plot_comparison.py CURVES.json OUTPUT_DIR

CURVES.json (written by `ibvalve compare`) lists the cases: {"cases": [{"name", "series", "cycle_start",
"cycle_end"}]}, the series being a run's timeseries.csv and the cycle the one its metrics were computed
from. Writes, with one line per case over its analysed cycle (time from the cycle's start):
flow.png (Q through the valve), pressure_difference.png (P_nlv - P_nao, when the series have those
columns) and orifice_area.png (when they have an orifice_area column).
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_series(path):
    with open(path) as f:
        lines = [line for line in f if line.strip() and not line.lstrip().startswith("#")]
    header = [h.strip() for h in lines[0].split(",")]
    data = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    return {name: data[:, i] for i, name in enumerate(header)}


def finite(x):
    return x is not None and isinstance(x, (int, float)) and math.isfinite(x)


def main():
    curves_path, out_dir = sys.argv[1:3]
    with open(curves_path) as f:
        cases = json.load(f)["cases"]
    loaded = []
    for case in cases:
        s = read_series(case["series"])
        t = s["t"]
        t0 = case["cycle_start"] if finite(case.get("cycle_start")) else t[0]
        t1 = case["cycle_end"] if finite(case.get("cycle_end")) else t[-1]
        sel = (t >= t0 - 1e-12) & (t <= t1 + 1e-12)
        loaded.append((case["name"], t[sel] - t0, {k: v[sel] for k, v in s.items()}))

    def draw(name, ylabel, values, title):
        fig, ax = plt.subplots(figsize=(8, 4))
        drawn = 0
        for label, t, s in loaded:
            y = values(s)
            if y is None:
                continue
            ax.plot(t, y, lw=1.2, label=label)
            drawn += 1
        if drawn == 0:
            plt.close(fig)
            return
        ax.axhline(0.0, color="k", lw=0.5)
        ax.set_xlabel("t from the analysed cycle's start (s)")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.legend(loc="upper right", fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out_dir, name), dpi=110)
        plt.close(fig)

    draw("flow.png", "Q (mL/s)", lambda s: s.get("Q_valve"), "Flow through the valve")
    draw("pressure_difference.png", "P_nlv - P_nao (mmHg)",
         lambda s: s["P_nlv"] - s["P_nao"] if "P_nlv" in s and "P_nao" in s else None,
         "Pressure difference across the leaflets")
    draw("orifice_area.png", "orifice area (cm^2)", lambda s: s.get("orifice_area"), "Geometric orifice area")


if __name__ == "__main__":
    main()
