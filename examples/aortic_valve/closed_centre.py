#!/usr/bin/python3
"""The closed valve's centre, from an aortic-valve run folder's field snapshots (fields_fluid.xdmf).

  examples/aortic_valve/closed_centre.py RUN_DIR TIME...

For the snapshot nearest each time (seconds), prints:
- for each leaflet, its mesh node nearest the tube's axis: the distance from the axis and the height z
  (three leaflets that meet at the centre have all three near the axis, at one height);
- the axial flow through the grid's cross-section at the mean of those heights: over the whole lumen
  (r < the tube's radius) and within r < 0.3 cm of the axis, in mL/s (negative = back into the
  ventricle), from the cell-centred velocities of the snapshot (a midpoint sum over the cells);
- the fastest fluid in the box and where it is (r, z).

Used in examples/aortic_valve/study/RESULTS.md to place a closed valve's leak (at the centre, where
the free edges meet, or around the rim).
"""
import re
import sys
import tomllib
from pathlib import Path

import h5py
import numpy as np

if len(sys.argv) < 3:
    sys.exit(__doc__)
run = Path(sys.argv[1])
xdmf = (run / "fields_fluid.xdmf").read_text()  # the fluid grid; the snapshot files hold the mesh too
origin, spacing = (np.array(v.split(), float)[::-1] for v in re.findall(
    r'<DataItem Dimensions="3"[^>]*Format="XML">([^<]+)</DataItem>', xdmf)[:2])  # (z, y, x) -> (x, y, z)
snapshots = [(float(t), name) for t, name in
             re.findall(r'<Time Value="([^"]+)"/>.*?(fields/step_\d+\.h5)', xdmf, re.S)]
with open(run / "config.toml", "rb") as f:
    tube_radius = tomllib.load(f)["mesh"]["tube_radius"]

for wanted in map(float, sys.argv[2:]):
    t, name = min(snapshots, key=lambda s: abs(s[0] - wanted))
    with h5py.File(run / name) as f:
        X, conn, part = f["/mesh/coordinates"][:], f["/mesh/connectivity"][:], f["/mesh/part"][:]
        u = f["/fluid/velocity"][:]  # (z, y, x, component), cell centred
    nearest = []
    for leaflet in (1, 2, 3):
        x = X[np.unique(conn[part == leaflet].ravel())]
        r = np.hypot(x[:, 0], x[:, 1])
        nearest.append((r.min(), x[np.argmin(r), 2]))
    hx, hy, hz = spacing
    centre = lambda n, d: origin[d] + (np.arange(n) + 0.5) * spacing[d]
    zc, yc, xc = centre(u.shape[0], 2), centre(u.shape[1], 1), centre(u.shape[2], 0)
    k = int(np.argmin(np.abs(zc - np.mean([z for _, z in nearest]))))
    R = np.hypot(*np.meshgrid(xc, yc))
    uz = u[k, :, :, 2]
    lumen, core = uz[R < tube_radius].sum() * hx * hy, uz[R < 0.3].sum() * hx * hy
    speed = np.linalg.norm(u, axis=-1)
    m = np.unravel_index(np.argmax(speed), speed.shape)
    print(f"t = {t:.3f} s: leaflet nodes nearest the axis "
          + ", ".join(f"{r:.3f} cm (z {z:.2f})" for r, z in nearest)
          + f"; axial flow at z = {zc[k]:.3f} cm: lumen {lumen:.2f} mL/s, r < 0.3 cm {core:.2f} mL/s;"
          f" fastest fluid {speed.max():.0f} cm/s at r = {np.hypot(xc[m[2]], yc[m[1]]):.2f} cm, z = {zc[m[0]]:.2f} cm")
