"""Checks that a run folder's outputs explain themselves (issue 20, item 15), reading them as ParaView and
a user would: fields.xdmf (ElementTree) and the HDF5 files it names (h5py), and timeseries.csv.

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
    xdmf = args.run / "fields.xdmf"
    if xdmf.exists():
        steps = ET.parse(xdmf).getroot().findall("./Domain/Grid/Grid")
        structures = []
        for step in steps:
            label = f"t = {step.find('Time').get('Value')}"
            for grid in step.findall("Grid"):
                fields = check_grid(args.run, grid, label)
                if grid.get("Name") == "structure":
                    check_structure(grid, fields, args, label)
                    structures.append(fields)
        print(f"fields.xdmf: {len(steps)} snapshots checked")
        if args.parts is not None and not structures:
            fail("fields.xdmf has no structure grid")
        if len(structures) >= 2 and "displacement" in structures[-1]:
            first, last = structures[0], structures[-1]
            moved = np.abs(last["displacement"][0]).max()
            reference = last["coordinates"][0] - last["displacement"][0]
            error = np.abs(reference - (first["coordinates"][0] - first["displacement"][0])).max()
            print(f"structure: coordinates - displacement = reference to {error:.1e} cm "
                  f"(largest displacement {moved:.1e} cm)")
            if error > 1e-12 * max(1.0, np.abs(reference).max()):
                fail("the structure's coordinates are not the current positions (coordinates - displacement "
                     "changes between snapshots)")
    if failures:
        print("FAIL:\n  " + "\n  ".join(failures))
        sys.exit(1)
    print("outputs explain themselves")


main()
