#!/usr/bin/env python3
"""Checks the uncertainties `ibvalve study` leaves for a study with an [[uncertainty]] source.
  check_study_uncertainty.py STUDY_DIR SOURCE CASE...
For every case: uncertainty.json holds, per metric, |variant - case| for the source (the variant's
metrics read from <STUDY_DIR>/uncertainty/<source>/<case>/report/metrics.json) and their root-sum-square,
and, the source being shared (common to the cases), the signed shift variant - case; the case's
report/metrics.json carries them ("uncertainty", "uncertainty_sources", "uncertainty_shared") and
report.md shows "value ± u" and the source's signed shift marked shared; the comparison shows the ±
figures and how often each rank holds. Exits 1 on a failure.
"""
import json
import math
import sys
from pathlib import Path

study, source, names = Path(sys.argv[1]), sys.argv[2], sys.argv[3:]
failures = []
for name in names:
    case = json.loads((study / name / "report" / "metrics.json").read_text())["metrics"]
    variant = json.loads((study / "uncertainty" / source.replace(" ", "_") / name / "report" / "metrics.json").read_text())["metrics"]
    stored = json.loads((study / name / "uncertainty.json").read_text())
    checked = 0
    for key, metric in case.items():
        a, b = metric.get("value"), variant.get(key, {}).get("value")
        if not isinstance(a, (int, float)) or not isinstance(b, (int, float)):
            continue
        u = abs(b - a)
        if abs(stored[key]["sources"][source] - u) > 1e-12 * max(1.0, abs(a)):
            failures.append(f"{name}: {key}: uncertainty.json says {stored[key]['sources'][source]}, |{b} - {a}| = {u}")
        if abs(metric.get("uncertainty", -1.0) - u) > 1e-12 * max(1.0, abs(a)):
            failures.append(f"{name}: {key}: metrics.json's uncertainty {metric.get('uncertainty')} is not {u}")
        for where, shifts in (("uncertainty.json", stored[key].get("shared", {})),
                              ("metrics.json", metric.get("uncertainty_shared", {}))):
            if abs(shifts.get(source, float("nan")) - (b - a)) > 1e-12 * max(1.0, abs(a)):
                failures.append(f"{name}: {key}: {where}'s shared shift {shifts.get(source)} is not {b} - {a}")
        checked += 1
    vf = case["forward_volume"]
    print(f"{name}: {checked} metrics with an uncertainty; V_F {vf['value']:.4f} ± {vf['uncertainty']:.3g} mL "
          f"({source}: the variant's {variant['forward_volume']['value']:.4f})")
    if checked < 10:
        failures.append(f"{name}: only {checked} metrics carry an uncertainty")
    if vf["uncertainty"] <= 0.0:
        failures.append(f"{name}: the variant did not change V_F: the source's overrides were not applied")
    report = (study / name / "report" / "report.md").read_text()
    if " ± " not in report:
        failures.append(f"{name}: report.md shows no ± figure")
    if f"{source} " not in report or "(shared)" not in report:
        failures.append(f"{name}: report.md does not show the source's signed shift marked (shared)")
comparison = (study / "comparison" / "comparison.md").read_text()
for text in (" ± ", "rank held", "the whole order holds in"):
    if text not in comparison:
        failures.append(f"comparison.md lacks '{text}'")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
