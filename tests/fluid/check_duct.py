"""Checks a short run of examples/duct (coarse): the flow enters through x_lower and leaves through
x_upper at the same rate, nothing crosses the walls, the centre pressure is half the inlet pressure,
and the velocity stays divergence-free (run with fluid.rtol = 1e-12). Usage: check_duct.py RUN_DIR"""
import csv
import sys
from pathlib import Path

# The '#' line under the header holds the units.
rows = list(csv.DictReader(line for line in open(Path(sys.argv[1]) / "timeseries.csv") if not line.startswith("#")))
assert len(rows) >= 5, len(rows)
mmHg = 1333.22
last = rows[-1]
q_in, q_out = -float(last["outflow_x_lower"]), float(last["outflow_x_upper"])
assert q_out > 0.0, q_out
assert abs(q_in - q_out) < 1e-8 * q_out, (q_in, q_out)
for side in ("y_lower", "y_upper", "z_lower", "z_upper"):
    assert abs(float(last["outflow_" + side])) < 1e-14, (side, last["outflow_" + side])
# Started from rest with x-independent data, the flow stays the same at every cross-section (the
# traction sides impose du/dx = 0), so the pressure is linear in x: at the centre, half the inlet
# pressure (0.1 mmHg, fully ramped up by t = 0.05 s).
assert abs(float(last["p_center"]) - 0.05 * mmHg) < 1e-3 * 0.05 * mmHg, last["p_center"]
for row in rows[1:]:
    h = 0.25
    assert float(row["max_divergence"]) < 1e-10 * max(float(row["max_velocity"]), 1e-30) / h, row
print(f"duct: Q in {q_in:.6f} out {q_out:.6f} mL/s, p_center {float(last['p_center']):.3f} dyn/cm^2")
