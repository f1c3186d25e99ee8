"""`mgelastic run` on the grid engine: a bar, one end fixed, the other keyframed (pulled along x)
and a traction on its top, three quasistatic frames. Checks the .pvd series, the fields of the
.vti and .vtp files, that the OBJ/PLY surfaces read back through `mgelastic info` as closed,
oriented meshes, and that the pulled end's displacement follows the keyframes."""
import json, subprocess, sys
import xml.etree.ElementTree as E

import vtk_xml  # tests/app: reads binary and ASCII VTK files

cli = sys.argv[1]
scene = {
    "geometry": {"box": {"size": [1, 0.25, 0.25]}},
    "grid": {"resolution": 24},
    "material": {"poisson_ratio": 0.3, "youngs_modulus": 1e5},
    "constraints": [
        {"region": {"box": {"center": [-0.5, 0, 0], "size": [0.1, 1, 1]}}},
        {"region": {"box": {"center": [0.5, 0, 0], "size": [0.1, 1, 1]}}, "motion": "keyframed",
         "keyframes": [{"time": 0}, {"time": 0.3, "translate": [0.06, 0, 0]}]}],
    "loads": {"gravity": [0, 0, 0],
              "tractions": [{"region": {"box": {"center": [0, 0.125, 0], "size": [0.4, 0.05, 1]}},
                             "traction": [0, -200, 0]}]},
    "time": {"dt": 0.1, "frames": 3},
    "solver": {"tolerance": 1e-6, "max_vcycles": 60},
    "output": {"formats": ["vtk", "obj", "ply"], "surface": {"interpolation": "tricubic"}},
}
json.dump(scene, open("grid_run_scene.json", "w"))
out = subprocess.run([cli, "run", "grid_run_scene.json", "--output", "grid_run_out"], check=True,
                     capture_output=True, text=True).stdout
assert out.count("frames ") == 3 and "summary:" in out and "NOT converged" not in out, out

series = [(d.get("file"), d.get("part"), float(d.get("timestep"))) for d in
          E.parse("grid_run_out/simulation.pvd").getroot().iter("DataSet")]
expected = [(f"{s}_{k:04d}.{e}", p) for k in range(3)
            for s, e, p in (("grid", "vti", "0"), ("surface", "vtp", "1"))]
assert [(f, p) for f, p, _ in series] == expected, series
assert [t for _, _, t in series][::2] == [0.1, 0.2, 0.30000000000000004] or \
    abs(series[4][2] - 0.3) < 1e-12, series


def arrays(path):
    return vtk_xml.read(path)[1]


grid = arrays("grid_run_out/grid_0002.vti")
for name in ("displacement", "cell_type", "pressure", "von_mises"):
    assert name in grid, grid.keys()
assert max(grid["von_mises"]) > 0

# The keyframed end moved by 0.02, 0.04, 0.06 m at t = 0.1, 0.2, 0.3: the largest x displacement
# of the surface follows it.
for frame, target in enumerate((0.02, 0.04, 0.06)):
    surface = arrays(f"grid_run_out/surface_{frame:04d}.vtp")["displacement"]
    ux = max(surface[0::3])
    assert abs(ux - target) < 0.15 * target, (frame, ux, target)

# The traction pushes the top down: some surface point moves down noticeably.
surface = arrays("grid_run_out/surface_0002.vtp")["displacement"]
assert min(surface[1::3]) < -1e-4, min(surface[1::3])

for ext in ("obj", "ply"):
    info = subprocess.run([cli, "info", f"grid_run_out/surface_0002.{ext}"], check=True,
                          capture_output=True, text=True).stdout
    assert "closed         yes" in info and "oriented       yes" in info, info
    volume = float(info.split("volume")[-1].split()[0])
    assert 0.06 < volume < 0.068, volume  # 1 x 0.25 x 0.25, slightly stretched
print("ok")
