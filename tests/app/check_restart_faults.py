#!/usr/bin/env python3
"""Runs that survive faults and mistakes (issue 20): each scenario is one specification.

  check_restart_faults.py SCENARIO IBVALVE MPIEXEC RANKS CASE WORK_DIR [--set key=value ...]

Scenarios (CASE is a case file of any model; the lumped one runs in a second):
  overwrite
      `run -o DIR --overwrite` of case B into the folder of an earlier run of case A (checkpoints,
      report) removes A's outputs first: B's checkpoints are the only ones, B's own survive pruning,
      and `--restart` continues B to B's uninterrupted series.
Prints what it checked; exits 1 on the first failure.
"""
import argparse
import pathlib
import shutil
import subprocess
import sys

FAIL = 1


def fail(message, output=None):
    if output is not None:
        print(output)
    print(f"FAIL: {message}")
    sys.exit(FAIL)


class Runner:
    def __init__(self, args):
        self.launch = [args.mpiexec, "--oversubscribe", "-n", args.ranks, args.ibvalve, "run"]
        self.case = args.case
        self.sets = [f"--set={s}" for s in args.set]

    def command(self, folder, *extra, restart=False):
        if restart:
            return self.launch + ["--restart", str(folder)] + list(extra)
        return self.launch + [self.case, "-o", str(folder)] + self.sets + list(extra)

    def run(self, folder, *extra, restart=False, expect=0):
        command = self.command(folder, *extra, restart=restart)
        print("+", " ".join(command), flush=True)
        result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        output = result.stdout + result.stderr
        if result.returncode != expect:
            fail(f"exit code {result.returncode}, expected {expect}", output)
        return result


def error_lines(result):
    return [line for line in result.stderr.splitlines() if line.startswith("error:")]


def one_error_line(result, *words):
    lines = error_lines(result)
    if len(lines) != 1:
        fail(f"{len(lines)} error lines, expected one", result.stdout + result.stderr)
    for word in words:
        if word not in lines[0]:
            fail(f"the error line does not name {word}: {lines[0]}")
    print(f"one error line: {lines[0]}")
    return lines[0]


def checkpoints(folder):
    return sorted(p.name for p in (folder / "checkpoints").glob("step_*.h5"))


def same_series(whole, continued, what):
    a, b = (whole / "timeseries.csv").read_bytes(), (continued / "timeseries.csv").read_bytes()
    if a != b:
        x, y = a.decode().splitlines(), b.decode().splitlines()
        for i, (p, q) in enumerate(zip(x, y)):
            if p != q:
                fail(f"{what}: timeseries.csv differs first at line {i + 1}:\n  whole: {p}\n  {what}: {q}")
        fail(f"{what}: timeseries.csv has {len(x)} lines uninterrupted, {len(y)} {what}")
    print(f"{what}: timeseries.csv identical byte for byte to the uninterrupted run's "
          f"({len(a.decode().splitlines()) - 1} rows)")


def overwrite_scenario(runner, work, steps_b, every):
    folder, reference = work / "folder", work / "reference_b"
    case_b = ["--set=valve.max_area_fraction=0.5", f"--set=checkpoint.every={every}"]
    runner.run(folder, "-q", f"--set=checkpoint.every={every}")  # case A, whole: checkpoints and report
    old = checkpoints(folder)
    print(f"case A left {old} and report/: {(folder / 'report').exists()}")
    runner.run(reference, "-q", *case_b)
    runner.run(folder, "-q", "--overwrite", *case_b, f"--stop-after-steps={steps_b}")
    found = checkpoints(folder)
    expected = [f"step_{steps_b - every:09d}.h5", f"step_{steps_b:09d}.h5"]
    if found != expected:
        fail(f"after --overwrite with case B stopped at step {steps_b}: checkpoints {found}, expected {expected}")
    if (folder / "report").exists():
        fail("case A's report/ is still in the folder")
    print(f"--overwrite: the folder holds case B's checkpoints only {found}, no report of case A")
    result = runner.run(folder, restart=True)
    if f"step_{steps_b:09d}.h5" not in result.stdout:
        fail("the restart did not continue case B's checkpoint", result.stdout)
    same_series(reference, folder, "case B restarted")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("scenario")
    parser.add_argument("ibvalve")
    parser.add_argument("mpiexec")
    parser.add_argument("ranks")
    parser.add_argument("case")
    parser.add_argument("work")
    parser.add_argument("--set", action="append", default=[], help="overrides of every run of CASE")
    parser.add_argument("--every", type=int, default=1000, help="checkpoint.every")
    parser.add_argument("--stop", type=int, default=5000, help="--stop-after-steps of the stopped runs")
    args = parser.parse_args()
    work = pathlib.Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    runner = Runner(args)
    s = args.scenario
    if s == "overwrite":
        overwrite_scenario(runner, work, args.stop, args.every)
    else:
        fail(f"unknown scenario {s}")
    print("PASS")


if __name__ == "__main__":
    main()
