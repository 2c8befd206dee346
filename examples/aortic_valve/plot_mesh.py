#!/usr/bin/python3
"""Draws an aortic-valve mesh (from `ibvalve mesh aortic-valve`) as a PNG: the leaflets' outer
faces from above and from the side, the tube as a wire outline. Reads the .msh with the gmsh API.

    /usr/bin/python3 plot_mesh.py valve.msh mesh.png
"""
import sys

import gmsh
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection


def hex_faces(connectivity):
    # Gmsh hexahedron faces (local node numbers), outward.
    local = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (0, 4, 7, 3)]
    faces = {}
    for element in connectivity:
        for f in local:
            nodes = tuple(element[i] for i in f)
            key = tuple(sorted(nodes))
            if key in faces:
                del faces[key]  # interior face: shared by two elements
            else:
                faces[key] = nodes
    return list(faces.values())


def group_elements(name):
    for dim, tag in gmsh.model.getPhysicalGroups(3):
        if gmsh.model.getPhysicalName(dim, tag) != name:
            continue
        connectivity = []
        for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
            types, _, nodes = gmsh.model.mesh.getElements(dim, entity)
            for t, n in zip(types, nodes):
                if t == 5:
                    connectivity.extend(np.asarray(n, dtype=np.int64).reshape(-1, 8).tolist())
        return connectivity
    return []


def main(mesh_file, png_file):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(mesh_file)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    position = dict(zip(tags.tolist(), np.asarray(coords).reshape(-1, 3)))
    colours = ["tab:red", "tab:green", "tab:blue"]
    leaflets = [group_elements(f"leaflet{k}") for k in (1, 2, 3)]
    tube = group_elements("tube")
    gmsh.finalize()

    fig = plt.figure(figsize=(11, 5.2))
    views = [(90, -90, "from the aorta (closed state)"), (12, -60, "from the side")]
    for i, (elevation, azimuth, title) in enumerate(views):
        ax = fig.add_subplot(1, 2, i + 1, projection="3d")
        for connectivity, colour in zip(leaflets, colours):
            polygons = [[position[n] for n in face] for face in hex_faces(connectivity)]
            ax.add_collection3d(Poly3DCollection(polygons, facecolor=colour, edgecolor="k", linewidths=0.1, alpha=0.85))
        if tube:
            z = np.array([position[n][2] for e in tube for n in e])
            r = max(np.hypot(*position[n][:2]) for n in tube[0])
            theta = np.linspace(0, 2 * np.pi, 100)
            for zz in (z.min(), z.max()):
                ax.plot(r * np.cos(theta), r * np.sin(theta), zz, color="grey", linewidth=0.8)
        all_points = np.array([position[n] for c in leaflets for e in c for n in e])
        centre = all_points.mean(axis=0)
        half = 1.5
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[1] - half, centre[1] + half)
        ax.set_zlim(centre[2] - half, centre[2] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(elevation, azimuth)
        ax.set_xlabel("x (cm)")
        ax.set_ylabel("y (cm)")
        ax.set_zlabel("z (cm)")
        ax.set_title(title)
    fig.suptitle(f"{mesh_file}: three leaflets (red, green, blue), tube ends in grey")
    fig.tight_layout()
    fig.savefig(png_file, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
