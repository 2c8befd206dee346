#!/usr/bin/env python3
"""The lumped closed-loop example (examples/lumped/closed_loop.toml) run through `ibvalve run`.

  check_closed_loop_example.py IBVALVE MPIEXEC CASE RUN_DIR [--set key=value ...]

Runs CASE and checks what the run folder holds:
  - timeseries.csv names every chamber volume (mL), compartment and chamber pressure (mmHg) and valve and
    compartment flow (mL/s) in its header and units line;
  - the blood volume summed from those columns, with each compliance from the run's config.toml,
    stays what it was at the first row to 1e-8 relative (the columns print 12 significant digits; the
    model keeps it to round-off, tests/circulation/test_closed_loop.cpp);
  - the run's summary gives the last beat's figures, and those agree with the same figures read from
    the series' last beat (EDV and ESV as V_LV's largest and smallest value, to 0.05 mL with a row
    every output.every steps);
  - report/metrics.json exists (the aortic valve analysed as the lumped model's valve).
Prints the figures; exits 1 naming the first check that fails.
"""
import csv
import json
import pathlib
import re
import subprocess
import sys
import tomllib

VOLUMES = ["V_LA", "V_LV", "V_RA", "V_RV"]
PRESSURES = ["p_LA", "p_RA", "p_RV", "p_AR_SYS", "p_VEN_SYS", "p_AR_PUL", "p_VEN_PUL"]
FLOWS = ["Q_MV", "Q_AV", "Q_TV", "Q_PV", "Q_AR_SYS", "Q_VEN_SYS", "Q_AR_PUL", "Q_VEN_PUL"]
COMPARTMENTS = {"p_AR_SYS": "systemic_arteries", "p_VEN_SYS": "systemic_veins",
                "p_AR_PUL": "pulmonary_arteries", "p_VEN_PUL": "pulmonary_veins"}


def fail(message):
    sys.exit("FAIL: " + message)


def main():
    ibvalve, mpiexec, case, run_dir = sys.argv[1:5]
    overrides = sys.argv[5:]
    run_dir = pathlib.Path(run_dir)
    command = [mpiexec, "--oversubscribe", "-n", "1", ibvalve, "run", case, "-o", str(run_dir), "--overwrite",
               *overrides]
    p = subprocess.run(command, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=240)
    print(p.stdout + p.stderr)
    if p.returncode != 0:
        fail(f"ibvalve run exited with {p.returncode}")

    with open(run_dir / "timeseries.csv") as f:
        lines = f.readlines()
    units_line = next((line for line in lines if line.startswith("# units: ")), None)
    if units_line is None:
        fail("timeseries.csv has no '# units: ' line")
    lines = [line for line in lines if not line.startswith("#")]
    header, units = next(csv.reader([lines[0]])), next(csv.reader([units_line[len("# units: "):].strip()]))
    unit_of = dict(zip(header, units))
    for names, unit in ((VOLUMES, "mL"), (PRESSURES, "mmHg"), (FLOWS, "mL/s")):
        for name in names:
            if unit_of.get(name) != unit:
                fail(f"timeseries.csv: column {name} missing or not in {unit} (units: {unit_of.get(name)})")
    rows = [dict(zip(header, map(float, r))) for r in csv.reader(lines[1:])]

    config = tomllib.loads((run_dir / "config.toml").read_text())
    circulation = config["circulation"]
    compliance = {p: circulation[c]["compliance"] for p, c in COMPARTMENTS.items()}
    total = [sum(r[v] for v in VOLUMES) + sum(compliance[p] * r[p] for p in COMPARTMENTS) for r in rows]
    drift = max(abs(v - total[0]) for v in total) / total[0]
    print(f"blood volume from the columns: {total[0]:.3f} mL, largest relative change {drift:.1e}")
    if drift > 1e-8:
        fail(f"the blood volume summed from timeseries.csv changes by {drift:.1e} of itself (> 1e-8)")

    match = re.search(r"last beat: EDV ([0-9.]+) mL, ESV ([0-9.]+) mL, SV ([0-9.]+) mL", p.stdout + p.stderr)
    if not match:
        fail("the run's summary has no 'last beat: EDV ... ESV ... SV ...' line")
    edv, esv, sv = map(float, match.groups())
    period = config["report"]["period"]
    t_end = rows[-1]["t"]
    beat = [r["V_LV"] for r in rows if r["t"] >= t_end - period * (1 + 1e-9)]
    print(f"summary: EDV {edv} ESV {esv} SV {sv} mL; series' last beat: V_LV {max(beat):.3f} to {min(beat):.3f} mL")
    if abs(max(beat) - edv) > 0.05 or abs(min(beat) - esv) > 0.05 or abs(sv - (edv - esv)) > 0.02:
        fail("the summary's EDV/ESV/SV do not match the series' last beat")
    if not (run_dir / "report" / "metrics.json").exists():
        fail("no report/metrics.json")
    metrics = json.loads((run_dir / "report" / "metrics.json").read_text())["metrics"]
    print(f"report: forward volume {metrics['forward_volume']['value']} mL")
    print("PASS")


if __name__ == "__main__":
    main()
