#!/usr/bin/env python3
"""Acceptance of a full aortic-valve cycle (issue 8): the run finished its cycle without NaN, the
valve opened (geometric orifice area above 2 cm^2 at its largest) and closed (below 0.1 cm^2 all through
late diastole, the last quarter of the cycle), and the report carries every headline metric.
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
failures = []
if not rows or t[-1] < 0.8 - 1e-9:
    failures.append(f"the run stopped at t = {t[-1] if t else 0} s, before the end of the cycle")
for r in rows:
    if not all(math.isfinite(float(v)) for v in r.values()):
        failures.append(f"not finite at t = {r['t']}")
        break
late = [a for ti, a in zip(t, area) if ti >= 0.6]
print(f"orifice area: largest {max(area):.4f} cm^2, largest in late diastole {max(late) if late else float('nan'):.4f} cm^2")
if max(area) <= 2.0:
    failures.append(f"the valve did not open: largest orifice area {max(area):.4f} cm^2 (needs > 2)")
if not late or max(late) >= 0.1:
    failures.append("the valve did not stay closed: orifice area reaches 0.1 cm^2 or more after t = 0.6 s")
metrics = json.loads((run / "report" / "metrics.json").read_text())["metrics"]
for key in ("forward_volume", "peak_forward_flow", "regurgitant_fraction", "transvalvular_pressure_gradient",
            "effective_orifice_area", "energy_loss"):
    entry = metrics.get(key)
    value = entry.get("value") if isinstance(entry, dict) else None
    print(f"{key}: {value} {entry.get('unit', '') if isinstance(entry, dict) else ''}")
    if not isinstance(value, (int, float)) or not math.isfinite(value):
        failures.append(f"metric {key} missing or not finite")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
