#!/usr/bin/python3
"""The aortic-valve case's first steps: time a coupled step and its parts, solver iterations, memory.

  bench_aortic_valve.py IBVALVE [--case default.toml ...] [--steps 400] [--ranks 1 2] [--repeat 3]
  bench_aortic_valve.py IBVALVE --from RUN_DIR [--steps 300] [--ranks 2] [--repeat 3]

For each case (default: examples/aortic_valve/default.toml and paper.toml) and rank count, runs the
case for --steps steps and for 1 step, --repeat times each, and prints the medians of the figures below.
A case's first steps are its start from rest (more Stokes iterations than mid-cycle); --from RUN_DIR
instead continues a copy of that run from its newest checkpoint (`ibvalve run --restart`), fresh for
every run, so that a valve open or closed mid-cycle is measured. The medians:
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
import shutil
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
    nested = re.search(r"fluid per step: (.*)", out)
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
    parser.add_argument("--from", dest="source", type=pathlib.Path,
                        help="a run folder with checkpoints: continue copies of it instead of running --case")
    args = parser.parse_args()
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    overrides = [item for s in args.set for item in ("--set", s)]

    if args.source and overrides:
        sys.exit("--set does not apply to --from: a restart continues the run's own case")
    petsc = ["--", "-fluid_stokes_ksp_converged_reason"]

    def copy_of_source(scratch):
        """A fresh copy of the --from run: its record, series and newest checkpoint (no fields)."""
        checkpoints = sorted((args.source / "checkpoints").glob("step_*.h5"))
        if not checkpoints:
            sys.exit(f"{args.source}: no checkpoints to continue from")
        target = pathlib.Path(scratch)
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(args.source, target, ignore=shutil.ignore_patterns("fields", "checkpoints", "report"))
        (target / "checkpoints").mkdir()
        shutil.copy2(checkpoints[-1], target / "checkpoints")
        return target

    # A copy of a --from run sits beside it, at the same depth, so that the relative paths of its resolved
    # case (config.toml: the LV table, the biaxial samples) still resolve.
    beside = args.source.resolve().parent if args.source else None
    with tempfile.TemporaryDirectory(dir=beside) as scratch:
        for case in [args.source] if args.source else args.case:
            for ranks in args.ranks:
                def command(steps):
                    launch = [args.mpiexec, "--oversubscribe", "-n", str(ranks), args.ibvalve, "run"]
                    if args.source:
                        return [*launch, "--restart", str(copy_of_source(scratch)), "--stop-after-steps", str(steps),
                                *petsc]
                    return [*launch, str(case), "-o", f"{scratch}/run", "--overwrite", "--stop-after-steps",
                            str(steps), "--set", "checkpoint.every=0", "--set", "output.fields_interval=0",
                            *overrides, *petsc]
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
