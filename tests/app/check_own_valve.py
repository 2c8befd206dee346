#!/usr/bin/env python3
"""`ibvalve check`: a case validated as `ibvalve run` validates it, nothing run or written.

  check_own_valve.py SCENARIO IBVALVE MPIEXEC RANKS SOURCE_DIR WORK_DIR

Scenarios:
  check
      `ibvalve check` of the default valve (examples/aortic_valve/default.toml) and of the lumped
      example: exit 0, one line each, nothing written; of a case with a bad key: exit 2 and the one
      error line `ibvalve run` gives.
Prints what it checked; exits 1 on the first failure.
"""
import os
import pathlib
import subprocess
import sys


def fail(message, result=None):
    if result is not None:
        print(f"--- exit {result.returncode}\n--- stdout:\n{result.stdout}--- stderr:\n{result.stderr}")
    print(f"FAIL: {message}")
    sys.exit(1)


class Runner:
    def __init__(self, ibvalve, mpiexec, ranks, work):
        self.ibvalve, self.mpiexec, self.ranks, self.work = ibvalve, mpiexec, ranks, work

    def __call__(self, *args, ranks=None):
        command = [self.mpiexec, "--oversubscribe", "-n", str(ranks or self.ranks), self.ibvalve]
        return subprocess.run(command + [str(a) for a in args], cwd=self.work, stdin=subprocess.DEVNULL,
                              capture_output=True, text=True, timeout=600)


def error_lines(result):
    return [line for line in result.stderr.splitlines() if line.startswith("error:")]


def check(run, case, source):
    before = sorted(os.listdir(run.work))
    lumped = source / "examples/lumped/default.toml"
    for name, path in (("aortic-valve", case), ("lumped", lumped)):
        result = run("check", path)
        lines = result.stdout.splitlines()
        if result.returncode != 0 or len(lines) != 1 or not lines[0].startswith(f"{path}: a valid {name} case"):
            fail(f"ibvalve check {path}: expected exit 0 and one line", result)
        print(f"ok: {lines[0]}")
    bad = run("check", case, "--set", "fluid.viscosity=-1")
    lines = error_lines(bad)
    if bad.returncode != 2 or len(lines) != 1 or "fluid.viscosity" not in lines[0] or bad.stdout.strip():
        fail("ibvalve check with a bad key: expected exit 2 and one error line naming it", bad)
    print(f"ok: {lines[0]}")
    if sorted(os.listdir(run.work)) != before:
        fail("ibvalve check wrote into the working folder")
    print("ok: nothing written")


def main():
    scenario, ibvalve, mpiexec, ranks, source, work = sys.argv[1:7]
    source, work = pathlib.Path(source).resolve(), pathlib.Path(work).resolve()
    work.mkdir(parents=True, exist_ok=True)
    run = Runner(ibvalve, mpiexec, int(ranks), work)
    case = source / "examples/aortic_valve/default.toml"
    {"check": check}[scenario](run, case, source)


if __name__ == "__main__":
    main()
