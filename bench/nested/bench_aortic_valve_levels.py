#!/usr/bin/python3
"""The aortic-valve case on two nested levels against one uniform grid of the same finest spacing.

  bench_aortic_valve_levels.py IBVALVE [--case paper.toml] [--ratio 4] [--margin 4] [--steps 40]
                               [--ranks 1 2] [--mpiexec mpiexec]

Runs the case (default: examples/aortic_valve/paper.toml, the study's 8 x 8 x 14 cm box on one grid of
80 x 80 x 128 cells) for --steps steps as it is, then on two levels: level 0 of fluid.cells / ratio
cells and a level of that ratio around the valve and tube (nested.ratios = [ratio], nested.margins =
[margin]: the study's layout for paper.toml; the projection by the composite multigrid), on each rank
count. Prints per run: the time per coupled step and its parts as the run reports them (set-up and the
first step's solver set-ups included in that average; use enough steps), the nested fluid's parts and
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
    parser.add_argument("--ratio", type=int, default=4)
    parser.add_argument("--margin", type=int, default=4)
    parser.add_argument("--steps", type=int, default=40)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--mpiexec", default="mpiexec")
    args = parser.parse_args()

    with open(args.case, "rb") as f:
        case = tomllib.load(f)
    if case.get("nested", {}).get("ratios"):
        sys.exit(f"{args.case}: already on nested levels: give the case on one grid of the finest spacing")
    cells = case["fluid"]["cells"]
    if any(c % args.ratio for c in cells):
        sys.exit(f"{args.case}: fluid.cells {cells} are not multiples of the ratio {args.ratio}")
    coarse = [c // args.ratio for c in cells]
    levels = ["--set", f"fluid.cells={coarse}", "--set", f"nested.ratios=[{args.ratio}]",
              "--set", f"nested.margins=[{args.margin}]",
              # the projection by the composite multigrid (docs/nested.md, "The projection's multigrid")
              "--set", 'petsc.options="-nested_pressure_composite_multigrid"']
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")

    print(f"case {args.case}, {args.steps} steps; uniform grid {cells[0]} x {cells[1]} x {cells[2]}; "
          f"level 0 {coarse[0]} x {coarse[1]} x {coarse[2]} with ratio {args.ratio}")
    with tempfile.TemporaryDirectory() as scratch:
        for ranks in args.ranks:
            for name, extra in (("uniform", []), ("two levels", levels)):
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
