#!/usr/bin/python3
"""The aortic-valve case on two nested levels against one uniform grid of the same finest spacing.

  bench_aortic_valve_levels.py IBVALVE [--case paper.toml] [--steps 40] [--ranks 1 2] [--mpiexec mpiexec]

Runs the case (default: examples/aortic_valve/paper.toml, the study's 8 x 8 x 14 cm box with level 0
20 x 20 x 32 and a ratio-4 level around the valve and tube) for --steps steps, then the same case on the
uniform grid of its finest spacing (fluid.cells times the ratio, nested.ratios = []), on each rank count.
Prints per run: the time per coupled step and its parts as the run reports them (set-up and the first
step's solver set-ups included in that average; use enough steps), the nested fluid's parts and
iterations, the whole process's wall time and the peak memory of the largest process. Figures only;
nothing passes or fails.
"""
import argparse
import os
import pathlib
import re
import sys
import tempfile
import tomllib

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from process_figures import run  # noqa: E402


def main():
    here = pathlib.Path(__file__).resolve()
    source = here.parents[2] if (here.parents[2] / "examples").is_dir() else pathlib.Path.cwd()
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("ibvalve")
    parser.add_argument("--case", type=pathlib.Path, default=source / "examples/aortic_valve/paper.toml")
    parser.add_argument("--steps", type=int, default=40)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--mpiexec", default="mpiexec")
    args = parser.parse_args()

    with open(args.case, "rb") as f:
        case = tomllib.load(f)
    ratios = case.get("nested", {}).get("ratios", [])
    if not ratios:
        sys.exit(f"{args.case}: no nested.ratios: nothing to compare")
    factor = 1
    for r in ratios:
        factor *= r
    cells = [c * factor for c in case["fluid"]["cells"]]
    uniform = ["--set", f"fluid.cells={cells}", "--set", "nested.ratios=[]"]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")

    print(f"case {args.case}, {args.steps} steps; uniform grid {cells[0]} x {cells[1]} x {cells[2]}")
    with tempfile.TemporaryDirectory() as scratch:
        for ranks in args.ranks:
            for name, extra in (("two levels", []), ("uniform", uniform)):
                command = [args.mpiexec, "-n", str(ranks), args.ibvalve, "run", str(args.case), "-o",
                           f"{scratch}/run", "--overwrite", "--stop-after-steps", str(args.steps),
                           "--set", "checkpoint.every=0", "--set", "output.fields_interval=0", *extra]
                out, wall, peak = run(command, env)
                grid = re.search(r"(\d+ nested levels \([^)]*\)|grid \d+ x \d+ x \d+)", out)
                step = re.search(r"per step: (.*?) over \d+ steps", out)
                nested = re.search(r"nested fluid per step: (.*)", out)
                print(f"\n{name}, {ranks} rank(s): {grid.group(1) if grid else '?'}")
                print(f"  per step: {step.group(1) if step else '?'}")
                if nested:
                    print(f"  nested fluid per step: {nested.group(1)}")
                print(f"  whole process {wall:.1f} s; peak memory of the largest process {peak:.0f} MiB")


if __name__ == "__main__":
    main()
