#!/usr/bin/env python3
"""Writes the seed corpora fuzz/corpus/<target>/ (small valid files of every variant each reader
accepts, so the fuzzer starts from deep inside the formats). Rerun after changing a seed here."""
import json
import pathlib
import struct

root = pathlib.Path(__file__).resolve().parent / "corpus"
P = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)]  # two tets sharing a face
T = [(0, 1, 2, 3), (1, 2, 3, 4)]
F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]  # a tetrahedron's surface


def write(target, name, data):
    folder = root / target
    folder.mkdir(parents=True, exist_ok=True)
    (folder / name).write_bytes(data.encode() if isinstance(data, str) else data)


def num(x):
    return f"{x:g}"


# ---- surface meshes ----
v4 = "".join(f"v {' '.join(map(num, p))}\n" for p in P[:4])
write("obj", "tet.obj", "# tetrahedron\n" + v4 + "".join(f"f {a+1} {b+1} {c+1}\n" for a, b, c in F))
write("obj", "corners.obj", "o t\nmtllib m.mtl\n" + v4 + "vt 0 0\nvn 0 0 1\ng g\ns off\n"
      "f 1/1 3/1 2/1\nf 1//1 2//1 4//1\nf -4/1/1 -1/1/1 -2/1/1\nf 2 3 4 1\n")

stl_ascii = "solid t\n" + "".join(
    "facet normal 0 0 1\n outer loop\n" + "".join(f"  vertex {' '.join(map(num, P[i]))}\n" for i in f)
    + " endloop\nendfacet\n" for f in F) + "endsolid t\n"
write("stl", "ascii.stl", stl_ascii)
binary = b"solid binary header".ljust(80, b" ") + struct.pack("<I", 2)
for f in F[:2]:
    binary += struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *P[i]) for i in f)
    binary += struct.pack("<H", 0)
write("stl", "binary.stl", binary)


def ply_header(fmt, extra=""):
    return (f"ply\nformat {fmt} 1.0\ncomment seed\nelement vertex 4\nproperty float x\n"
            f"property float y\nproperty double z\n{extra}element face 4\n"
            "property list uchar int vertex_indices\nend_header\n")


write("ply", "ascii.ply", ply_header("ascii") + "".join(" ".join(map(num, p)) + "\n" for p in P[:4])
      + "".join(f"3 {a} {b} {c}\n" for a, b, c in F))
for order, fmt in (("<", "binary_little_endian"), (">", "binary_big_endian")):
    body = b"".join(struct.pack(order + "ffdh", *p, 7) for p in P[:4])
    body += b"".join(struct.pack(order + "B3i", 3, *f) for f in F)
    body += struct.pack(order + "BH", 1, 9)  # the extra element: a list of one ushort
    header = ply_header(fmt, "property short flag\n").replace(
        "end_header\n", "element extra 1\nproperty list uchar ushort values\nend_header\n")
    write("ply", f"{fmt}.ply", header.encode() + body)

off_v = "".join(" ".join(map(num, p)) + "\n" for p in P[:4])
write("off", "tet.off", "OFF\n# comment\n4 4 6\n" + off_v + "".join(f"3 {a} {b} {c}\n" for a, b, c in F))
write("off", "coff.off", "COFF 4 2 0\n" + "".join(" ".join(map(num, p)) + " 255 0 0 255\n" for p in P[:4])
      + "4 0 1 2 3 1 0 0\n3 1 2 3\n")

# ---- tetrahedral meshes ----
g22 = ("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 7 \"body\"\n$EndPhysicalNames\n"
       "$Nodes\n5\n" + "".join(f"{i+1} {' '.join(map(num, p))}\n" for i, p in enumerate(P)) +
       "$EndNodes\n$Elements\n3\n1 2 2 7 1 1 2 3\n2 4 2 7 1 1 2 3 4\n3 4 2 8 1 2 3 4 5\n$EndElements\n")
write("gmsh", "ascii22.msh", g22)
write("gmsh", "ascii41.msh",
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 1\n1 0 0 0 1 1 1 0 0\n$EndEntities\n"
      "$Nodes\n1 5 1 5\n3 1 0 5\n1\n2\n3\n4\n5\n" + "".join(" ".join(map(num, p)) + "\n" for p in P) +
      "$EndNodes\n$Elements\n2 3 1 3\n2 1 2 1\n1 1 2 3\n3 1 4 2\n2 1 2 3 4\n3 2 3 4 5\n$EndElements\n")
