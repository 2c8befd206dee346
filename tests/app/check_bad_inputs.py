#!/usr/bin/env python3
"""Bad input across the models and commands: each input of the table below must give

  - exit code 2,
  - exactly one line on stderr (under mpiexec, its own "process returned a non-zero exit code" block of
    dashed lines is not the program's and is left out), starting "error: ",
  - naming the key (or option) and where it was given: FILE:LINE for a case file, "command line" for
    the command line,
  - and nothing written: no run folder (-o), or the given folder unchanged.

  check_bad_inputs.py IBVALVE EXAMPLES WORK_DIR [--mpiexec MPIEXEC --ranks N] [--group G] [--subset]
                      [--cap-gib G]

1 rank runs IBVALVE directly (a singleton MPI process); --ranks 2 runs it under MPIEXEC (the timeout
catches a rank left waiting). --group runs one group of the table (lumped, fluid, ibfe, aortic-valve,
commands); --subset the inputs marked for the 2-rank pass. --cap-gib limits each process's address
space (for trying the table on a build that allocates what it should refuse). Prints one line per input; exits 1 when any
failed, after running them all.
"""
import argparse
import os
import pathlib
import re
import shutil
import subprocess
import sys

CL = "command line"

# One row per bad input: (name, group, how, what, key, where, subset)
#   how:   ("edit", CASE, OLD, NEW) - the example case with OLD replaced by NEW (NEW's first line is where)
#          ("append", CASE, TEXT)   - the example case with TEXT added at the end (TEXT's first line)
#          ("set", CASE, KEY=VALUE...) - the example case with --set overrides
#          ("args", [ARGS])         - a command line; {examples}, {work}, {out}, {cases} (tests/app/cases) expand
#   key:   the key or option the one line must name
#   where: CL ("command line" in the line), "case" (CASE:LINE of the edit; "case+1" the line after it),
#          "default" or "nofile-line" (the case file named, no line: a key left out or at its default),
#          "path" (a path given on the command line, named in the line), "waveform-line" (the data file)
LUMPED, DUCT, TG, BLOCK, SHELL_NESTED = ("lumped/default.toml", "duct/case.toml", "taylor_green/case.toml",
                                         "ibfe/block.toml", "ibfe/shell_nested.toml")
