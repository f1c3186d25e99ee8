#!/usr/bin/python3
"""Renders a strip of deformed-surface frames (OBJ files written by `mgelastic run`) into one PNG
with matplotlib: orthographic view along -z, flat shading by the face normal, painter's order.
Meant for README and docs figures of a few frames.

  scripts/render_frames.py OUT.png FRAME.obj [FRAME.obj ...] [--height 220] [--labels t0,t1,...]

Needs numpy and matplotlib (Debian python3-numpy python3-matplotlib)."""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402


def read_obj(path):
    """Vertices (n, 3) and triangles (m, 3) of an OBJ file (polygons fanned into triangles)."""
    vertices, triangles = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                ids = [int(x.split("/")[0]) - 1 for x in line.split()[1:]]
                triangles.extend([ids[0], ids[k], ids[k + 1]] for k in range(1, len(ids) - 1))
    if not vertices or not triangles:
        raise SystemExit(f"{path}: no vertices or faces")
    return np.array(vertices), np.array(triangles)


def shaded_polygons(vertices, triangles):
    """Triangles projected on the xy plane, back to front, with a grey level from |n_z|."""
    corners = vertices[triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    lengths = np.linalg.norm(normals, axis=1)
    keep = lengths > 0
    corners, normals, lengths = corners[keep], normals[keep], lengths[keep]
    order = np.argsort(corners[:, :, 2].mean(axis=1))  # farthest (smallest z) first
    shade = 0.25 + 0.75 * np.abs(normals[order, 2]) / lengths[order]
    colors = np.outer(shade, [90 / 255, 140 / 255, 220 / 255])
    return corners[order, :, :2], colors


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("frames", nargs="+")
    parser.add_argument("--height", type=int, default=220, help="image height in pixels")
    parser.add_argument("--labels", default="", help="comma-separated captions, one per frame")
    args = parser.parse_args()
    meshes = [read_obj(p) for p in args.frames]
    labels = args.labels.split(",") if args.labels else []
    points = np.concatenate([v for v, _ in meshes])
    (x0, y0), (x1, y1) = points[:, :2].min(axis=0), points[:, :2].max(axis=0)
    pad = 0.04 * max(x1 - x0, y1 - y0)
    panel_aspect = (x1 - x0 + 2 * pad) / (y1 - y0 + 2 * pad)
    dpi = 100
    height = args.height / dpi
    fig, axes = plt.subplots(1, len(meshes), figsize=(height * panel_aspect * len(meshes), height),
                             dpi=dpi, squeeze=False)
    for n, (ax, (vertices, triangles)) in enumerate(zip(axes[0], meshes)):
        polygons, colors = shaded_polygons(vertices, triangles)
        ax.add_collection(PolyCollection(polygons, facecolors=colors, edgecolors="none"))
        ax.set_xlim(x0 - pad, x1 + pad)
        ax.set_ylim(y0 - pad, y1 + pad)
        ax.set_aspect("equal")
        ax.axis("off")
        if n < len(labels):
            ax.set_title(labels[n], fontsize=8)
    fig.subplots_adjust(left=0, right=1, bottom=0, top=0.9 if labels else 1, wspace=0)
    fig.savefig(args.out, facecolor="white")


if __name__ == "__main__":
    main()