b22 = b"$MeshFormat\n2.2 1 8\n" + struct.pack("<i", 1) + b"\n$EndMeshFormat\n$Nodes\n5\n"
b22 += b"".join(struct.pack("<i3d", i + 1, *p) for i, p in enumerate(P))
b22 += b"\n$EndNodes\n$Elements\n3\n" + struct.pack("<9i", 2, 1, 2, 1, 7, 1, 1, 2, 3)
b22 += struct.pack("<3i", 4, 2, 2) + b"".join(
    struct.pack("<7i", t + 2, 7 + t, 1, *(i + 1 for i in T[t])) for t in range(2))
write("gmsh", "binary22.msh", b22 + b"\n$EndElements\n")
b41 = b"$MeshFormat\n4.1 1 8\n" + struct.pack("<i", 1) + b"\n$EndMeshFormat\n$Nodes\n"
b41 += struct.pack("<4Q", 1, 5, 1, 5) + struct.pack("<3iQ", 3, 1, 0, 5)
b41 += struct.pack("<5Q", 1, 2, 3, 4, 5) + b"".join(struct.pack("<3d", *p) for p in P)
b41 += b"\n$EndNodes\n$Elements\n" + struct.pack("<4Q", 2, 3, 1, 3)
b41 += struct.pack("<3iQ", 2, 1, 2, 1) + struct.pack("<4Q", 1, 1, 2, 3)
b41 += struct.pack("<3iQ", 3, 1, 4, 2) + b"".join(
    struct.pack("<5Q", t + 2, *(i + 1 for i in T[t])) for t in range(2))
write("gmsh", "binary41.msh", b41 + b"\n$EndElements\n")

SEP = "\n--- ele ---\n"  # fuzz_tetgen.cpp splits an input here into the .node and .ele files
node0 = "# nodes\n5 3 0 0\n" + "".join(f"{i} {' '.join(map(num, p))}\n" for i, p in enumerate(P))
ele0 = "2 4 0\n" + "".join(f"{t} {' '.join(map(str, T[t]))}\n" for t in range(2))
write("tetgen", "zero_based", node0 + SEP + ele0)
node1 = "5 3 1 1\n" + "".join(f"{i+1} {' '.join(map(num, p))} 0.5 1\n" for i, p in enumerate(P))
ele1 = "2 10 1\n" + "".join(
    f"{t+1} {' '.join(str(i + 1) for i in T[t])} 1 2 3 4 5 1 {t}\n" for t in range(2))
write("tetgen", "one_based_10_node", node1 + SEP + ele1)

write("medit", "tets.mesh",
      "MeshVersionFormatted 1\nDimension 3\n# comment\nVertices\n5\n" +
      "".join(f"{' '.join(map(num, p))} 0\n" for p in P) +
      "Triangles\n1\n1 2 3 0\nEdges\n1\n1 2 0\nTetrahedra\n2\n1 2 3 4 7\n2 3 4 5 8\nEnd\n")

# ---- scenes ----
write("scene", "box.json", json.dumps({
    "geometry": {"box": {"size": [1, 0.3, 0.3]}}, "grid": {"resolution": 24},
    "material": {"poisson_ratio": 0.3},
    "constraints": [{"region": {"box": {"center": [-0.5, 0, 0], "size": [0.1, 1, 1]}}}],
    "solver": {"tolerance": 1e-5, "max_vcycles": 40, "cycle": "W"},
    "output": {"formats": ["vtk"], "surface": {"interpolation": "trilinear"}}}))
write("scene", "csg_keyframes.json", json.dumps({
    "engine": "tet",
    "geometry": {"difference": [
        {"union": [{"cylinder": {"a": [0, 0, 0], "b": [0, 1, 0], "radius": 0.5}},
                   {"torus": {"major_radius": 1, "minor_radius": 0.2}}]},
        {"capsule": {"a": [0, 0, 0], "b": [1, 0, 0], "radius": 0.1},
         "transform": {"translate": [0, 1, 0], "rotate_degrees": 30, "scale": 2}}]},
    "material": {"regions": [{"region": {"sphere": {"radius": 0.2}}, "youngs_modulus": 2e5}]},
    "constraints": [{"region": {"mesh": "part.obj"}, "motion": "keyframed", "pivot": [0, 1, 0],
                     "keyframes": [{"time": 0}, {"time": 1, "translate": [0, 0.1, 0],
                                                 "rotate_axis": [1, 0, 0], "rotate_degrees": 90}]}],
    "loads": {"gravity": [0, 0, -9.81],
              "tractions": [{"region": {"box": {"size": [1, 1, 1]}}, "traction": [1, 0, 0]}]},
    "time": {"dt": 0.01, "frames": 3, "substeps": 2, "quasistatic": False, "integrator": "newmark"},
    "tet": {"rotation": "smoothed_polar", "resolution": 8, "linear_solver": "cholesky"}}))
