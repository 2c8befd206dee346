"""The study's stored results (examples/aortic_valve/study/) recomputed from their raw series by a second
implementation of the definitions (numpy here, C++ in hemodynamics/metrics.cpp and compare.cpp).

usage: check_study_results.py STUDY_DIR

For each case in STUDY_DIR/runs/<case>/: the reported cycle's forward-flow start t_ff, pressure
crossover, orifice opening and t_bs (the latest of the three, docs/hemodynamics.md, "Phases of the
analysed cycle"), t_es, and V_F, TPG, Q_rms, EOA and T_ej, from timeseries.csv, against
report/metrics.json; then the 12-criterion ranking's totals from metrics.csv against ranking.csv. Every
figure RESULTS.md quotes is in those files. Instants agree to 1e-9 s and values to 1e-9 relative (both
implementations integrate the same piecewise-linear interpolant; the difference is round-off). Exits 1
on the first disagreement, naming the case and the figure.
"""
import csv
import json
import pathlib
import sys

import numpy as np

PERIOD = 0.8


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def last_rise(t, y, i, level):
    """Where y last rose above level at or before sample i (t[0] if above from the start; None if never)."""
    j = i
    while j > 0 and not y[j] > level:
        j -= 1
    if not y[j] > level:
        return None
    while j > 0 and y[j - 1] > level:
        j -= 1
    if j == 0:
        return t[0]
    return t[j - 1] + (level - y[j - 1]) / (y[j] - y[j - 1]) * (t[j] - t[j - 1])


def integral(t, y, a, b):
    inside = (t > a) & (t < b)
    tt = np.concatenate(([a], t[inside], [b]))
    yy = np.interp(tt, t, y)
    return float(np.sum(0.5 * (yy[1:] + yy[:-1]) * np.diff(tt)))


def recompute(series_file, closed_fraction, open_fraction, density):
    d = np.genfromtxt(series_file, delimiter=",", names=True, comments="#")
    t_all = d["t"]
    cycles = int(np.floor((t_all[-1] - t_all[0]) / PERIOD * (1 + 1e-9)))
    t0 = t_all[0] + (cycles - 1) * PERIOD
    t1 = t0 + PERIOD
    # The cycle's samples with both ends interpolated, as the report takes them.
    inside = (t_all > t0) & (t_all < t1)
    t = np.concatenate(([t0], t_all[inside], [t1]))
    col = {name: np.interp(t, t_all, d[name]) for name in ("Q_valve", "P_nlv", "P_nao", "orifice_area")}
    q, gradient, area = col["Q_valve"], col["P_nlv"] - col["P_nao"], col["orifice_area"]
    i_peak = int(np.argmax(q))
    t_ff = last_rise(t, q, i_peak, 0.0)
    j = i_peak
    while j + 1 < len(q) and q[j + 1] > 0:
        j += 1
    t_es = t[j] + (0 - q[j]) / (q[j + 1] - q[j]) * (t[j + 1] - t[j])
    crossover = last_rise(t, gradient, i_peak, 0.0)
    # The orifice opening: the area normalised by its smallest value before the largest, the last
    # upward crossing of the closed fraction before it first reaches the open fraction.
    i_big = int(np.argmax(area))
    a = (area - area[: i_big + 1].min()) / (area[i_big] - area[: i_big + 1].min())
    i_open = int(np.argmax(a >= open_fraction))
    opening = last_rise(t, a, i_open, closed_fraction)
    candidates = [x for x in (t_ff, crossover, opening) if x is not None and x < t_es]
    t_bs = max(candidates)
    length = t_es - t_bs
    tpg = integral(t, gradient, t_bs, t_es) / length
    q_rms = np.sqrt(integral(t, q * q, t_bs, t_es) / length)
    return {
        "phases": {"forward_flow_start": t_ff, "pressure_crossover": crossover, "opening_start": opening,
                   "ejection_start": t_bs, "ejection_end": t_es},
        "metrics": {"forward_volume": integral(t, q, t_ff, t_es), "transvalvular_pressure_gradient": tpg,
                    "rms_forward_flow": q_rms, "effective_orifice_area": q_rms / (51.6 * np.sqrt(tpg / density)),
                    "ejection_duration": length * 1e3},
    }


# The ranking's criteria and which way is better (docs/hemodynamics.md, "Comparison").
CRITERIA = [("fit_error", -1), ("max_orifice_area", 1), ("opening_duration", -1), ("closing_duration", -1),
            ("forward_volume", 1), ("regurgitant_volume", -1), ("strain_variation", -1),
            ("stress_variation", -1), ("regurgitant_fraction", -1), ("transvalvular_pressure_gradient", -1),
            ("effective_orifice_area", 1), ("energy_loss", -1)]


def ranking_totals(metrics_csv, cases):
    rows = {r["metric"]: r for r in csv.DictReader(open(metrics_csv))}
    totals = dict.fromkeys(cases, 0.0)
    for key, better in CRITERIA:
        v = {c: float(rows[key][c]) for c in cases}
        lo, hi = min(v.values()), max(v.values())
        for c in cases:
            if hi - lo <= 1e-3 * max(abs(lo), abs(hi)):
                totals[c] += 1.0
            else:
                totals[c] += (v[c] - lo) / (hi - lo) if better > 0 else (hi - v[c]) / (hi - lo)
    return totals


def main():
    study = pathlib.Path(sys.argv[1])
    cases = sorted(p.name for p in (study / "runs").iterdir() if p.is_dir())
    if len(cases) != 6:
        fail(f"{study}/runs holds {len(cases)} cases, the study has 6")
    for case in cases:
        doc = json.load(open(study / "runs" / case / "report" / "metrics.json"))
        s = doc["settings"]
        mine = recompute(study / "runs" / case / "timeseries.csv", s["closed_area_fraction"],
                         s["open_area_fraction"], s["density_g_per_mL"])
        for name, value in mine["phases"].items():
            stored = doc["phases"][name]
            if abs(stored - value) > 1e-9:
                fail(f"{case}: {name} {stored} in metrics.json, {value} recomputed")
        for name, value in mine["metrics"].items():
            stored = doc["metrics"][name]["value"]
            if abs(stored - value) > 1e-9 * abs(value):
                fail(f"{case}: {name} {stored} in metrics.json, {value} recomputed")
        print(f"ok: {case}: t_bs {mine['phases']['ejection_start'] - doc['phases']['cycle_start']:.4f} s into "
              f"the cycle ({doc['phases']['ejection_start_condition']}), TPG "
              f"{mine['metrics']['transvalvular_pressure_gradient']:.3f} mmHg, EOA "
              f"{mine['metrics']['effective_orifice_area']:.4f} cm^2")
    totals = ranking_totals(study / "metrics.csv", cases)
    for row in csv.DictReader(open(study / "ranking.csv")):
        if abs(float(row["total"]) - totals[row["case"]]) > 1e-9:
            fail(f"ranking.csv: {row['case']} total {row['total']}, recomputed {totals[row['case']]}")
    print("ok: ranking totals " + ", ".join(f"{c} {totals[c]:.3f}" for c in cases))


if __name__ == "__main__":
    main()
