#!/usr/bin/env python3
"""Checks what `ibvalve study` left: every case's run folder with its report, under its study name,
and the comparison of exactly those cases, whose metrics are the cases' own.
  check_study.py STUDY_DIR CASE...
"""
import csv
import json
import sys
from pathlib import Path

study, names = Path(sys.argv[1]), sys.argv[2:]
failures = []
metrics = {}
for name in names:
    doc = json.loads((study / name / "report" / "metrics.json").read_text())
    metrics[name] = {k: v.get("value") for k, v in doc["metrics"].items() if isinstance(v, dict)}
    config = (study / name / "config.toml").read_text()
    if f"name = '{name}'" not in config and f'name = "{name}"' not in config:
        failures.append(f"{name}: config.toml does not carry the case name")
with open(study / "comparison" / "metrics.csv", newline="") as f:
    rows = list(csv.reader(f))
print("comparison/metrics.csv:", rows[0])
compared = set(rows[0][3:])  # metric, symbol, unit, then one column per case
print("cases in the comparison:", sorted(compared))
for name in names:
    if name not in compared:
        failures.append(f"{name} missing from the comparison")
a, b = (metrics[n].get("forward_volume") for n in names[:2])
print(f"forward volume: {names[0]} {a}, {names[1]} {b}")
if a is None or b is None or a == b:
    failures.append("the cases' overrides made no difference to the forward volume")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
