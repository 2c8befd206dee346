"""Checks that a run folder's outputs explain themselves, reading them as ParaView and a user would: the
XDMF series fields_fluid.xdmf and fields_structure.xdmf (ElementTree) and the HDF5 files they name (h5py),
and timeseries.csv.

  - the fluid and the structure are two series, two datasets in ParaView: fields_fluid.xdmf holds the
    fluid's grids alone, fields_structure.xdmf the structure's mesh alone (no fields.xdmf holding both),
    at the same times; each is XML with one grid per time whose name is the same at every time (and so
    are the names of the grids inside it), so ParaView keeps one block as the animation runs;
  - no array name is in both series (the structure's node velocity is `structure_velocity`, the fluid's
    cell velocity `velocity`); the structure's stress is `cauchy_stress_along_fiber [kPa]`, the unit of
    the report, with an Information element saying what it is;
  - every real dataset an XDMF Attribute or Geometry names has a `units` attribute, and the Attribute's
    name is "<dataset name> [<units>]" ("J" alone for a pure number, units "1");
  - the structure (when there is one): an integer cell attribute `part` whose ids are 1..N with the names
    given by --parts, stated in the grid's Information "part" and the dataset's `parts` attribute;
    `fiber_reference` and `fiber_direction` per element, unit vectors in the parts given by --fibers-in
    and zero elsewhere; the geometry is the current positions (Information "geometry"), so the last
    snapshot's coordinates minus its displacement are the first snapshot's (the reference);
  - timeseries.csv: a '# units: ' line right under the header with one unit per column;
  - with --extra-metrics KEY,...: extra_metrics.json holds each KEY as an object with a finite value,
    a unit, a symbol and a description (the aortic-valve model's fit_error).

Usage: check_outputs.py RUN_DIR [--parts leaflet1,leaflet2,leaflet3,tube] [--fibers-in leaflet1,...]"""
import argparse
import json
import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np

failures = []


def fail(message):
    failures.append(message)


def dataset(run, item):
    file_name, name = item.text.strip().split(":")
    with h5py.File(run / file_name, "r") as f:
        data = f[name]
        return data[...], {k: (v.decode() if isinstance(v, bytes) else str(v)) for k, v in data.attrs.items()}


def check_grid(run, grid, step):
    """The attributes of one grid: {dataset name: (values, attributes)}."""
    fields = {}
    geometry = grid.find("Geometry/DataItem")
    if geometry is not None and geometry.get("Format") == "HDF":
        values, attrs = dataset(run, geometry)
        if attrs.get("units") != "cm":
            fail(f"{step} {grid.get('Name')}: the geometry dataset has units {attrs.get('units')!r}, not 'cm'")
        fields["coordinates"] = (values, attrs)
    for attribute in grid.findall("Attribute"):
        item = attribute.find("DataItem")
        values, attrs = dataset(run, item)
        name = item.text.strip().split(":")[1].rsplit("/", 1)[-1]
        shown = attribute.get("Name")
        if np.issubdtype(values.dtype, np.floating):
            units = attrs.get("units")
            if not units:
                fail(f"{step} {grid.get('Name')}/{name}: no units attribute")
            elif shown != (name if units == "1" else f"{name} [{units}]"):
                fail(f"{step} {grid.get('Name')}/{name}: XDMF name {shown!r} does not show its units {units!r}")
        elif item.get("NumberType") != "Int":
            fail(f"{step} {grid.get('Name')}/{name}: integer data not declared NumberType=\"Int\"")
        fields[name] = (values, attrs)
    return fields