# The default valve holds its tube as the fluid's wall; the immersed tube's keys are tried on the case that has one.
VALVE, IMMERSED = "aortic_valve/default.toml", "aortic_valve/immersed_tube.toml"
CLOSED_LOOP = "lumped/closed_loop.toml"
INPUTS = [
    # --- the model key and the common keys
    ("model misspelt key", "lumped", ("edit", LUMPED, 'model = "lumped"', 'modle = "lumped"'), "modle", "case", True),
    ("model misspelt value", "lumped", ("edit", LUMPED, 'model = "lumped"', 'model = "lumpd"'), "model", "case", True),
    ("model not a string", "lumped", ("edit", LUMPED, 'model = "lumped"', "model = 3"), "model", "case", False),
    ("model missing", "lumped", ("edit", LUMPED, 'model = "lumped"', "# no model"), "model", "nofile-line", False),
    ("model by --set unknown", "lumped", ("set", LUMPED, 'model="particles"'), "model", CL, False),
    ("log.level not a choice", "lumped", ("append", LUMPED, '[log]\nlevel = "loud"'), "log.level", "case+1", False),
    ("log interval negative", "lumped", ("append", LUMPED, "[log]\nprogress_interval = -1.0"),
     "log.progress_interval", "case+1", False),
    ("run.max_memory negative", "lumped", ("append", LUMPED, "[run]\nmax_memory = -1.0"), "run.max_memory",
     "case+1", False),
    # --- lumped
    ("lumped cycles zero", "lumped", ("edit", LUMPED, "cycles = 4", "cycles = 0"), "time.cycles", "case", True),
    ("lumped step a string", "lumped", ("edit", LUMPED, "step = 1.0e-4", 'step = "1e-4"'), "time.step", "case",
     False),
    ("lumped step negative", "lumped", ("edit", LUMPED, "step = 1.0e-4", "step = -1.0e-4"), "time.step", "case",
     False),
    ("lumped waveform missing", "lumped",
     ("edit", LUMPED, 'file = "../waveforms/lv_pressure_typeA.csv"', 'file = "no_such.csv"'), "lv_pressure.file",
     "case", True),
    ("lumped waveform not a table", "lumped",
     ("edit", LUMPED, 'file = "../waveforms/lv_pressure_typeA.csv"', 'file = "../lumped/default.toml"'),
     "default.toml", "waveform-line", False),
    ("lumped interpolation unknown", "lumped",
     ("edit", LUMPED, 'interpolation = "monotone-cubic"', 'interpolation = "spline"'), "lv_pressure.interpolation",
     "case", False),
    ("lumped windkessel preset unknown", "lumped",
     ("edit", LUMPED, 'preset = "stergiopulos-typeA"', 'preset = "typeZ"'), "windkessel.preset", "case", False),
    ("lumped area fraction above 1", "lumped",
     ("edit", LUMPED, "max_area_fraction = 0.6", "max_area_fraction = 1.6"), "valve.max_area_fraction", "case",
     False),
    ("lumped unknown key in table", "lumped", ("edit", LUMPED, "annulus_radius = 1.3", "anulus_radius = 1.3"),
     "valve.anulus_radius", "case", False),
    # --- lumped, inlet.driver = outlet.driver = "circulation"
    ("lumped heart key retired", "lumped", ("edit", LUMPED, 'model = "lumped"', 'model = "lumped"\nheart = "circulation"'),
     "heart", "case+1", False),
    ("closed loop on the inlet only", "lumped", ("edit", CLOSED_LOOP, '[outlet]\ndriver = "circulation"', '[outlet]'),
     "outlet.driver", "nofile-line", False),
    ("lumped table without its file", "lumped",
     ("edit", LUMPED, 'file = "../waveforms/lv_pressure_typeA.csv"', '# no file'), "lv_pressure.file",
     "nofile-line", False),
    ("closed loop given a table", "lumped",
     ("append", CLOSED_LOOP, '[lv_pressure]\nfile = "../waveforms/lv_pressure_typeA.csv"'), "lv_pressure.file",
     "case+1", True),
    ("closed loop preset unknown", "lumped",
     ("edit", CLOSED_LOOP, 'preset = "regazzoni2022"', 'preset = "smith2004"'), "circulation.preset", "case",
     False),
    ("closed loop elastance negative", "lumped",
     ("set", CLOSED_LOOP, "circulation.left_ventricle.passive_elastance=-0.1"),
     "circulation.left_ventricle.passive_elastance", CL, False),
    ("closed loop beat overfull", "lumped",
     ("set", CLOSED_LOOP, "circulation.left_ventricle.contraction_time=0.6",
      "circulation.left_ventricle.relaxation_time=0.5"), "circulation.left_ventricle.relaxation_time", CL, True),
    ("closed loop valve never closes", "lumped",
     ("set", CLOSED_LOOP, "circulation.mitral_valve.closed_resistance=0.001"),
     "circulation.mitral_valve.closed_resistance", CL, False),
    ("closed loop report period", "lumped", ("edit", CLOSED_LOOP, "period = 0.8333333333333334", "period = 0.8"),
     "report.period", "case", False),
    ("lumped misspelt table", "lumped", ("append", LUMPED, "[windkesel]\npreset = \"stergiopulos-typeA\""),
     "windkesel", "case", False),
    ("lumped closure rule unknown", "lumped", ("edit", LUMPED, 'closure_rule = "flow"', 'closure_rule = "pressure"'),
     "report.closure_rule", "case", False),
    ("lumped override without value", "lumped", ("set", LUMPED, "time.cycles"), "time.cycles", CL, False),
    ("lumped override bad TOML", "lumped", ("set", LUMPED, "time.cycles=[1"), "time.cycles", CL, False),
    ("lumped override wrong type", "lumped", ("set", LUMPED, 'time.cycles="two"'), "time.cycles", CL, True),
    ("lumped syntax error", "lumped", ("edit", LUMPED, "cycles = 4", "cycles = = 4"), "TOML syntax error", "case",
     False),
    ("lumped cycles beyond int64", "lumped", ("edit", LUMPED, "cycles = 4", "cycles = 99999999999999999999"),
     "TOML syntax error", "case", False),
    # A time step so small that the step count overflows (or is beyond the bound of a run) is refused,
    # not rounded to one step or to a step of the whole cycle.
    ("lumped step subnormal", "lumped", ("set", LUMPED, "time.step=5e-324"), "time.step", CL, True),
    ("lumped steps beyond the bound", "lumped", ("set", LUMPED, "time.step=1e-10"), "time.step", CL, False),
    # --- fluid
    ("fluid cells too few", "fluid", ("edit", DUCT, "cells = [32, 16, 16]", "cells = [32, 16, 2]"), "fluid.cells",
     "case", True),
    ("fluid cells two values", "fluid", ("edit", DUCT, "cells = [32, 16, 16]", "cells = [32, 16]"), "fluid.cells",
     "case", False),
    ("fluid cells not integers", "fluid", ("edit", DUCT, "cells = [32, 16, 16]", "cells = [1e5, 1e5, 1e5]"),
     "fluid.cells", "case", False),
    ("fluid cells beyond int", "fluid", ("edit", DUCT, "cells = [32, 16, 16]", "cells = [4294967297, 16, 16]"),
     "fluid.cells", "case", True),
    ("fluid cells beyond PETSc indices", "fluid", ("edit", DUCT, "cells = [32, 16, 16]", "cells = [2000, 2000, 2000]"),
     "fluid.cells", "case", False),
    ("fluid cells beyond memory", "fluid", ("edit", DUCT, "cells = [32, 16, 16]", "cells = [700, 700, 700]"),
     "fluid.cells", "case", True),
    ("fluid memory limit by --set", "fluid", ("set", DUCT, "run.max_memory=0.01"), "fluid.cells", "default", False),
    ("fluid upper below lower", "fluid", ("edit", DUCT, "upper = [4.0, 1.0, 1.0]", "upper = [4.0, -1.0, 1.0]"),
     "fluid.upper", "case", False),
    ("fluid solver unknown", "fluid", ("edit", DUCT, 'solver = "krylov"', 'solver = "multigrid"'), "fluid.solver",
     "case", False),
    ("fluid fft with walls", "fluid", ("edit", DUCT, 'solver = "krylov"', 'solver = "fft"'), "fluid.solver", "case",
     False),
    ("fluid half periodic", "fluid", ("set", DUCT, 'boundary.x_upper.type="periodic"'), "boundary.x_upper.type",
     CL, False),
    ("fluid side type unknown", "fluid", ("edit", DUCT, 'type = "wall"', 'type = "slip"'), "boundary.y_lower.type",
     "case", False),
    ("fluid velocity two values", "fluid", ("set", DUCT, "boundary.x_lower.velocity=[1.0, 0.0]"),
     "boundary.x_lower.velocity", CL, False),
    ("fluid viscosity negative", "fluid", ("edit", DUCT, "viscosity = 100.0", "viscosity = -1.0"),
     "fluid.viscosity", "case", False),
    ("fluid end missing", "fluid", ("edit", DUCT, "end = 0.5", "# no end"), "time.end", "nofile-line", False),
    ("fluid max iterations beyond int", "fluid", ("set", DUCT, "fluid.max_iterations=4294967297"),
     "fluid.max_iterations", CL, False),
    ("fluid taylor-green with walls", "fluid", ("set", DUCT, 'initial.condition="taylor_green"'),
     "initial.condition", CL, False),
    ("fluid step tiny", "fluid", ("set", DUCT, "time.step=1e-300"), "time.step", CL, False),
    ("fluid checkpoint every negative", "fluid", ("set", TG, "checkpoint.every=-2"), "checkpoint.every", CL, False),
    ("fluid unknown side", "fluid", ("append", TG, "[boundary.w_lower]\ntype = \"wall\""), "boundary.w_lower", "case",
     False),
    # --- ibfe
    ("ibfe box cells beyond int", "ibfe", ("edit", BLOCK, "box.cells = [12, 8, 8]", "box.cells = [4294967297, 8, 8]"),
     "structure.box.cells", "case", True),
    ("ibfe box cells beyond memory", "ibfe", ("edit", BLOCK, "box.cells = [12, 8, 8]", "box.cells = [4000, 4000, 40]"),
     "structure.box.cells", "case", False),
    ("ibfe box cells zero", "ibfe", ("edit", BLOCK, "box.cells = [12, 8, 8]", "box.cells = [12, 0, 8]"),
     "structure.box.cells", "case", False),
    ("ibfe shell patches beyond memory", "ibfe",
     ("set", BLOCK, 'structure.shape="spherical-shell"', "structure.shell.patches=4000",
      "structure.shell.layers=400"), "structure.shell.patches", CL, False),
    ("ibfe shell patches beyond int", "ibfe", ("set", BLOCK, 'structure.shape="spherical-shell"',
                                               "structure.shell.patches=2147483649"), "structure.shell.patches", CL,
     False),
    ("ibfe shape unknown", "ibfe", ("edit", BLOCK, 'shape = "box"', 'shape = "sphere"'), "structure.shape", "case",
     False),
    ("ibfe mesh file missing", "ibfe", ("edit", BLOCK, 'shape = "box"', 'shape = "file"\nmesh = "no_such.msh"'),
     "structure.mesh", "case+1", False),
    ("ibfe file shape without mesh", "ibfe", ("edit", BLOCK, 'shape = "box"', 'shape = "file"'), "structure.shape",
     "case", False),
    ("ibfe box outside walls", "ibfe", ("set", BLOCK, 'fluid.boundary="walls"', "structure.box.upper=[1.5, 0.6, 0.6]"),
     "structure.box.upper", CL, False),
    ("ibfe law unknown", "ibfe", ("edit", BLOCK, 'law = "neo-hookean"', 'law = "rubber"'), "structure.material.law",
     "case", False),
    ("ibfe expression unknown symbol", "ibfe",
     ("edit", BLOCK, 'law = "neo-hookean"\nmu = 0.01',
      'energy = "mu/2*(I1 - 3) + q"\nlaw = "expression"\nparameters = { mu = 0.01 }\nmoduli = ["mu"]\n#'),
     "structure.material.energy", "case", False),
    ("ibfe kernel unknown", "ibfe", ("edit", BLOCK, 'kernel = "ib-4"', 'kernel = "ib-5"'), "ib.kernel", "case", False),
    ("ibfe quadrature beyond int", "ibfe", ("set", BLOCK, "structure.quadrature_degree=4294967298"),
     "structure.quadrature_degree", CL, False),
    ("ibfe nested on periodic box", "ibfe", ("set", BLOCK, "nested.ratios=[2]"), "nested.ratios", CL, True),
    ("ibfe nested ratio 3", "ibfe", ("set", SHELL_NESTED, "nested.ratios=[3]"), "nested.ratios", CL, False),
    ("ibfe nested margins beyond int", "ibfe", ("set", SHELL_NESTED, "nested.margins=[4294967297]"),
     "nested.margins", CL, False),
    ("ibfe tether group unknown", "ibfe", ("append", BLOCK, '[[ib.tether]]\ngroup = "nowhere"\nstiffness = 1.0'),
     "ib.tether[0].group", "case+1", False),
    ("ibfe part group unknown", "ibfe",
     ("append", BLOCK, '[[structure.part]]\ngroup = "nowhere"\nmaterial.law = "neo-hookean"\nmaterial.mu = 1.0'),
     "structure.part[0].group", "case+1", False),
    ("ibfe part parameter of another law", "ibfe",
     ("append", BLOCK, '[[structure.part]]\nmaterial.mu = 1.0\ngroup = "body"\nmaterial.law = "W1"'),
     "structure.part[0].material.mu", "case+1", False),
    ("ibfe step tiny", "ibfe", ("set", BLOCK, "time.step=1e-300"), "time.step", CL, False),
    ("ibfe stretch negative", "ibfe", ("set", BLOCK, "structure.initial.stretch=[1.0, -1.0, 1.0]"),
     "structure.initial.stretch", CL, False),
    # --- aortic valve
    ("valve model underscore", "aortic-valve", ("edit", VALVE, 'model = "aortic-valve"', 'model = "aortic_valve"'),
     "model", "case", True),
    ("valve model key misspelt", "aortic-valve", ("edit", VALVE, 'model = "aortic-valve"', 'modle = "aortic-valve"'),
     "modle", "case", False),
    ("valve tube around beyond int", "aortic-valve", ("set", IMMERSED, "mesh.tube_around=4294967344"),
     "mesh.tube_around", CL, True),
    ("valve tube around beyond memory", "aortic-valve", ("set", IMMERSED, "mesh.tube_around=4096", "mesh.tube_along=4096"),
     "mesh.tube_around", CL, False),
    ("valve leaflet across odd", "aortic-valve", ("set", VALVE, "mesh.leaflet_across=15"), "mesh", "default", False),
    ("valve fluid cells beyond memory", "aortic-valve", ("set", VALVE, "fluid.cells=[700, 700, 700]"), "fluid.cells",
     CL, False),
    ("valve tube surface unknown", "aortic-valve", ("set", IMMERSED, 'tether.tube_surfaces=["tube_top"]'),
     "tether.tube_surfaces[0]", CL, False),
    ("valve fiber rule unknown", "aortic-valve", ("set", VALVE, 'fibers.rule="FD3"'), "fibers.rule", CL, False),
    ("valve preset unknown", "aortic-valve", ("set", VALVE, 'leaflets.material.preset="zhu2021-W9"'),
     "leaflets.material.preset", CL, False),
    ("valve expression fibers in the tube", "aortic-valve",
     ("edit", IMMERSED, 'law = "neo-hookean"\nmu = 100.0',
      'energy = "mu/2*(I1 - 3) + k*(I4 - 1)^2"\nlaw = "expression"\nparameters = { mu = 100.0, k = 1.0 }\n'
      'moduli = ["mu", "k"]\n#'),
     "tube.material.energy", "case", True),
    ("valve mesh file missing", "aortic-valve", ("set", VALVE, 'mesh.file="no_such.msh"'), "mesh.file", CL, False),
    ("valve petsc option writes a file", "aortic-valve", ("set", VALVE, 'petsc.options="-log_view :/tmp/x.txt"'),
     "petsc.options", CL, False),
    ("valve step tiny", "aortic-valve", ("set", VALVE, "time.step=1e-300"), "time.step", CL, False),
    ("valve coaptation step tiny", "aortic-valve",
     ("set", IMMERSED, "time.coaptation_step=1e-300", "time.coaptation_window=[0.1, 0.2]"), "time.coaptation_step",
     CL, False),
    ("valve report period differs", "aortic-valve", ("set", VALVE, "report.period=0.7"), "report.period", CL, False),
    ("valve orifice resolution beyond int", "aortic-valve", ("set", VALVE, "probes.orifice_resolution=4294967552"),
     "probes.orifice_resolution", CL, False),
    # --- other commands
    ("run no case file", "commands", ("args", ["run", "{work}/no_such.toml", "-o", "{out}"]), "no_such.toml",
     "nofile-line", True),
    ("run stop after negative", "commands", ("args", ["run", "{examples}/lumped/default.toml", "-o", "{out}",
                                                      "--stop-after-steps=-3"]), "--stop-after-steps", CL, False),
    ("run restart not a run folder", "commands", ("args", ["run", "--restart", "{work}"]), "given: not a run folder", "path", False),
    ("report not a run folder", "commands", ("args", ["report", "{work}"]), "timeseries.csv", "path", False),
    ("report missing folder", "commands", ("args", ["report", "{work}/no_such_run"]), "no_such_run", "path", False),
    ("compare missing folder", "commands", ("args", ["compare", "{work}/no_such_run"]), "no_such_run", "path", False),
    ("fibers missing mesh", "commands", ("args", ["fibers", "{work}/no_such.msh", "--rule", "FD1", "-o", "{out}"]),
     "no_such.msh", "path", False),
    ("fibers unknown rule", "commands",
     ("args", ["fibers", "{examples}/fibers/leaflet.msh", "--rule", "FD3", "-o", "{out}"]), "--rule", CL, True),
    ("fibers not a mesh", "commands",
     ("args", ["fibers", "{examples}/lumped/default.toml", "--rule", "FD1", "-o", "{out}"]), "default.toml",
     "path", False),
    ("mesh negative radius", "commands", ("args", ["mesh", "aortic-valve", "-o", "{out}", "--tube-radius=-1"]),
     "tube radius", CL, False),
    ("mesh odd leaflet across", "commands", ("args", ["mesh", "aortic-valve", "-o", "{out}", "--leaflet-across=15"]),
     "leaflet elements across", CL, False),
    # A name is a name, not a path: a run or study case named "..", "." or "../x" would write outside
    # the folder meant for it (over an older run).
    ("run name parent folder", "lumped", ("set", LUMPED, 'name=".."'), "name", CL, True),
    ("run name a path", "lumped", ("edit", LUMPED, 'name = "lumped-default"', 'name = "../x"'), "name", "case",
     False),
    ("study case name parent folder", "commands", ("args", ["study", "{cases}/study_case_parent.toml", "-o", "{out}"]),
     "study_case_parent.toml:6: case[0].name", "nofile-line", True),
    ("study case name a path", "commands", ("args", ["study", "{cases}/study_case_path.toml", "-o", "{out}"]),
     "study_case_path.toml:6: case[0].name", "nofile-line", False),
    ("study source name parent folder", "commands",
     ("args", ["study", "{cases}/study_source_parent.toml", "-o", "{out}"]),
     "study_source_parent.toml:9: uncertainty[0].name", "nofile-line", False),
    # Input files that are no regular files (a device, a FIFO) or beyond bounds; outputs that cannot be
    # written; numbers no tissue or run has: bad input (exit 2), not an internal error or a hang.
    ("fibers mesh a device", "commands", ("args", ["fibers", "/dev/zero", "--rule", "FD1", "-o", "{out}"]),
     "/dev/zero: not a regular file", "path", False),
    ("mesh tube around beyond bound", "commands",
     ("args", ["mesh", "aortic-valve", "-o", "{out}/valve.msh", "--tube-around", "100000000"]), "--tube-around",
     CL, True),
    ("mesh elements beyond bound", "commands",
     ("args", ["mesh", "aortic-valve", "-o", "{out}/valve.msh", "--tube-around", "4096", "--tube-along", "4096"]),
     "hexahedra", CL, False),
    ("mesh output below a file", "commands",
     ("args", ["mesh", "aortic-valve", "-o", "{cases}/syntax_error.toml/valve.msh", "--tube-around", "12",
               "--tube-along", "8", "--leaflet-across", "4", "--leaflet-radial", "2"]),
     "syntax_error.toml: cannot create the output folder", "path", False),
    ("fibers axis not a number", "commands",
     ("args", ["fibers", "{examples}/fibers/leaflet.msh", "--rule", "FD1", "--axis", "nan", "0", "0", "0", "0", "1",
               "-o", "{out}"]), "--axis", CL, False),
    ("fit stresses beyond a tissue", "commands",
     ("args", ["fit", "--law", "W1", "{cases}/biaxial_stress_beyond_tissue.csv"]),
     "biaxial_stress_beyond_tissue.csv:4: sigma11_kPa", "path", False),
    ("run stop after beyond int64", "commands",
     ("args", ["run", "{examples}/lumped/default.toml", "-o", "{out}", "--stop-after-steps",
               "99999999999999999999"]), "--stop-after-steps", CL, False),
    ("run output empty", "commands", ("args", ["run", "{examples}/lumped/default.toml", "-o", ""]), "empty path",
     CL, False),
    ("compare output empty", "commands", ("args", ["compare", "{work}", "-o", ""]), "empty path", CL, False),
    ("study missing file", "commands", ("args", ["study", "{work}/no_such_study.toml"]), "no_such_study.toml",
     "nofile-line", False),
    ("unknown subcommand", "commands", ("args", ["simulate"]), "subcommand", CL, False),
]


