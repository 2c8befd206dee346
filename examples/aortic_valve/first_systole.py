#!/usr/bin/python3
"""The first systole of aortic-valve runs, from their timeseries.csv: how wide the valve opens and how
much of that opening the jet uses.

usage: first_systole.py RUN_DIR... [--start 0] [--end 0.45]

For each run, over START <= t <= END (the first cycle's ejection; a run stopped there with --set
time.end=0.45 needs no full cycle; --start 0.8 --end 1.25 for the second cycle's): the largest geometric orifice GOA_max; the peak flow Q_max and, at that instant,
where dQ/dt = 0 and the drop across the valve is the jet's alone, the jet's area
A_jet = Q / sqrt(2 (P_nlv - P_nao) / rho) against the orifice then; the ejection window [t_bs, t_es]
by the report's rule (docs/hemodynamics.md: the valve open and the flow forward) and on it the TPG,
Q_rms and EOA = Q_rms / (51.6 sqrt(TPG / rho)), with EOA / GOA_max; V_F. One Markdown table row a run.
The window's arithmetic is tests/regression/check_study_results.py's (numpy, independent of the C++).
"""
import argparse
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tests" / "regression"))
from check_study_results import integral, last_rise  # noqa: E402

MMHG = 1333.22  # dyn/cm^2
RHO = 1.0  # g/mL


def first_systole(series, end, start=0.0):
    d = np.genfromtxt(series, delimiter=",", names=True, comments="#")
    keep = (d["t"] >= start - 1e-12) & (d["t"] <= end + 1e-12)
    t, q, area = d["t"][keep], d["Q_valve"][keep], d["orifice_area"][keep]
    gradient = (d["P_nlv"] - d["P_nao"])[keep]
    i = int(np.argmax(q))
    j = i
    while j + 1 < len(q) and q[j + 1] > 0:
        j += 1
    if j + 1 == len(q):
        return None  # forward flow has not ended by END
    t_es = t[j] - q[j] * (t[j + 1] - t[j]) / (q[j + 1] - q[j])
    big = int(np.argmax(area))
    normalised = (area - area[: big + 1].min()) / (area[big] - area[: big + 1].min())
    opening = last_rise(t, normalised, int(np.argmax(normalised >= 0.9)), 0.05)
    t_ff = last_rise(t, q, i, 0.0)
    t_bs = max(x for x in (t_ff, last_rise(t, gradient, i, 0.0), opening) if x is not None and x < t_es)
    length = t_es - t_bs
    tpg = integral(t, gradient, t_bs, t_es) / length
    q_rms = np.sqrt(integral(t, q * q, t_bs, t_es) / length)
    eoa = q_rms / (51.6 * np.sqrt(tpg / RHO))
    jet = q[i] / np.sqrt(2.0 * gradient[i] * MMHG / RHO)
    return {"GOA_max (cm^2)": area.max(), "Q_max (mL/s)": q[i], "t_peak (s)": t[i],
            "dP at peak (mmHg)": gradient[i], "A_jet (cm^2)": jet, "GOA at peak (cm^2)": area[i],
            "A_jet / GOA": jet / area[i], "t_bs (s)": t_bs, "t_es (s)": t_es, "TPG (mmHg)": tpg,
            "Q_rms (mL/s)": q_rms, "EOA (cm^2)": eoa, "EOA / GOA_max": eoa / area.max(),
            "V_F (mL)": integral(t, q, t_ff, t_es)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", type=pathlib.Path)
    parser.add_argument("--start", type=float, default=0.0, help="s: the start of the systole's cycle")
    parser.add_argument("--end", type=float, default=0.45, help="s: the end of the systole")
    args = parser.parse_args()
    header = False
    for run in args.runs:
        r = first_systole(run / "timeseries.csv", args.end, args.start)
        if r is None:
            print(f"{run}: forward flow has not ended by t = {args.end} s")
            continue
        if not header:
            print("| run | " + " | ".join(r) + " |")
            print("|---" * (len(r) + 1) + "|")
            header = True
        print(f"| {run.name} | " + " | ".join(f"{v:.4g}" for v in r.values()) + " |")


if __name__ == "__main__":
    main()
