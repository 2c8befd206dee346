#!/usr/bin/env python3
"""Acceptance of a full aortic-valve cycle, the reported one (the last of the run's cycles): the run
reached its end without NaN, the valve opened (geometric orifice area above 2 cm^2 at its largest) and
closed, and the report carries every headline metric and the study's structural figures. Closed is the criterion of docs/hemodynamics.md ("Closed"): the late-diastolic leak as an
effective orifice, metric diastolic_leak_area, below 0.1 cm^2. The geometric area of late diastole
(the last quarter of the reported cycle) is printed beside it; a gap of about one cell between the free edges,
which the IB kernel seals, keeps it near 0.2 cm^2. (nightly_aortic_valve_cycle_compare holds the
series to 1e-4 of each column's scale and every metric to 1e-3 of the reference.)
  check_av_cycle.py RUN_DIR
"""
import csv
import json
import math
import sys
from pathlib import Path

run = Path(sys.argv[1])
with open(run / "timeseries.csv", newline="") as f:
    rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
t = [float(r["t"]) for r in rows]
area = [float(r["orifice_area"]) for r in rows]
report = json.loads((run / "report" / "metrics.json").read_text())
metrics = report["metrics"]
start, end = report["phases"]["cycle_start"], report["phases"]["cycle_end"]
print(f"reported cycle: {start:.4f} to {end:.4f} s")
failures = []
if not rows or t[-1] < end - 1e-9 or end - start < 0.8 - 1e-9:
    failures.append(f"the run stopped at t = {t[-1] if t else 0} s, before the end of a whole cycle")
for r in rows:
    if not all(math.isfinite(float(v)) for v in r.values()):
        failures.append(f"not finite at t = {r['t']}")
        break
cycle = [a for ti, a in zip(t, area) if start <= ti <= end]
late = [a for ti, a in zip(t, area) if end - 0.25 * (end - start) <= ti <= end]
print(f"geometric orifice area: largest {max(cycle):.4f} cm^2, largest in late diastole "
      f"{max(late) if late else float('nan'):.4f} cm^2")
if max(cycle) <= 2.0:
    failures.append(f"the valve did not open: largest orifice area {max(cycle):.4f} cm^2 (needs > 2)")
leak = (metrics.get("diastolic_leak_area") or {}).get("value")
print(f"late-diastolic leak orifice (EROA_d): {leak} cm^2")
if not isinstance(leak, (int, float)) or not math.isfinite(leak) or leak >= 0.1:
    failures.append(f"the valve did not stay closed: late-diastolic leak orifice {leak} cm^2 (needs < 0.1)")
for key in ("forward_volume", "peak_forward_flow", "regurgitant_fraction", "transvalvular_pressure_gradient",
            "effective_orifice_area", "energy_loss", "peak_velocity_open", "leaflet_displacement_max_open",
            "strain_variation", "stress_variation", "fit_error"):
    entry = metrics.get(key)
    value = entry.get("value") if isinstance(entry, dict) else None
    print(f"{key}: {value} {entry.get('unit', '') if isinstance(entry, dict) else ''}")
    if not isinstance(value, (int, float)) or not math.isfinite(value):
        failures.append(f"metric {key} missing or not finite")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