def mpiexec_block(lines):
    """stderr without mpiexec's own report of a non-zero exit (blocks between dashed lines)."""
    kept, inside = [], False
    for line in lines:
        if re.fullmatch(r"-{20,}", line.strip()):
            inside = not inside
            continue
        if not inside:
            kept.append(line)
    return kept


def snapshot(folder):
    if not folder.exists():
        return None
    return sorted((str(p.relative_to(folder)), p.stat().st_mtime_ns, p.stat().st_size) for p in folder.rglob("*"))


def prepare(row, examples, work):
    """The command line of a row, and the 'FILE:LINE' its error must name (or None)."""
    name, group, how, key, where, subset = row
    slug = re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_")
    out = work / "runs" / slug
    location = None
    if how[0] in ("edit", "append", "set"):
        source = examples / how[1]
        text = source.read_text()
        # The case sits one folder below WORK_DIR, beside links to the examples' waveforms and biaxial
        # samples, so its relative paths (../waveforms/lv_pressure.csv, ../biaxial/sample1.csv) still hold.
        case = work / "cases" / f"bad_{slug}.toml"
        if how[0] == "edit":
            if how[2] not in text:
                raise SystemExit(f"table error: {name}: {how[2]!r} is not in {how[1]}")
            index = text.index(how[2])
            text = text.replace(how[2], how[3], 1)
            line = text[:index].count("\n") + 1
        elif how[0] == "append":
            text += "\n"
            line = text.count("\n") + 1
            text += how[2] + "\n"
        else:
            line = None
        args = ["run", str(case), "-o", str(out)]
        if how[0] == "set":
            for override in how[2:]:
                args += ["--set", override]
        if where == "case":
            location = f"{case.name}:{line}"
        elif where == "case+1":
            location = f"{case.name}:{line + 1}"
        elif where == "default" or where == "nofile-line":
            location = case.name
        elif where == "waveform-line":
            location = None
        return args, location, out, case, text
    given = work / "given"
    cases = pathlib.Path(__file__).resolve().parent / "cases"
    args = [a.replace("{examples}", str(examples)).replace("{work}", str(given)).replace("{out}", str(out))
            .replace("{cases}", str(cases)) for a in how[1]]
    return args, location, out, None, None