def check_structure(grid, fields, args, step):
    information = {i.get("Name"): i.get("Value") for i in grid.findall("Information")}
    if "current positions" not in information.get("geometry", ""):
        fail(f"{step}: the structure's Information 'geometry' does not say the coordinates are current positions")
    stress = fields.get("cauchy_stress_along_fiber")
    if stress is None or stress[1].get("units") != "kPa":
        fail(f"{step}: the structure has no 'cauchy_stress_along_fiber' in kPa")
    elif "total Cauchy stress" not in information.get("cauchy_stress_along_fiber", ""):
        fail(f"{step}: no Information saying what cauchy_stress_along_fiber is")
    if "part" not in fields:
        fail(f"{step}: the structure has no cell attribute 'part'")
        return
    part, attrs = fields["part"]
    expected = ", ".join(f"{i + 1} = {name}" for i, name in enumerate(args.parts)) if args.parts else None
    if expected is not None:
        if information.get("part") != expected:
            fail(f"{step}: Information 'part' is {information.get('part')!r}, expected {expected!r}")
        if attrs.get("parts") != expected:
            fail(f"{step}: mesh/part's 'parts' attribute is {attrs.get('parts')!r}, expected {expected!r}")
        ids = sorted(set(part.tolist()))
        if ids != list(range(1, len(args.parts) + 1)):
            fail(f"{step}: part ids {ids}, expected 1..{len(args.parts)}")
    for name in ("fiber_reference", "fiber_direction"):
        if name not in fields:
            fail(f"{step}: the structure has no cell attribute '{name}'")
            continue
        f = fields[name][0]
        length = np.linalg.norm(f, axis=1)
        with_fibers = np.isin(part, [args.parts.index(p) + 1 for p in args.fibers_in]) if args.fibers_in else length > 0
        if args.fibers_in and not with_fibers.any():
            fail(f"{step}: no element with fibers")
        if np.abs(length[with_fibers] - 1).max(initial=0) > 1e-12:
            fail(f"{step}: {name} not unit length in the fiber parts (max |len - 1| "
                 f"{np.abs(length[with_fibers] - 1).max():.2e})")
        if np.abs(length[~with_fibers]).max(initial=0) > 0:
            fail(f"{step}: {name} not zero outside the fiber parts")


def read_series(run, name):
    """The output times of the series <run>/<name>: [(time, [grids])], one grid per time holding them.
    Fails where the name of a time's grid, or of a grid inside it, changes from one time to the next."""
    try:
        root = ET.parse(run / name).getroot()
    except ET.ParseError as error:
        fail(f"{name}: not XML: {error}")
        return []
    steps = root.findall("./Domain/Grid/Grid")
    if not steps:
        fail(f"{name}: no output time")
    names = sorted({step.get("Name") for step in steps})
    inner = sorted({tuple(grid.get("Name") for grid in step.findall("Grid")) for step in steps})
    if len(names) != 1 or len(inner) > 1:
        fail(f"{name}: the names of the grids change with time: {names} holding {inner}")
    series = []
    for step in steps:
        inside = step.findall("Grid")
        series.append((float(step.find("Time").get("Value")), inside if inside else [step]))
    print(f"{name}: {len(steps)} output times, each one grid named {names[0]!r}"
          + (f" holding {len(inner[0])} grids" if inner and inner[0] else ""))
    return series


def check_fluid_series(run):
    """fields_fluid.xdmf: regular grids only. Returns the times and the array names."""
    times, names = [], set()
    for t, grids in read_series(run, "fields_fluid.xdmf"):
        times.append(t)
        for grid in grids:
            if grid.find("Topology").get("TopologyType") != "3DCoRectMesh":
                fail(f"fields_fluid.xdmf, t = {t}: grid {grid.get('Name')!r} is not the fluid's regular grid")
            check_grid(run, grid, f"t = {t}")
            names |= {attribute.get("Name") for attribute in grid.findall("Attribute")}
    return times, names


def check_structure_series(run, args):
    """fields_structure.xdmf: the structure's mesh alone. Returns the times, the array names and the
    fields of each time."""
    times, names, structures = [], set(), []
    for t, grids in read_series(run, "fields_structure.xdmf"):
        times.append(t)
        if [grid.get("Name") for grid in grids] != ["structure"]:
            fail(f"fields_structure.xdmf, t = {t}: grids {[g.get('Name') for g in grids]}, expected the structure alone")
            continue
        fields = check_grid(run, grids[0], f"t = {t}")
        check_structure(grids[0], fields, args, f"t = {t}")
        names |= {attribute.get("Name") for attribute in grids[0].findall("Attribute")}
        structures.append(fields)
    return times, names, structures


