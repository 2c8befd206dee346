#!/usr/bin/python3
"""Element quality of the leaflets over a run, from an aortic-valve run folder's field snapshots.

  examples/aortic_valve/quadrature_jacobians.py RUN_DIR [--every N] [--tips]

The aortic-valve model integrates the volumetric penalty once per element (selective reduced
integration, docs/fe.md) and the tissue law on the 2 x 2 x 2 Gauss rule, so an element's mean volume
is held while its corners may collapse. For every N-th snapshot this prints the smallest
J = det F over the Gauss points of the leaflet elements (below 0: an inverted corner), the element
and where it is now (r, theta in degrees, z; cm), J at the element's centre, and how many Gauss points
lie below 0.5 and 0.2. With --tips, also the Gauss points within 0.15 cm (in the reference
configuration) of each leaflet's node nearest the axis, where the study's top-centre sphere sits: the
reported fiber stress there is Cauchy's, sigma = P F^T / J, so a point near J = 0 dominates the average.
"""
import argparse
import re
from pathlib import Path

import h5py
import numpy as np

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("run", type=Path)
parser.add_argument("--every", type=int, default=1)
parser.add_argument("--tips", action="store_true")
args = parser.parse_args()

# Trilinear hexahedron, nodes at the corners (-1/+1)^3 in the mesh's order (bottom face 0-3, top 4-7).
corners = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                    [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], float)


def shape(p):
    return np.prod(1 + corners * p, axis=1) / 8


def shape_gradient(p):  # (8, 3): dN_a / dxi_i at p
    g = np.empty((8, 3))
    for i in range(3):
        others = [j for j in range(3) if j != i]
        g[:, i] = corners[:, i] * np.prod(1 + corners[:, others] * p[others], axis=1) / 8
    return g


gauss = corners / np.sqrt(3)


def jacobian_ratio(p, x, X):  # det F at p for elements x, X: (elements, 8, 3)
    g = shape_gradient(p)
    return np.linalg.det(np.einsum("eai,aj->eij", x, g)) / np.linalg.det(np.einsum("eai,aj->eij", X, g))


xdmf = (args.run / "fields_structure.xdmf").read_text()
snapshots = re.findall(r'<Time Value="([^"]+)"/>.*?(fields/step_\d+\.h5)', xdmf, re.S)
for t, name in snapshots[::args.every]:
    with h5py.File(args.run / name) as f:
        x, u = f["/mesh/coordinates"][:], f["/mesh/displacement"][:]
        connectivity, part = f["/mesh/connectivity"][:], f["/mesh/part"][:]
    X = x - u  # the field files hold the current positions
    leaflets = np.where(part < 4)[0]
    xe, Xe = x[connectivity[leaflets]], X[connectivity[leaflets]]
    J = np.stack([jacobian_ratio(p, xe, Xe) for p in gauss], axis=1)
    worst = int(np.argmin(J.min(axis=1)))
    c = xe[worst].mean(axis=0)
    print(f"t = {float(t):.3f} s: smallest Gauss-point J {J.min():.3f} (element {leaflets[worst]}, "
          f"r {np.hypot(c[0], c[1]):.2f} theta {np.degrees(np.arctan2(c[1], c[0])):.0f} z {c[2]:.2f}; "
          f"centre J {jacobian_ratio(np.zeros(3), xe[worst:worst + 1], Xe[worst:worst + 1])[0]:.3f}); "
          f"points below 0.5: {(J < 0.5).sum()}, below 0.2: {(J < 0.2).sum()} of {J.size}")
    if args.tips:
        for leaflet in (1, 2, 3):
            elements = np.where(part == leaflet)[0]
            nodes = np.unique(connectivity[elements].ravel())
            tip = X[nodes[np.argmin(np.hypot(X[nodes, 0], X[nodes, 1]))]]
            near = []
            for p in gauss:
                positions = np.einsum("a,eai->ei", shape(p), X[connectivity[elements]])
                inside = elements[np.linalg.norm(positions - tip, axis=1) < 0.15]
                if inside.size:
                    near.extend(jacobian_ratio(p, x[connectivity[inside]], X[connectivity[inside]]))
            near = np.array(near)
            print(f"    leaflet {leaflet} tip: {near.size} Gauss points, J from {near.min():.3f} to {near.max():.3f}"
                  f" (median {np.median(near):.3f})")
