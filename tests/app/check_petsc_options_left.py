#!/usr/bin/env python3
"""PETSc options no solver read are named at the end of the run.

  check_petsc_options_left.py IBVALVE MPIEXEC RANKS CASE WORK_DIR

CASE is a small fluid case (tests/app/cases/restart_fluid.toml: the Krylov solver, prefixes
fluid_stokes_, fluid_helmholtz_, fluid_poisson_). Two steps of it each with:
  - a misspelt option after -- (-fluid_ksp_typo) and one in petsc.options (-fluid_poisson_ksp_typ):
    exit 0 and exactly one warning line "PETSc options not used:" naming both and nothing else;
  - valid options of the solver (-fluid_stokes_ksp_rtol, -fluid_poisson_ksp_type): no such warning.
Prints what it checked; exits 1 on the first failure.
"""
import os
import shutil
import subprocess
import sys


def run(ibvalve, mpiexec, ranks, case, folder, petsc_case, petsc_after):
    shutil.rmtree(folder, ignore_errors=True)
    command = [mpiexec, "--oversubscribe", "-n", str(ranks), ibvalve, "run", case, "-o", folder,
               "--stop-after-steps", "2", "--set", f'petsc.options="{petsc_case}"', "--"] + petsc_after
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    result = subprocess.run(command, capture_output=True, text=True, stdin=subprocess.DEVNULL, env=env,
                            timeout=280)
    if result.returncode != 0:
        print(result.stdout, result.stderr)
        sys.exit(f"FAIL: exit code {result.returncode}: {' '.join(command)}")
    return [line for line in result.stderr.splitlines() if "PETSc options not used" in line]


def main():
    ibvalve, mpiexec, ranks, case, work = sys.argv[1:6]
    os.makedirs(work, exist_ok=True)
    folder = os.path.join(work, "run")
    lines = run(ibvalve, mpiexec, ranks, case, folder, "-fluid_poisson_ksp_typ cg", ["-fluid_ksp_typo", "3"])
    if len(lines) != 1:
        sys.exit(f"FAIL: misspelt options: {len(lines)} warning lines, expected one: {lines}")
    named = lines[0].split("not used:")[1].split("(")[0].split()
    if not lines[0].startswith("warning: ") or sorted(named) != ["-fluid_ksp_typo", "-fluid_poisson_ksp_typ"]:
        sys.exit(f"FAIL: the warning should name -fluid_ksp_typo and -fluid_poisson_ksp_typ only: {lines[0]}")
    print(f"ok: {lines[0]}")
    lines = run(ibvalve, mpiexec, ranks, case, folder, "-fluid_poisson_ksp_type cg",
                ["-fluid_stokes_ksp_rtol", "1e-9"])
    if lines:
        sys.exit(f"FAIL: valid options were reported as unused: {lines}")
    print("ok: valid options give no warning")
    shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