def check_reference(structures):
    """Current positions: the last snapshot's coordinates minus its displacement are the first's."""
    if len(structures) < 2 or "displacement" not in structures[-1]:
        return
    first, last = structures[0], structures[-1]
    moved = np.abs(last["displacement"][0]).max()
    reference = last["coordinates"][0] - last["displacement"][0]
    error = np.abs(reference - (first["coordinates"][0] - first["displacement"][0])).max()
    print(f"structure: coordinates - displacement = reference to {error:.1e} cm "
          f"(largest displacement {moved:.1e} cm)")
    if error > 1e-12 * max(1.0, np.abs(reference).max()):
        fail("the structure's coordinates are not the current positions (coordinates - displacement "
             "changes between snapshots)")


def check_fields(args):
    run = args.run
    if (run / "fields.xdmf").exists():
        fail("fields.xdmf: one series holding the fluid and the structure (ParaView merges or renames "
             "them); they go in fields_fluid.xdmf and fields_structure.xdmf")
    if not (run / "fields").is_dir():
        return
    if not (run / "fields_fluid.xdmf").exists():
        fail("field files but no fields_fluid.xdmf")
        return
    fluid_times, fluid_names = check_fluid_series(run)
    if args.parts is None:
        return
    if not (run / "fields_structure.xdmf").exists():
        fail("no fields_structure.xdmf")
        return
    times, names, structures = check_structure_series(run, args)
    if times != fluid_times:
        fail(f"the structure's output times {times} are not the fluid's {fluid_times}")
    if fluid_names & names:
        fail(f"array names in both series: {sorted(fluid_names & names)}")
    print(f"fluid arrays {sorted(fluid_names)}, structure arrays {sorted(names)}: none in both")
    check_reference(structures)


def check_series(run):
    path = run / "timeseries.csv"
    if not path.exists():
        return
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    if len(lines) < 2 or not lines[1].startswith("# units: "):
        fail(f"timeseries.csv: line 2 is not the '# units: ' line: {lines[1] if len(lines) > 1 else ''!r}")
        return
    units = lines[1][len("# units: "):].split(",")
    if len(units) != len(header) or not all(units):
        fail(f"timeseries.csv: {len(units)} units for {len(header)} columns: {lines[1]!r}")
    if any(line.startswith("#") for line in lines[2:]):
        fail("timeseries.csv: a '#' line among the rows")
    print("timeseries.csv units: " + ", ".join(f"{c} [{u}]" for c, u in zip(header, units)))


def check_extra_metrics(run, keys):
    path = run / "extra_metrics.json"
    if not path.exists():
        fail("no extra_metrics.json")
        return
    extra = json.loads(path.read_text())
    for key in keys:
        entry = extra.get(key)
        if not isinstance(entry, dict) or not all(entry.get(k) for k in ("unit", "symbol", "description")):
            fail(f"extra_metrics.json: {key}: not an object with a unit, a symbol and a description: {entry!r}")
        elif not isinstance(entry.get("value"), (int, float)) or not math.isfinite(entry["value"]):
            fail(f"extra_metrics.json: {key}: value {entry.get('value')!r} is not a finite number")
        else:
            print(f"extra_metrics.json: {key} = {entry['value']:.4g} {entry['unit']}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", type=Path)
    parser.add_argument("--parts", type=lambda s: s.split(","), default=None)
    parser.add_argument("--fibers-in", type=lambda s: [p for p in s.split(",") if p], default=None,
                        help="the parts with fibers (default: any element whose vector is not zero)")
    parser.add_argument("--extra-metrics", type=lambda s: s.split(","), default=[])
    args = parser.parse_args()
    check_series(args.run)
    if args.extra_metrics:
        check_extra_metrics(args.run, args.extra_metrics)
    check_fields(args)
    if failures:
        print("FAIL:\n  " + "\n  ".join(failures))
        sys.exit(1)
    print("outputs explain themselves")


main()
