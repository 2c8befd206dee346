"""Plots of an ibvalve report and curves of a comparison (run by `ibvalve report` and `ibvalve compare`
with Debian's /usr/bin/python3).

usage: plot_report.py TIMESERIES.csv METRICS.json OUTPUT_DIR [METRICS.json OUTPUT_DIR ...]
       plot_report.py --compare CURVES.json OUTPUT_DIR

Report: reads the run's time series and the metrics.json written beside the report (for the analysed
cycle and its phases) and writes into OUTPUT_DIR flow.png, pressures.png, pressure_difference.png and, when the series
has an orifice_area column, orifice_area.png; with a V_LV column (a run inside the closed-loop
circulation) pv_loop.png, the LV pressure-volume loop. Only the analysed cycle is drawn. Further
METRICS.json OUTPUT_DIR pairs (a run's other cycles) are drawn by the same process.

Comparison: CURVES.json (written by `ibvalve compare`) lists the cases: {"cases": [{"name", "series",
"cycle_start", "cycle_end"}]}, the series being a run's timeseries.csv and the cycle the one its metrics
come from. Writes, one line per case over its analysed cycle (time from the cycle's start), flow.png
(Q through the valve), pressure_difference.png (P_nlv - P_nao) and orifice_area.png, each when the
series have the columns.
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


def shade(ax, start, end, color, label):
    if finite(start) and finite(end) and end > start:
        ax.axvspan(start, end, color=color, alpha=0.18, lw=0, label=label)


def main():
    # One page or several of the same series (a run's cycles): the series is read, and matplotlib
    # imported, once for all of them.
    series_path, pages = sys.argv[1], sys.argv[2:]
    if len(pages) < 2 or len(pages) % 2:
        sys.exit("usage: plot_report.py TIMESERIES.csv METRICS.json OUTPUT_DIR [METRICS.json OUTPUT_DIR ...]")
    s = read_series(series_path)
    for metrics_path, out_dir in zip(pages[0::2], pages[1::2]):
        draw_page(s, metrics_path, out_dir)


def draw_page(s, metrics_path, out_dir):
    with open(metrics_path) as f:
        doc = json.load(f)
    ph = doc["phases"]
    t0, t1 = ph["cycle_start"], ph["cycle_end"]
    t = s["t"]
    sel = (t >= t0 - 1e-12) & (t <= t1 + 1e-12)
    t = t[sel]

    def col(name):
        return s[name][sel] if name in s else None

    bs, es, tc = ph.get("ejection_start"), ph.get("ejection_end"), ph.get("closure")
    written = []

    def save(fig, name):
        path = os.path.join(out_dir, name)
        fig.tight_layout()
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)

    # Flow with phases.
    fig, ax = plt.subplots(figsize=(8, 4))
    shade(ax, bs, es, "tab:green", "forward ejection")
    shade(ax, es, tc, "tab:orange", "closing regurgitation")
    shade(ax, t0, bs, "tab:blue", "before ejection")
    shade(ax, tc, t1, "tab:gray", "leakage")
    ax.plot(t, col("Q_valve"), color="k", lw=1.5, label="Q through the valve")
    if col("Q_outlet") is not None:
        ax.plot(t, col("Q_outlet"), color="tab:blue", lw=1, ls="--", label="Q at the outlet")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("Q (mL/s)")
    ax.set_xlim(t0, t1)
    ax.legend(loc="upper right", fontsize=8)
    m = doc["metrics"]

    def val(key):
        v = m.get(key, {}).get("value")
        return f"{v:.3g}" if finite(v) else "missing"

    ax.set_title(f"V_F {val('forward_volume')} mL, V_R {val('regurgitant_volume')} mL, "
                 f"V_L {val('leakage_volume')} mL, RF {val('regurgitant_fraction')} %", fontsize=10)
    save(fig, "flow.png")

    # Pressures.
    fig, ax = plt.subplots(figsize=(8, 4))
    for name, style in (("P_LV", "tab:red"), ("P_Ao", "tab:blue"), ("P_Wk", "tab:purple")):
        if col(name) is not None:
            ax.plot(t, col(name), color=style, lw=1.3, label=name)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("pressure (mmHg)")
    ax.set_xlim(t0, t1)
    ax.legend(loc="upper right", fontsize=8)
    save(fig, "pressures.png")

    # Pressure difference across the leaflets.
    fig, ax = plt.subplots(figsize=(8, 4))
    shade(ax, bs, es, "tab:green", "forward ejection")
    ax.plot(t, col("P_nlv") - col("P_nao"), color="k", lw=1.3, label="P_nlv - P_nao")
    tpg = m.get("transvalvular_pressure_gradient", {}).get("value")
    if finite(tpg) and finite(bs) and finite(es):
        ax.hlines(tpg, bs, es, colors="tab:green", linestyles="--", label=f"TPG {tpg:.3g} mmHg")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("P_nlv - P_nao (mmHg)")
    ax.set_xlim(t0, t1)
    ax.legend(loc="lower right", fontsize=8)
    save(fig, "pressure_difference.png")

    # Orifice area.
    if col("orifice_area") is not None:
        fig, ax = plt.subplots(figsize=(8, 4))
        shade(ax, ph.get("opening_start"), ph.get("fully_open_start"), "tab:cyan", "opening")
        shade(ax, ph.get("fully_open_start"), ph.get("fully_open_end"), "tab:green", "fully open")
        shade(ax, ph.get("fully_open_end"), ph.get("closing_end"), "tab:orange", "closing")
        ax.plot(t, col("orifice_area"), color="k", lw=1.3, label="orifice area")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("area (cm$^2$)")
        ax.set_xlim(t0, t1)
        ax.legend(loc="upper right", fontsize=8)
        save(fig, "orifice_area.png")

    # The LV pressure-volume loop (runs with the closed-loop circulation: a V_LV column).
    if col("V_LV") is not None:
        pressure = col("p_LV") if col("p_LV") is not None else col("P_LV")
        fig, ax = plt.subplots(figsize=(6, 5))
        ax.plot(col("V_LV"), pressure, color="tab:red", lw=1.5)
        ax.plot(col("V_LV")[:1], pressure[:1], "o", color="k", ms=4, label="cycle start")
        ax.set_xlabel("V_LV (mL)")
        ax.set_ylabel(("p_LV" if col("p_LV") is not None else "P_LV") + " (mmHg)")
        ax.set_title(f"SV {val('stroke_volume')} mL, EF {val('ejection_fraction')} %, "
                     f"SW {val('stroke_work')} mJ, E_L/SW {val('valve_share_of_stroke_work')} %", fontsize=9)
        ax.legend(loc="upper right", fontsize=8)
        save(fig, "pv_loop.png")

    for path in written:
        print(path)


def compare_main(curves_path, out_dir):
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
    if sys.argv[1:2] == ["--compare"]:
        compare_main(*sys.argv[2:4])
    else:
        main()
