"""`mgelastic run` with grid-engine dynamics (Sec. 8): an unsupported box falls under gravity with
an initial sideways velocity, 3 frames of 2 backward-Euler substeps. A uniform motion is strain
free, so every surface point must follow backward Euler's free fall exactly:
u_y = g h^2 n (n + 1) / 2 after n steps of length h, u_x = v0 n h."""
import json, subprocess, sys
import xml.etree.ElementTree as E

import vtk_xml  # tests/app: reads binary and ASCII VTK files

cli = sys.argv[1]
dt, substeps, frames, g, v0 = 0.05, 2, 3, -9.81, 0.4
scene = {
    "geometry": {"box": {"size": [0.4, 0.2, 0.2]}},
    "grid": {"resolution": 16},
    "loads": {"gravity": [0, g, 0]},
    "time": {"quasistatic": False, "dt": dt, "frames": frames, "substeps": substeps,
             "vcycles_per_step": 0},
    "initial": {"velocity": [v0, 0, 0]},
    "solver": {"tolerance": 1e-9, "max_vcycles": 40, "precision": "double"},
    "output": {"formats": ["vtk"]},
}
json.dump(scene, open("grid_dynamic_scene.json", "w"))
out = subprocess.run([cli, "run", "grid_dynamic_scene.json", "--output", "grid_dynamic_out"],
                     check=True, capture_output=True, text=True).stdout
assert "backward Euler" in out and "summary:" in out and "6 steps" in out, out
series = [d.get("file") for d in E.parse("grid_dynamic_out/simulation.pvd").getroot().iter("DataSet")]
assert series == [f"{s}_{k:04d}.{e}" for k in range(frames)
                  for s, e in (("grid", "vti"), ("surface", "vtp"))], series
h = dt / substeps
for frame in range(frames):
    n = (frame + 1) * substeps
    u = vtk_xml.read(f"grid_dynamic_out/surface_{frame:04d}.vtp")[1]["displacement"]
    uy, ux = g * h * h * n * (n + 1) / 2, v0 * n * h
    assert max(abs(x - ux) for x in u[0::3]) < 1e-6, (frame, ux, min(u[0::3]), max(u[0::3]))
    assert max(abs(y - uy) for y in u[1::3]) < 1e-6, (frame, uy, min(u[1::3]), max(u[1::3]))
    assert max(abs(z) for z in u[2::3]) < 1e-6
print("ok")
