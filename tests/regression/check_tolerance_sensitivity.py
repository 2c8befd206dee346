#!/usr/bin/env python3
"""Checks that a stored reference's tolerances can fail: a check that passes whatever the run says
catches nothing.

  check_tolerance_sensitivity.py LIST ID COMPARE_RUNS [--move 0.01]

Reads ID's compare_runs.py tolerances from LIST (nightly.txt or cases.txt, `id | run | tolerances`)
and its reference from reference/ID/ beside LIST, then runs compare_runs.py on copies of the reference:

* the reference itself passes;
* every metric of metrics.json moved by MOVE (relative, 1 % by default) fails, and names that metric;
* every time-series column scaled by 1 + MOVE fails, and names that column;
* every metric moved by a tenth of its tolerance still passes (the tolerance is not zero).

Needs no run: it judges the tolerances against the reference's own numbers.
"""
import argparse
import json
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path


def tolerances_of(list_file, case_id):
    for line in list_file.read_text().splitlines():
        if line.startswith("#") or "|" not in line:
            continue
        fields = [f.strip() for f in line.split("|")]
        if fields[0] == case_id:
            return shlex.split(fields[2])
    sys.exit(f"{list_file}: no case '{case_id}'")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("list", type=Path)
    parser.add_argument("id")
    parser.add_argument("compare_runs", type=Path)
    parser.add_argument("--move", type=float, default=0.01)
    args = parser.parse_args()
    sys.path.insert(0, str(args.compare_runs.parent))
    import compare_runs

    reference = args.list.parent / "reference" / args.id
    words = tolerances_of(args.list, args.id)
    metrics_rtol = compare_runs.metrics_tolerance(compare_runs.argument_parser().parse_args([".", "."] + words))
    series_text = (reference / "timeseries.csv").read_text()
    metrics_doc = json.loads((reference / "metrics.json").read_text())
    failures = []

    def compare(series, doc):
        with tempfile.TemporaryDirectory() as tmp:
            run = Path(tmp)
            (run / "report").mkdir()
            (run / "timeseries.csv").write_text(series)
            (run / "report" / "metrics.json").write_text(json.dumps(doc))
            out = subprocess.run([sys.executable, str(args.compare_runs), str(reference), str(run)] + words,
                                 capture_output=True, text=True)
            return out.returncode, out.stdout

    code, _ = compare(series_text, metrics_doc)
    print(f"{args.id}: tolerances {' '.join(words)}; the reference against itself: exit {code}")
    if code != 0:
        failures.append("the reference does not pass against itself")

    numeric = [k for k in compare_runs.read_metrics(reference / "metrics.json")
               if isinstance(metrics_doc["metrics"][k], dict)]
    for key in numeric:
        value = metrics_doc["metrics"][key]["value"]
        if value == 0:
            print(f"  metric {key}: 0, no relative move")
            continue
        for factor, must_fail in ((1 + args.move, True), (1 - args.move, True), (1 + 0.1 * metrics_rtol, False)):
            doc = json.loads(json.dumps(metrics_doc))
            doc["metrics"][key]["value"] = value * factor
            code, out = compare(series_text, doc)
            named = f"FAIL: metric {key}:" in out
            if must_fail and not (code == 1 and named):
                failures.append(f"metric {key} x {factor:g} passes")
            if not must_fail and code != 0:
                failures.append(f"metric {key} x {factor:g} (a tenth of its tolerance) fails")
    print(f"  {len(numeric)} metrics: each moved by +-{args.move:g} fails, by {0.1 * metrics_rtol:g} passes")

    lines = series_text.splitlines()
    body = [i for i, l in enumerate(lines) if l and not l.startswith("#")]
    header = lines[body[0]].split(",")
    for c, name in enumerate(header):
        if name == "t":
            continue
        moved = list(lines)
        for i in body[1:]:
            cells = moved[i].split(",")
            cells[c] = repr(float(cells[c]) * (1 + args.move))
            moved[i] = ",".join(cells)
        code, out = compare("\n".join(moved) + "\n", metrics_doc)
        if not (code == 1 and f"FAIL: column {name}:" in out):
            failures.append(f"column {name} x {1 + args.move:g} passes")
    print(f"  {len(header) - 1} series columns: each scaled by {1 + args.move:g} fails")

    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
