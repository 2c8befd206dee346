#!/usr/bin/env python3
"""An interval whose sub-steps go unstable is taken again from its start (time.retries).

    check_retries.py IBVALVE MPIEXEC RANKS CASE RUN_DIR [--set KEY=VALUE ...]

CASE with the adaptive step and sub-steps past the structure's limit (the test sets time.safety = 2), so
that an interval blows up early:
  - with time.retries = 0 the run stops there: exit 3, "error: aortic-valve: step N (t = ...)" and
    "the run stopped; all output so far is kept", diagnostics.csv up to step N - 1;
  - with the default retries the same run warns "step N taken again from t = ... in 2m sub-steps (1 of 3
    time.retries): <the same error>", goes on to its end (exit 0), and diagnostics.csv says so: step N
    has retries >= 1 and the sub-steps the last warning names; the rows before step N are those of the
    first run to the digit (the interval's snapshot changes nothing); the step after a retried interval
    is at most `grow` (1.2) times the one that went through (the cap, app/adaptive_step.hpp).
Prints what it checked; exits 1 on the first failure.
"""
import argparse
import csv
import pathlib
import re
import shutil
import subprocess
import sys


def fail(message):
    sys.exit("FAIL: " + message)


def run(args, run_dir, extra):
    cmd = [args.mpiexec, "--oversubscribe", "-n", str(args.ranks), args.ibvalve, "run", args.case,
           "-o", str(run_dir), "--overwrite"] + [s for kv in args.set for s in ("--set", kv)] + extra
    result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            stdin=subprocess.DEVNULL)
    return result.returncode, result.stdout


def diagnostics(run_dir):
    with open(run_dir / "diagnostics.csv", newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    return rows[0], rows[1:]


def main():
    parser = argparse.ArgumentParser()
    for name in ("ibvalve", "mpiexec", "ranks", "case", "run_dir"):
        parser.add_argument(name)
    parser.add_argument("--set", action="append", default=[])
    args = parser.parse_args()
    base = pathlib.Path(args.run_dir)
    shutil.rmtree(base, ignore_errors=True)
    stopped, retried = base / "no_retries", base / "retries"

    code, out = run(args, stopped, ["--set", "time.retries=0"])
    if code != 3:
        fail(f"time.retries = 0: exit {code}, expected 3 (the interval blowing up stops the run):\n{out}")
    error = re.search(r"^error: (aortic-valve: step (\d+) \(t = [^)]*\): .*)$", out, re.M)
    if not error or "the run stopped; all output so far is kept" not in out:
        fail(f"time.retries = 0: no step's error and stop message:\n{out}")
    failed_step = int(error.group(2))
    columns, rows_stopped = diagnostics(stopped)
    if [int(r[0]) for r in rows_stopped] != list(range(1, failed_step)):
        fail(f"time.retries = 0: diagnostics.csv holds steps {[r[0] for r in rows_stopped]}, "
             f"expected 1..{failed_step - 1}")

    code, out = run(args, retried, [])
    if code != 0:
        fail(f"with retries: exit {code}, expected 0:\n{out}")
    warnings = re.findall(r"^warning: step (\d+) taken again from t = (\S+) s in (\d+) sub-steps "
                          r"\((\d+) of 3 time.retries\): (.*)$", out, re.M)
    if not warnings:
        fail(f"with retries: no interval was taken again:\n{out}")
    first = warnings[0]
    if int(first[0]) != failed_step or first[3] != "1" or first[4] != error.group(1):
        fail(f"the first retry {first} is not step {failed_step}'s, with its error {error.group(1)!r}")
    columns_retried, rows = diagnostics(retried)
    c = {name: i for i, name in enumerate(columns_retried)}
    if "retries" not in c:
        fail(f"diagnostics.csv has no retries column: {columns_retried}")
    skip = {c["wall_step"]}
    for before, again in zip(rows_stopped, rows):
        if [v for i, v in enumerate(before) if i not in skip] != [v for i, v in enumerate(again) if i not in skip]:
            fail(f"step {before[0]} differs with the snapshots taken: {before} against {again}")
    by_step = {int(r[0]): r for r in rows}
    for step, _, substeps, attempt, _ in warnings:
        last = [w for w in warnings if w[0] == step][-1]
        row = by_step[int(step)]
        if int(row[c["retries"]]) != int(last[3]) or int(row[c["substeps"]]) != int(last[2]):
            fail(f"step {step}: diagnostics.csv says {row[c['retries']]} retries, {row[c['substeps']]} "
                 f"sub-steps; the warnings {last[3]} and {last[2]}")
        after = by_step.get(int(step) + 1)
        if after and float(after[c["dt"]]) > 1.2 * float(row[c["dt"]]) * (1 + 1e-9):
            fail(f"step {int(step) + 1}'s sub-step {after[c['dt']]} s is more than 1.2 times step {step}'s "
                 f"{row[c['dt']]} s, which went through after a retry")
    print(f"time.retries = 0: stopped at step {failed_step} (exit 3, {len(rows_stopped)} rows kept); with "
          f"retries: {len(warnings)} intervals taken again (the first step {failed_step}, "
          f"{first[2]} sub-steps), {len(rows)} rows to the end, the rows before step {failed_step} as "
          f"without snapshots, each retried interval's row and the cap after it as the warnings say")


if __name__ == "__main__":
    main()
