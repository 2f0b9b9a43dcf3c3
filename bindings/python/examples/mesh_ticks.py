#!/usr/bin/env python3
"""Loads a triangle mesh from an OBJ or STL file, scatters moving copies of it in
a box, runs ticks and saves a picture of the last tick with the colliding
bodies in red.

    python3 mesh_ticks.py [MESH] [--n N] [--ticks T] [--side L] [--seed S]
                          [--threads K] [--out tick.png]

MESH defaults to torus.obj beside this file. The file is read by meshio
(Debian python3-meshio), which knows OBJ, STL, PLY and more; polygons are
split into triangles, and vertices at exactly the same position are welded
(STL stores each triangle's corners separately: without welding no edge would
be shared and the mesh would be open, so it could not contain anything).
"""
import argparse
import os
import time

import matplotlib
import meshio
import numpy as np

import hgcd

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the backend)
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def load_mesh(path):
    """(vertices (V, 3) float64, triangles (T, 3) uint32), welded, centred, radius 1."""
    m = meshio.read(path)
    faces = []
    for block in m.cells:
        if block.type in ("triangle", "quad", "polygon"):
            f = np.asarray(block.data)
            faces += [f[:, [0, k, k + 1]] for k in range(1, f.shape[1] - 1)]  # fans
    if not faces:
        raise SystemExit(f"{path}: no triangles or polygons")
    faces = np.concatenate(faces)
    points, weld = np.unique(np.asarray(m.points, dtype=np.float64)[:, :3], axis=0, return_inverse=True)
    triangles = weld.reshape(-1)[faces].astype(np.uint32)
    used = points[np.unique(triangles)]
    centre = (used.min(axis=0) + used.max(axis=0)) / 2
    points = points - centre
    return points / np.linalg.norm(points[np.unique(triangles)], axis=1).max(), triangles


def random_unit_quaternions(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def rotation_matrices(q):
    """(n, 3, 3) rotations of unit quaternions (x, y, z, w), for drawing only."""
    x, y, z, w = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def draw(path, vertices, triangles, positions, orientations, scales, colliding, side, title):
    world = positions[:, None, :] + scales[:, None, None] * np.einsum(
        "bij,vj->bvi", rotation_matrices(orientations), vertices)
    polys = world[:, triangles]  # (bodies, T, 3 corners, xyz)
    fig = plt.figure(figsize=(6, 6), dpi=100)
    ax = fig.add_subplot(projection="3d")
    for hit, colour, alpha in ((False, "#9aa5b1", 0.25), (True, "#d62728", 0.9)):
        sel = colliding == hit
        if sel.any():
            ax.add_collection3d(Poly3DCollection(polys[sel].reshape(-1, 3, 3), facecolor=colour,
                                                 edgecolor="#333333", linewidth=0.05, alpha=alpha))
    ax.set_xlim(0, side)
    ax.set_ylim(0, side)
    ax.set_zlim(0, side)
    ax.set_box_aspect((1, 1, 1))
    ax.set_title(title)
    fig.savefig(path)
    plt.close(fig)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("mesh", nargs="?", default=os.path.join(here, "torus.obj"))
    p.add_argument("--n", type=int, default=100)
    p.add_argument("--ticks", type=int, default=20)
    p.add_argument("--side", type=float, default=16.0)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--out", default="tick.png")
    a = p.parse_args()

    vertices, triangles = load_mesh(a.mesh)
    rng = np.random.default_rng(a.seed)
    with hgcd.World(threads=a.threads, bounds=((0, 0, 0), (a.side,) * 3)) as world:
        mesh = world.create_mesh(vertices, triangles)
        info = mesh.info()
        print(f"{os.path.basename(a.mesh)}: {info.vertex_count} vertices, {info.triangle_count} triangles, "
              f"closed {info.closed}, convex {info.convex}")
        scales = np.exp(rng.uniform(np.log(0.5), np.log(1.5), a.n))
        world.create_bodies(mesh, positions=rng.uniform(1.5, a.side - 1.5, (a.n, 3)),
                            orientations=random_unit_quaternions(rng, a.n),
                            velocities=rng.uniform(-0.1, 0.1, (a.n, 3)), scales=scales)
        for tick in range(a.ticks):
            t0 = time.perf_counter()
            world.step()
            pairs = world.pairs()
            ms = 1e3 * (time.perf_counter() - t0)
        st = world.stats()
        print(f"{a.ticks} ticks of {a.n} bodies; last tick: {len(pairs)} pairs "
              f"({st.containment_pairs} by containment), {ms:.2f} ms")
        positions, orientations = world.get_poses()
    colliding = np.zeros(a.n, dtype=bool)
    colliding[pairs.reshape(-1)] = True
    draw(a.out, vertices, triangles, positions, orientations, scales, colliding, a.side,
         f"tick {a.ticks}: {colliding.sum()} of {a.n} bodies collide ({len(pairs)} pairs)")
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
