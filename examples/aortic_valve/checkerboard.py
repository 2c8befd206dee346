#!/usr/bin/python3
"""The leaflets' element fiber stress of an aortic-valve run's field snapshots, split into the volumetric
penalty's pressure and the rest, and the element-by-element alternation (checkerboard) of each part.

usage: checkerboard.py RUN_DIR SNAPSHOT.h5... [--kappa 1000] [--across 24] [--radial 10]

For every snapshot (RUN_DIR/fields/step_*.h5, written by `ibvalve run`), independently of the C++:
  - each leaflet element's mean deformation gradient at its centre (trilinear hex: dN_a/dxi = xi_a / 8
    there) from the stored current coordinates x and displacement u (X = x - u), J_c = det F_c;
  - the log penalty's stress along any direction, v = kappa ln J_c / J_c (docs/fe.md; the stress of the
    centre law is isotropic), and the rest d = s - v of the stored element fiber stress s;
  - the checkerboard component of a field q over each leaflet's structured sheet (radial x across
    elements, one through the thickness), c = (q_ij - q_i+1,j - q_i,j+1 + q_i+1,j+1) / 4 over its 2 x 2
    patches: its rms and largest size, against the spread (standard deviation) of the patch means;
  - the same after the output filter of fe/solid.hpp (SolidModel::filtered_centre_stress) written
    again here: node means of the element pressures weighted by reference volume, element means of
    the node means. Fields written before the filter (2026-12-06) hold the unfiltered s.
Figures in MPa. Used for docs/notebook/checkerboard-2026-12-06.md.
"""
import argparse
import pathlib

import h5py
import numpy as np

# Reference positions of the 8 nodes of a trilinear hex in Gmsh/XDMF order.
CORNERS = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                    [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], float)


def centre_jacobian(X, x, conn):
    """det of the centre deformation gradient of every element, and the elements' reference volumes."""
    dX = np.einsum("eai,aj->eij", X[conn], CORNERS) / 8
    dx = np.einsum("eai,aj->eij", x[conn], CORNERS) / 8
    if not (np.linalg.det(dX) > 0).all():
        raise SystemExit("unexpected node ordering: a reference Jacobian is not positive")
    return np.linalg.det(dx @ np.linalg.inv(dX)), 8 * np.linalg.det(dX)


def checkerboard(q, leaflets, radial, across):
    """rms and largest checkerboard component, spread of the 2 x 2 patch means (MPa)."""
    c, m = [], []
    for leaflet in range(leaflets):
        g = q[leaflet * radial * across:(leaflet + 1) * radial * across].reshape(radial, across)
        c.append(((g[:-1, :-1] - g[1:, :-1] - g[:-1, 1:] + g[1:, 1:]) / 4).ravel())
        m.append(((g[:-1, :-1] + g[1:, :-1] + g[:-1, 1:] + g[1:, 1:]) / 4).ravel())
    c, m = np.concatenate(c), np.concatenate(m)
    return np.sqrt(np.mean(c ** 2)) / 1e7, np.abs(c).max() / 1e7, np.std(m) / 1e7


def node_filter(v, conn, volume, elements, nodes):
    """The output filter: volume-weighted node means, then element means of the node means."""
    num, den = np.zeros(nodes), np.zeros(nodes)
    np.add.at(num, conn[elements], (volume[elements] * v[elements])[:, None])
    np.add.at(den, conn[elements], volume[elements][:, None])
    out = np.zeros_like(v)
    out[elements] = (num[conn[elements]] / den[conn[elements]]).mean(axis=1)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", type=pathlib.Path)
    parser.add_argument("snapshots", nargs="+")
    parser.add_argument("--kappa", type=float, default=1000.0, help="the leaflets' bulk modulus, kPa")
    parser.add_argument("--across", type=int, default=24, help="mesh.leaflet_across")
    parser.add_argument("--radial", type=int, default=10, help="mesh.leaflet_radial")
    args = parser.parse_args()
    kappa = args.kappa * 1e4  # dyn/cm^2
    print("| snapshot | s: checkerboard rms, max; patch spread | penalty's part | rest | "
          "filtered penalty | filtered s | mean s -> filtered |")
    print("|---|---|---|---|---|---|---|")
    for name in args.snapshots:
        with h5py.File(args.run / "fields" / name) as h:
            x = h["mesh/coordinates"][:]
            u = h["mesh/displacement"][:]
            conn = h["mesh/connectivity"][:]
            part = h["mesh/part"][:]
            # dyn/cm^2 as fiber_stress before 2026-12-06, kPa as cauchy_stress_along_fiber since
            s = h["mesh/fiber_stress"][:] if "mesh/fiber_stress" in h else h["mesh/cauchy_stress_along_fiber"][:] * 1e4
        leaf = np.where(part <= 3)[0]  # parts 1-3 are the leaflets, element-major from 0
        if len(leaf) != 3 * args.radial * args.across or leaf.max() != len(leaf) - 1:
            raise SystemExit(f"{name}: {len(leaf)} leaflet elements, not 3 x {args.radial} x {args.across}")
        J, volume = centre_jacobian(x - u, x, conn)
        v = kappa * np.log(J) / J
        rest = s - v
        vf = node_filter(v, conn, volume, leaf, len(x))
        row = [checkerboard(q, 3, args.radial, args.across) for q in (s, v, rest, vf, rest + vf)]
        cells = " | ".join("%.4f, %.4f; %.4f" % r for r in row)
        print(f"| {name} | {cells} | {s[leaf].mean() / 1e7:.4f} -> {(rest + vf)[leaf].mean() / 1e7:.4f} |")


if __name__ == "__main__":
    main()
