#!/usr/bin/env python3
"""The valve timing an LV pressure table gives in the lumped model.

  check_lv_timing.py IBVALVE MPIEXEC CASE WAVEFORM RUN_DIR [CYCLES]

Runs the lumped CASE (examples/lumped/default.toml) on WAVEFORM for CYCLES cycles (default 4) from the
preset's P_Wk(0) = 85 mmHg, analyses every cycle with `ibvalve report --cycle`, prints one Markdown row
per cycle, and checks the last cycle against the study's timing (Zhu et al. 2021, W1FD1: pre-open about
0.08 s; a 0-D valve, which has no leaflets to move, opens a little earlier and is given 0.05-0.11 s):

  forward flow starts (t_bs)        0.05-0.11 s into the cycle
  forward flow ends (t_es)          0.30-0.42 s
  forward volume V_F                70-100 mL
  P_Wk at the cycle's end - start   within 3 mmHg (the Windkessel is periodic)

Exits 1 naming every band missed. The old default table (lv_pressure.csv) misses the first: its
flow starts at 0.13 s.
"""
import csv
import json
import pathlib
import subprocess
import sys

BANDS = [  # (figure, low, high, unit)
    ("t_bs", 0.05, 0.11, "s"),
    ("t_es", 0.30, 0.42, "s"),
    ("V_F", 70.0, 100.0, "mL"),
    ("dP_Wk", -3.0, 3.0, "mmHg"),
]


def run(prefix, *args):
    p = subprocess.run(prefix + [str(a) for a in args], stdin=subprocess.DEVNULL, capture_output=True,
                       text=True, timeout=240)
    if p.returncode != 0:
        print(p.stdout + p.stderr)
        sys.exit(f"FAIL: {' '.join(str(a) for a in args[:2])} exited with {p.returncode}")


def interpolate(times, values, t):
    for i in range(1, len(times)):
        if times[i] >= t:
            s = (t - times[i - 1]) / (times[i] - times[i - 1])
            return values[i - 1] + s * (values[i] - values[i - 1])
    return values[-1]


def cycle_figures(run_dir, times, p_wk):
    doc = json.loads((run_dir / "report" / "metrics.json").read_text())
    phases, metrics = doc["phases"], doc["metrics"]
    t0, t1 = phases["cycle_start"], phases["cycle_end"]
    value = lambda key: metrics[key]["value"]
    return {
        "t_bs": phases["ejection_start"] - t0,
        "t_es": phases["ejection_end"] - t0,
        "t_c": phases["closure"] - t0,
        "Q_max": value("peak_forward_flow"),
        "V_F": value("forward_volume"),
        "V_R": value("regurgitant_volume"),
        "P_Ao": f"{value('systolic_aortic_pressure'):.1f}/{value('diastolic_aortic_pressure'):.1f}",
        "P_Wk start": interpolate(times, p_wk, t0),
        "P_Wk end": interpolate(times, p_wk, t1),
        "dP_Wk": interpolate(times, p_wk, t1) - interpolate(times, p_wk, t0),
    }


def main():
    if len(sys.argv) not in (6, 7):
        sys.exit(__doc__)
    ibvalve, mpiexec, case, waveform, run_dir = sys.argv[1:6]
    cycles = int(sys.argv[6]) if len(sys.argv) == 7 else 4
    run_dir = pathlib.Path(run_dir)
    prefix = [mpiexec, "--oversubscribe", "-n", "1", ibvalve]
    run(prefix, "run", case, "-o", run_dir, "--overwrite", "-q", "--set", f"time.cycles={cycles}",
        "--set", "report.plots=false", "--set", f"lv_pressure.file={json.dumps(str(pathlib.Path(waveform).resolve()))}")
    with open(run_dir / "timeseries.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    times = [float(r["t"]) for r in rows]
    p_wk = [float(r["P_Wk"]) for r in rows]
    print(f"{pathlib.Path(waveform).name} in the lumped model, {cycles} cycles from P_Wk(0) = {p_wk[0]:g} mmHg")
    names = ["t_bs", "t_es", "t_c", "Q_max", "V_F", "V_R", "P_Ao", "P_Wk start", "P_Wk end", "dP_Wk"]
    print("| cycle | " + " | ".join(names) + " |")
    print("|---" * (len(names) + 1) + "|")
    for k in range(cycles):  # the last one last, so report/ is the last cycle's, as the run wrote it
        run(prefix, "report", run_dir, "--no-plots", "--cycle", k + 1)
        figures = cycle_figures(run_dir, times, p_wk)
        shown = [f if isinstance(f, str) else f"{f:.3f}" if abs(f) < 1 else f"{f:.1f}"
                 for f in (figures[n] for n in names)]
        print(f"| {k + 1} | " + " | ".join(shown) + " |")
    missed = [f"{name} = {figures[name]:.3f} {unit} is outside [{low}, {high}]"
              for name, low, high, unit in BANDS if not low <= figures[name] <= high]
    for line in missed:
        print(f"FAIL: last cycle: {line}")
    if missed:
        sys.exit(1)
    print("the last cycle is within every band: " +
          ", ".join(f"{name} in [{low}, {high}] {unit}" for name, low, high, unit in BANDS))


if __name__ == "__main__":
    main()