def check(row, args, location, out, case, text, launcher, watched, cap_gib):
    name, group, how, key, where, subset = row
    if case is not None:
        case.write_text(text)
    shutil.rmtree(out, ignore_errors=True)
    before = snapshot(watched)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    def cap():
        if cap_gib:
            import resource
            limit = int(cap_gib * 2**30)
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    try:
        result = subprocess.run(launcher + args, capture_output=True, text=True, stdin=subprocess.DEVNULL,
                                env=env, timeout=240, preexec_fn=cap)
    except subprocess.TimeoutExpired:
        return "timeout (a rank left waiting?)"
    finally:
        if case is not None:
            case.unlink()
    lines = [l for l in mpiexec_block(result.stderr.splitlines()) if l.strip()]
    problems = []
    if result.returncode != 2:
        problems.append(f"exit code {result.returncode}")
    if len(lines) != 1:
        problems.append(f"{len(lines)} stderr lines")
    error = lines[0] if lines else ""
    if lines and not error.startswith("error: "):
        problems.append("does not start with 'error: '")
    if key not in error:
        problems.append(f"does not name {key}")
    if where == CL and CL not in error:
        problems.append("does not say 'command line'")
    if location and location not in error:
        problems.append(f"does not name {location}")
    if out.exists():
        problems.append(f"{out.name} was written")
        shutil.rmtree(out, ignore_errors=True)
    if snapshot(watched) != before:
        problems.append(f"{watched} changed")
    if problems:
        return "; ".join(problems) + " | " + " / ".join(lines[:3])[:400]
    return None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("ibvalve")
    parser.add_argument("examples", type=pathlib.Path)
    parser.add_argument("work", type=pathlib.Path)
    parser.add_argument("--mpiexec", default="mpiexec")
    parser.add_argument("--ranks", type=int, default=1)
    parser.add_argument("--group")
    parser.add_argument("--subset", action="store_true")
    parser.add_argument("--cap-gib", type=float, default=0.0)
    parser.add_argument("--name", help="only the inputs whose name holds this")
    options = parser.parse_args()
    names = [row[0] for row in INPUTS]
    assert len(set(names)) == len(names), "duplicate input names"
    work = options.work.resolve()
    shutil.rmtree(work, ignore_errors=True)
    (work / "runs").mkdir(parents=True)
    (work / "cases").mkdir()
    (work / "waveforms").symlink_to(options.examples.resolve() / "waveforms")
    (work / "biaxial").symlink_to(options.examples.resolve() / "biaxial")
    # The folder the commands are given (not a run folder): it must stay as it is.
    (work / "given").mkdir()
    (work / "given" / "notes.txt").write_text("not a run\n")
    launcher = [options.ibvalve] if options.ranks == 1 else [options.mpiexec, "--oversubscribe", "-n",
                                                               str(options.ranks), options.ibvalve]
    failed = 0
    rows = [r for r in INPUTS if (not options.group or r[1] == options.group) and (not options.subset or r[5])
            and (not options.name or options.name in r[0])]
    for row in rows:
        args, location, out, case, text = prepare(row, options.examples.resolve(), work)
        problem = check(row, args, location, out, case, text, launcher, work / "given", options.cap_gib)
        print(f"{'FAIL' if problem else 'ok'}: {row[0]}" + (f": {problem}" if problem else ""), flush=True)
        failed += bool(problem)
    print(f"{len(rows) - failed} of {len(rows)} bad inputs refused as they should be ({len(INPUTS)} in the table)")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
