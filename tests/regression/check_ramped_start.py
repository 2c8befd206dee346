#!/usr/bin/env python3
"""The aortic-valve case started from rest with its boundary pressures ramped (time.pressure_ramp).

  check_ramped_start.py IBVALVE MPIEXEC CASE RUN_DIR [--set key=value ...]

Applied at once, the Windkessel's 85 mmHg on the outlet slams the nearly closed valve shut: the
backflow reaches about -350 mL/s at 5 ms and the water hammer of its stop about 730 mmHg beside the
leaflets at 7 ms, where a step of 4e-5 s or more blows up (measured 2026-12-01). Ramped over
50 ms the valve closes quasi-statically. Specification: over the first 12 ms at dt = 6e-5 s the run
finishes its steps (exit 0), every row is finite, and the valve flow stays within 150 mL/s of zero
(ramped: 44 mL/s; the sudden start: 350).
"""
import csv
import math
import os
import subprocess
import sys

ibvalve, mpiexec, case, run_dir = sys.argv[1:5]
overrides = sys.argv[5:]
environment = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
command = [mpiexec, "--oversubscribe", "-n", "1", ibvalve, "run", case, "-o", run_dir, "--overwrite",
           "--stop-after-steps", "200", "--set", "time.step=6e-5", "--set", "time.pressure_ramp=0.05",
           "--set", "output.every=5", "--set", "output.fields_interval=0", "--set", "checkpoint.every=0",
           "--set", "report.plots=false", *overrides]
result = subprocess.run(command, env=environment, capture_output=True, text=True)
if result.returncode != 0:
    sys.exit(f"FAIL: exit {result.returncode}\n{result.stdout}\n{result.stderr}")
with open(os.path.join(run_dir, "timeseries.csv"), newline="") as f:
    rows = [row for row in csv.DictReader(line for line in f if not line.startswith("#"))]
flow_key = next(k for k in rows[0] if k.split(" ")[0] == "Q_valve")
time_key = next(k for k in rows[0] if k.split(" ")[0] == "t")
last_time = float(rows[-1][time_key])
if last_time < 0.0119:
    sys.exit(f"FAIL: the series ends at t = {last_time} s, before 12 ms")
for row in rows:
    if not all(math.isfinite(float(v)) for v in row.values()):
        sys.exit(f"FAIL: a row that is not finite: {row}")
largest = max(abs(float(row[flow_key])) for row in rows)
print(f"largest |Q_valve| over the first {last_time * 1e3:.1f} ms: {largest:.1f} mL/s")
if largest > 150.0:
    sys.exit(f"FAIL: |Q_valve| reached {largest:.1f} mL/s (a ramped start stays within 150)")
print("ok")
