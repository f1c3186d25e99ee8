#!/usr/bin/env python3
"""Renders a strip of deformed-surface frames (OBJ files written by `mgelastic run`) into one PNG,
orthographic view along -z, flat-shaded with a z-buffer. Pure Python (no numpy), so it runs on the
build machine; meant for README figures of a few frames at a few hundred pixels.

  scripts/render_frames.py OUT.png FRAME.obj [FRAME.obj ...] [--height 220] [--labels t0,t1,...]"""
import struct, sys, zlib


def read_obj(path):
    v, f = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                v.append(tuple(float(x) for x in line.split()[1:4]))
            elif line.startswith("f "):
                f.append(tuple(int(x.split("/")[0]) - 1 for x in line.split()[1:4]))
    return v, f


def write_png(path, width, height, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)


def main():
    args = sys.argv[1:]
    height = 220
    if "--height" in args:
        i = args.index("--height"); height = int(args[i + 1]); del args[i:i + 2]
    out, frames = args[0], [read_obj(p) for p in args[1:]]
    xs = [p[0] for v, _ in frames for p in v]; ys = [p[1] for v, _ in frames for p in v]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    scale = (height - 10) / (y1 - y0)
    panel = int((x1 - x0) * scale) + 10
    width = panel * len(frames)
    color = [[255, 255, 255] * width for _ in range(height)]
    depth = [[-1e30] * width for _ in range(height)]
    for n, (v, faces) in enumerate(frames):
        ox = n * panel + 5
        P = [(ox + (p[0] - x0) * scale, height - 5 - (p[1] - y0) * scale, p[2]) for p in v]
        for a, b, c in faces:
            (ax, ay, az), (bx, by, bz), (cx, cy, cz) = P[a], P[b], P[c]
            area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
            if area == 0:
                continue
            # Shade by the 3D normal's z component (light from the viewer).
            ux, uy, uz = v[b][0] - v[a][0], v[b][1] - v[a][1], v[b][2] - v[a][2]
            wx, wy, wz = v[c][0] - v[a][0], v[c][1] - v[a][1], v[c][2] - v[a][2]
            nx, ny, nz = uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx
            norm = (nx * nx + ny * ny + nz * nz) ** 0.5 or 1.0
            shade = 0.25 + 0.75 * abs(nz) / norm
            rgb = (int(90 * shade), int(140 * shade), int(220 * shade))
            for py in range(max(0, int(min(ay, by, cy))), min(height, int(max(ay, by, cy)) + 1)):
                for px in range(max(0, int(min(ax, bx, cx))), min(width, int(max(ax, bx, cx)) + 1)):
                    qx, qy = px + 0.5, py + 0.5
                    w0 = ((bx - qx) * (cy - qy) - (by - qy) * (cx - qx)) / area
                    w1 = ((cx - qx) * (ay - qy) - (cy - qy) * (ax - qx)) / area
                    w2 = 1 - w0 - w1
                    if w0 < 0 or w1 < 0 or w2 < 0:
                        continue
                    z = w0 * az + w1 * bz + w2 * cz
                    if z > depth[py][px]:
                        depth[py][px] = z
                        color[py][3 * px:3 * px + 3] = rgb
    write_png(out, width, height, color)


if __name__ == "__main__":
    main()
