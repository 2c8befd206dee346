#!/usr/bin/env python3
"""A valve of one's own: an aortic-valve case run on a Gmsh mesh the user brings (mesh.file), and
`ibvalve check`. Each scenario is one specification:

  check_own_valve.py SCENARIO IBVALVE MPIEXEC RANKS SOURCE_DIR WORK_DIR

Scenarios (the case is examples/aortic_valve/immersed_tube.toml, whose tube is part of the mesh; the mesh
is written by `ibvalve mesh aortic-valve` with that case's geometry, coarse, into WORK_DIR):
  missing-groups
      A mesh whose groups leaflet1, leaflet2_attachment, leaflet3_n1, tube and tube_outer were renamed:
      `ibvalve check` and `ibvalve run` with --set mesh.file=broken.msh (named from the working folder)
      each end with exit 2 and one error line naming mesh.file, the mesh file and all five groups; the
      run writes no run folder; on 2 ranks no rank is left waiting.
  set-path
      --set mesh.file=valve.msh names the file in the working folder (not the case file's): `ibvalve
      check` exits 0 with one line naming the case, the model and that file, and writes nothing.
  recorded
      A run on the mesh file (one step) names the file in log.txt; its config.toml holds mesh.file and
      the keys the model still reads (tube_radius, tube_wall, leaflet_thickness, valve_base,
      commissure_height) and none of the generator's (tube_length, commissure_strip, sag,
      free_edge_drop, free_edge_gap, leaflet_across, leaflet_radial, tube_around, tube_along), and one
      warning names those the case gave; `ibvalve check` passes on that config.toml.
  check
      `ibvalve check` of the default valve and of the lumped example: exit 0, one line each, nothing
      written; of a case with a bad key: exit 2 and the one error line `ibvalve run` gives.
Prints what it checked; exits 1 on the first failure.
"""
import os
import pathlib
import re
import subprocess
import sys

GENERATOR_KEYS = ["tube_length", "commissure_strip", "sag", "free_edge_drop", "free_edge_gap", "leaflet_across",
                  "leaflet_radial", "tube_around", "tube_along"]
READ_KEYS = ["tube_radius", "tube_wall", "leaflet_thickness", "valve_base", "commissure_height"]
RENAMED = {"leaflet1": "cusp1", "leaflet2_attachment": "leaflet2_hinge", "leaflet3_n1": "leaflet3_tip",
           "tube": "wall", "tube_outer": "wall_outer"}


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


def write_mesh(run, name):
    """The default case's valve and tube, coarse, as WORK/name."""
    result = run("mesh", "aortic-valve", "--tube-length", "5", "--valve-base", "2", "--free-edge-drop", "0.5",
                 "--leaflet-across", "8", "--leaflet-radial", "4", "--tube-around", "24", "--tube-along", "10",
                 "-o", name, ranks=1)
    if result.returncode != 0:
        fail("ibvalve mesh aortic-valve", result)
    return run.work / name


def rename_groups(mesh, renamed):
    """The mesh with physical groups renamed (the $PhysicalNames section of the ASCII .msh)."""
    text = mesh.read_text()
    begin, end = text.index("$PhysicalNames"), text.index("$EndPhysicalNames")
    section = text[begin:end]
    for old, new in renamed.items():
        section, count = re.subn(rf'"{old}"', f'"{new}"', section)
        if count != 1:
            fail(f"{mesh}: no group {old} to rename")
    broken = mesh.with_name("broken.msh")
    broken.write_text(text[:begin] + section + text[end:])
    return broken


def missing_groups(run, case):
    broken = rename_groups(write_mesh(run, "valve.msh"), RENAMED)
    folder = run.work / "run_missing_groups"
    for command in (["check", case], ["run", case, "-o", folder]):
        result = run(*command, "--set", "mesh.file=broken.msh")
        lines = error_lines(result)
        if result.returncode != 2 or len(lines) != 1:
            fail(f"ibvalve {command[0]} on a mesh without five groups: expected exit 2 and one error line", result)
        line = lines[0]
        for needed in ["mesh.file", str(broken)] + list(RENAMED):
            if not re.search(rf"[ (:]{re.escape(needed)}[ :(,]", line):
                fail(f"ibvalve {command[0]}: the error line does not name {needed}", result)
        print(f"ok: ibvalve {command[0]}, exit 2, one line: {line[:160]}...")
    if folder.exists():
        fail(f"{folder} was created")
    print(f"ok: on {run.ranks} rank(s), no run folder")


def set_path(run, case):
    mesh = write_mesh(run, "valve.msh")
    before = sorted(os.listdir(run.work))
    result = run("check", case, "--set", "mesh.file=valve.msh")
    lines = result.stdout.splitlines()
    if result.returncode != 0 or len(lines) != 1:
        fail("ibvalve check with --set mesh.file=valve.msh: expected exit 0 and one line", result)
    if not lines[0].startswith(f"{case}: a valid aortic-valve case; mesh: {mesh} ("):
        fail("the line does not name the case, the model and the mesh file in the working folder", result)
    if sorted(os.listdir(run.work)) != before:
        fail("ibvalve check wrote into the working folder")
    print(f"ok: {lines[0]}")


def recorded(run, case):
    mesh = write_mesh(run, "valve.msh")
    folder = run.work / "run_recorded"
    result = run("run", case, "-o", folder, "--overwrite", "--stop-after-steps", "1", "--set", "mesh.file=valve.msh",
                 "--set", "checkpoint.every=0", "--set", "output.fields_interval=0")
    if result.returncode != 0:
        fail("a run on the mesh file", result)
    if f"mesh: {mesh} (" not in (folder / "log.txt").read_text():
        fail(f"log.txt does not name the mesh file {mesh}", result)
    config = (folder / "config.toml").read_text()
    section = config[config.index("\n[mesh]\n"):].split("\n\n")[0].splitlines()
    keys = [line.split(" = ")[0].lstrip("# ") for line in section[1:]]
    if "file" not in keys or any(key not in keys for key in READ_KEYS):
        fail(f"config.toml's [mesh] lacks file or a key the model reads: {keys}")
    if any(key in keys for key in GENERATOR_KEYS):
        fail(f"config.toml's [mesh] holds generator keys: {[k for k in keys if k in GENERATOR_KEYS]}")
    print(f"ok: log.txt names {mesh}; config.toml's [mesh]: {', '.join(keys)}")
    warnings = [line for line in result.stderr.splitlines() if "not used with mesh.file" in line]
    given = ["tube_length", "free_edge_drop", "leaflet_across", "leaflet_radial", "tube_around", "tube_along"]
    if len(warnings) != 1 or any(f"mesh.{key}" not in warnings[0] for key in given):
        fail("expected one warning naming the generator keys the case gave", result)
    print(f"ok: {warnings[0]}")
    again = run("check", folder / "config.toml")
    if again.returncode != 0:
        fail("ibvalve check on the run's config.toml", again)
    print("ok: the run's config.toml checks")


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
    if scenario == "check":
        check(run, source / "examples/aortic_valve/default.toml", source)
    else:
        # A mesh of one's own with its tube: the immersed-tube case reads the tube's groups too.
        case = source / "examples/aortic_valve/immersed_tube.toml"
        {"missing-groups": missing_groups, "set-path": set_path, "recorded": recorded}[scenario](run, case)


if __name__ == "__main__":
    main()
