#!/usr/bin/python3
"""The ventricle's figures of one cycle of a run, recomputed from its timeseries.csv alone.

  closed_loop_figures.py RUN_DIR [RUN_DIR...] [--period 0.8] [--cycle 2]

For each run folder: the cycle [t0 + (k-1) T, t0 + k T] (t0 the first row) of its timeseries.csv, and
over the rows inside it

  EDV, ESV = max, min V_LV;  SV = EDV - ESV;  EF = SV / EDV;
  SW = -sum over the rows of (p_i + p_{i-1})/2 (V_i - V_{i-1}), p the loop's ventricle p_LV (P_LV when
       the series has no p_LV), mmHg mL -> mJ (x 0.133322);
  E_L = sum of the trapezoids of (P_LV - P_Ao) Q_valve dt, in mJ (the probes' pressures, as the report's
        energy loss); E_L / SW;
  V_F = the trapezoids of Q_valve where it is positive (all forward flow in the cycle);
  peak P_LV (probe), peak p_LV (the loop's ventricle), P_Ao's largest and smallest (probe);
  the forward lobe: the rows around the largest Q_valve while Q_valve > 0 (V_F_lobe its volume); the
  ejection window: its part after P_nlv - P_nao last rose through 0 before the peak flow; TPG the mean
  of P_nlv - P_nao over it, Q_rms, EOA = Q_rms / (51.6 sqrt(TPG)) (density 1 g/mL); RF = all backflow
  after the lobe over V_F_lobe; the largest orifice_area.

A run without V_LV (a prescribed-pressure run) gets the same but the volume figures. Written for
docs/notebook/closed-loop-2026-12-06.md as a second, independent computation beside the report's metrics.json:
it shares no code with hemodynamics/ (numpy only), and its energy loss and V_F are simpler definitions
(whole cycle, all forward flow) than the report's phases, so they agree with the report to the
sampling and the phase choice, not bit for bit.
"""
import argparse
import csv
import json
import pathlib

import numpy as np

MMHG_ML_IN_MJ = 133.322e-6 * 1e3  # 1 mmHg mL = 133.322 Pa x 1e-6 m^3 = 1.33322e-4 J


def read(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header = rows[0]
    data = np.array([[float(x) for x in r] for r in rows[1:]])
    return {name: data[:, i] for i, name in enumerate(header)}


def trapezoid(t, y):
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t)))


def ejection(c):
    """The forward lobe, the ejection window and their figures (simpler rules than the report's)."""
    t, q = c["t"], c["Q_valve"]
    peak = int(np.argmax(q))
    a = peak
    while a > 0 and q[a - 1] > 0:
        a -= 1
    b = peak
    while b < len(q) - 1 and q[b + 1] > 0:
        b += 1
    dp = c["P_nlv"] - c["P_nao"]
    start = a
    for i in range(peak, a, -1):
        if dp[i - 1] <= 0 < dp[i]:
            start = i
            break
    w = slice(start, b + 1)
    span = t[b] - t[start]
    tpg = trapezoid(t[w], dp[w]) / span
    q_rms = (trapezoid(t[w], q[w] ** 2) / span) ** 0.5
    back = -trapezoid(t[b:], np.minimum(q[b:], 0.0))
    lobe = trapezoid(t[a:b + 1], q[a:b + 1])
    out = {"V_F_lobe_mL": lobe, "ejection_ms": 1e3 * span, "TPG_mmHg": tpg, "Q_rms_mL_per_s": q_rms,
           "EOA_cm2": q_rms / (51.6 * tpg ** 0.5) if tpg > 0 else None, "RF_percent": 100.0 * back / lobe,
           "Q_max_mL_per_s": float(q.max())}
    if "orifice_area" in c:
        out["GOA_max_cm2"] = float(c["orifice_area"].max())
    return out


def figures(run, period, cycle):
    s = read(pathlib.Path(run) / "timeseries.csv")
    t = s["t"]
    t0 = t[0] + (cycle - 1) * period
    t1 = t0 + period
    inside = (t >= t0 - 1e-9) & (t <= t1 + 1e-9)
    c = {k: v[inside] for k, v in s.items()}
    tc = c["t"]
    out = {"run": str(run), "cycle": [float(tc[0]), float(tc[-1])], "rows": int(inside.sum())}
    q = c["Q_valve"]
    out["V_F_mL"] = trapezoid(tc, np.maximum(q, 0.0))
    out["E_L_mJ"] = trapezoid(tc, (c["P_LV"] - c["P_Ao"]) * q) * MMHG_ML_IN_MJ
    out["peak_P_LV_probe_mmHg"] = float(c["P_LV"].max())
    out["P_Ao_max_mmHg"], out["P_Ao_min_mmHg"] = float(c["P_Ao"].max()), float(c["P_Ao"].min())
    out.update(ejection(c))
    if "V_LV" in c:
        v = c["V_LV"]
        p = c["p_LV"] if "p_LV" in c else c["P_LV"]
        edv, esv = float(v.max()), float(v.min())
        sw = -float(np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(v))) * MMHG_ML_IN_MJ
        out.update({"EDV_mL": edv, "ESV_mL": esv, "SV_mL": edv - esv, "EF_percent": 100.0 * (edv - esv) / edv,
                    "SW_mJ": sw, "E_L_over_SW_percent": 100.0 * out["E_L_mJ"] / sw,
                    "peak_p_LV_mmHg": float(p.max()),
                    "V_LV_change_mL": float(v[-1] - v[0])})
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--period", type=float, default=0.8)
    parser.add_argument("--cycle", type=int, default=2)
    args = parser.parse_args()
    print(json.dumps([figures(r, args.period, args.cycle) for r in args.runs], indent=1))


if __name__ == "__main__":
    main()
