#!/usr/bin/python3
"""The aortic-valve case's first steps: time a coupled step and its parts, solver iterations, memory.

  bench_aortic_valve.py IBVALVE [--case default.toml ...] [--steps 400] [--ranks 1 2] [--repeat 3]

For each case (default: examples/aortic_valve/default.toml and paper.toml) and rank count, runs the
case for --steps steps and for 1 step, --repeat times each, and prints the medians of:
  - the marginal wall time a step, (wall(N steps) - wall(1 step)) / (N - 1): the cost of a step with
    the set-up (mesh, fibers, factorizations, FFTW planning, the first step's solver set-ups) taken out;
  - the parts of a step as the run reports them (IbfeTimings: fluid, interpolation, L2 projections,
    force, spreading, coupling points; averaged over all N steps, so slightly above the marginal figure);
  - the Stokes solver's FGMRES iterations a step (one grid) or the nested fluid's iterations;
  - the whole process's wall time and the peak resident memory of its largest process.
Figures only; nothing passes or fails. Time on an otherwise idle machine (bench/README.md).
"""
import argparse
import os
import pathlib
import re
import statistics
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from process_figures import run  # noqa: E402


def parts(out):
    """The run's 'per step' summary as {name: seconds}."""
    m = re.search(r"per step: ([0-9.e+-]+) s \(([^)]*)\)", out)
    if not m:
        return {}
    figures = {"total": float(m.group(1))}
    for item in m.group(2).split(","):
        name, value = item.split()
        figures[name] = float(value)
    return figures


def iterations(out, steps):
    counts = [int(n) for n in re.findall(r"Linear fluid_stokes_ solve converged due to \w+ iterations (\d+)", out)]
    if counts:
        return f"{sum(counts) / len(counts):.2f} FGMRES iterations a step ({min(counts)}-{max(counts)})"
    nested = re.search(r"nested fluid per step: (.*)", out)
    return nested.group(1) if nested else "?"


def main():
    here = pathlib.Path(__file__).resolve()
    source = here.parents[2]
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("ibvalve")
    parser.add_argument("--case", type=pathlib.Path, nargs="+",
                        default=[source / "examples/aortic_valve/default.toml",
                                 source / "examples/aortic_valve/paper.toml"])
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--mpiexec", default="mpiexec")
    parser.add_argument("--set", action="append", default=[], help="a case override, as ibvalve run --set")
    args = parser.parse_args()
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    overrides = [item for s in args.set for item in ("--set", s)]

    with tempfile.TemporaryDirectory() as scratch:
        for case in args.case:
            for ranks in args.ranks:
                def command(steps):
                    return [args.mpiexec, "--oversubscribe", "-n", str(ranks), args.ibvalve, "run", str(case), "-o",
                            f"{scratch}/run", "--overwrite", "--stop-after-steps", str(steps), "--set",
                            "checkpoint.every=0", "--set", "output.fields_interval=0", *overrides, "--",
                            "-fluid_stokes_ksp_converged_reason"]
                walls, firsts, peaks, reported, out = [], [], [], [], ""
                for _ in range(args.repeat):
                    _, first, _ = run(command(1), env)
                    out, wall, peak = run(command(args.steps), env)
                    firsts.append(first)
                    walls.append(wall)
                    peaks.append(peak)
                    reported.append(parts(out))
                marginal = [(w - f) / (args.steps - 1) for w, f in zip(walls, firsts)]
                grid = re.search(r"(\d+ nested levels \([^)]*\)|grid \d+ x \d+ x \d+)", out)
                names = list(reported[-1].keys())
                medians = {n: statistics.median(r.get(n, float("nan")) for r in reported) for n in names}
                print(f"{case.name}, {ranks} rank(s), {grid.group(1) if grid else '?'}, {args.steps} steps, "
                      f"{args.repeat} runs (medians):")
                print(f"  marginal {statistics.median(marginal):.4f} s a step (runs {min(marginal):.4f}-"
                      f"{max(marginal):.4f}); set-up and first step {statistics.median(firsts):.1f} s")
                print("  reported per step: " + ", ".join(f"{n} {v:.4g}" for n, v in medians.items()))
                print(f"  {iterations(out, args.steps)}")
                print(f"  whole process {statistics.median(walls):.1f} s, peak memory {statistics.median(peaks):.0f} MiB "
                      f"(largest process)")
                sys.stdout.flush()


if __name__ == "__main__":
    main()
