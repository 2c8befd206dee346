"""Reads a fluid run's fields_fluid.xdmf and the HDF5 files it names (h5py), and checks them against the
Taylor-Green vortex the run started from: the array shapes and grid the XDMF describes, the time of
each step, the velocity and pressure against the exact solution, the vorticity against the exact
vorticity, and timeseries.csv's columns. Usage: check_fields.py RUN_DIR"""
import csv
import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np

run = Path(sys.argv[1])
nu, mean, k = 0.01, (0.5, 0.0, 0.0), 2.0 * math.pi
nx, ny, nz, h = 16, 16, 8, 1.0 / 16

root = ET.parse(run / "fields_fluid.xdmf").getroot()
steps = root.findall("./Domain/Grid/Grid")  # one grid per output time, the fluid's
assert len(steps) == 3, f"expected 3 output times (steps 0, 5, 10), found {len(steps)}"
z, y, x = np.meshgrid((np.arange(nz) + 0.5) * h, (np.arange(ny) + 0.5) * h, (np.arange(nx) + 0.5) * h, indexing="ij")
for step in steps:
    t = float(step.find("Time").get("Value"))
    grid = step
    dims = [int(v) for v in grid.find("Topology").get("Dimensions").split()]
    assert dims == [nz + 1, ny + 1, nx + 1], dims
    fields = {}
    for attribute in grid.findall("Attribute"):
        item = attribute.find("DataItem")
        file_name, dataset = item.text.strip().split(":")
        with h5py.File(run / file_name, "r") as f:
            data = f[dataset][...]
            pressure_time = f.attrs["pressure_time"]
        shape = [int(v) for v in item.get("Dimensions").split()]
        assert list(data.shape) == shape, (attribute.get("Name"), data.shape, shape)
        fields[attribute.get("Name").split(" [")[0]] = data  # "velocity [cm/s]": the name before the units
    e = math.exp(-2 * k * k * nu * t)

    def exact_u(xx, yy):
        X, Y = k * (xx - mean[0] * t), k * (yy - mean[1] * t)
        return mean[0] - np.cos(X) * np.sin(Y) * e, mean[1] + np.sin(X) * np.cos(Y) * e

    def exact_omega_z(xx, yy):
        return 2 * k * np.cos(k * (xx - mean[0] * t)) * np.cos(k * (yy - mean[1] * t)) * e

    # The files hold cell averages of the two faces (velocity) and of the four edges (vorticity):
    # average the exact solution the same way, so what remains is the scheme's error.
    u = np.stack([0.5 * (exact_u(x - h / 2, y)[0] + exact_u(x + h / 2, y)[0]),
                  0.5 * (exact_u(x, y - h / 2)[1] + exact_u(x, y + h / 2)[1]), 0 * x], axis=-1)
    omega_z = 0.25 * sum(exact_omega_z(x + a * h / 2, y + b * h / 2) for a in (-1, 1) for b in (-1, 1))
    Xp, Yp = k * (x - mean[0] * pressure_time), k * (y - mean[1] * pressure_time)
    p = -0.25 * (np.cos(2 * Xp) + np.cos(2 * Yp)) * math.exp(-4 * k * k * nu * pressure_time)
    numeric_p = fields["pressure"] - fields["pressure"].mean()
    errors = (np.abs(fields["velocity"] - u).max(), np.abs(numeric_p - (p - p.mean())).max(),
              np.abs(fields["vorticity"][..., 2] - omega_z).max(), np.abs(fields["vorticity"][..., :2]).max())
    print(f"t = {t:.3f}: max errors u {errors[0]:.2e}, p {errors[1]:.2e}, omega_z {errors[2]:.2e} "
          f"(|omega_z| {2 * k * e:.2f}), omega_xy {errors[3]:.1e}")
    assert errors[0] < 5e-3 and errors[1] < 2e-2, errors
    # The discrete curl of the exact velocity differs from the exact curl by O((k h)^2 / 24).
    assert errors[2] < 0.03 * 2 * k, errors
    assert errors[3] < 1e-12, errors

with open(run / "timeseries.csv") as f:
    rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
assert len(rows) == 11, len(rows)
for row in rows:
    assert float(row["max_divergence"]) < 1e-10 * float(row["max_velocity"]) / h, row
    assert float(row["u_error_max"]) < 0.02, row
energy0 = float(rows[0]["kinetic_energy"])
volume = 0.5
# 1/2 int |u|^2 = V/2 (U^2 + 1/4 + 1/4) for the vortex of amplitude 1 carried by (U, 0, 0).
assert abs(energy0 - 0.5 * volume * (mean[0] ** 2 + 0.5)) < 1e-2 * energy0, energy0
print("fields_fluid.xdmf, HDF5 files and timeseries.csv check out")
