"""A diverging solve stops `mgelastic run` cleanly (docs/reliability.md, "Divergence handling"):
exit code 2, a message with the residual history and the diagnosis, every frame before the
failing one complete (listed in the .pvd, parses, finite fields) and a checkpoint of the last
good frame.

  check_divergence.py CLI grid   float precision, plain V-cycles, and a keyframed region that is
      sane for three frames and then jumps 1e36 m (halfway to 2e36 m): the float right-hand side of the correction
      overflows and the V-cycle produces NaN; the replay names level 0 and the phase;
  check_divergence.py CLI tet    a tet bar whose keyframed end jumps 1e200 m in the fourth frame (dynamic):
      the step's forces overflow and the step solve stops."""
import json, math, os, shutil, subprocess, sys
import xml.etree.ElementTree as E

import vtk_xml  # tests/app: reads binary and ASCII VTK files

cli, mode = sys.argv[1], sys.argv[2]
keyframes = [{"time": 0}, {"time": 0.35, "translate": [0.02, 0, 0]},
             {"time": 0.45, "translate": [2e36 if mode == "grid" else 2e200, 0, 0]}]
scene = {
    "geometry": {"box": {"size": [1, 0.25, 0.25]}},
    "constraints": [
        {"region": {"box": {"center": [-0.5, 0, 0], "size": [0.1, 1, 1]}}},
        {"region": {"box": {"center": [0.5, 0, 0], "size": [0.1, 1, 1]}}, "motion": "keyframed",
         "keyframes": keyframes}],
    "time": {"dt": 0.1, "frames": 6},
    "output": {"formats": ["vtk"], "checkpoint_every": 100},
}
if mode == "grid":
    scene.update({"grid": {"resolution": 20},
                  "solver": {"precision": "float", "accelerate": False, "max_vcycles": 40}})
else:
    # Dynamic, three substeps per frame: in frame 3 the first substep (t = 0.333 s) is sane, the
    # second (t = 0.367 s) is not, so the message carries the good step's residual.
    scene.update({"engine": "tet", "tet": {"resolution": 8}})
    scene["time"].update({"quasistatic": False, "substeps": 3})
json.dump(scene, open(f"diverge_{mode}.json", "w"))
out = f"diverge_{mode}_out"
shutil.rmtree(out, ignore_errors=True)
result = subprocess.run([cli, "run", f"diverge_{mode}.json", "--output", out, "--threads", "2"],
                        capture_output=True, text=True)
message = result.stderr
print(message)
assert result.returncode == 2, (result.returncode, message, result.stdout[-1000:])
expected = ["the run stopped in frame 3 (t = 0.4 s)", "the files of frames 0-2 are complete",
            "checkpoint.mgck holds frame 2"]
if mode == "grid":
    expected += ["solver: V-cycle 1 diverged: the residual is not finite", "residual history: ",
                 "diagnosis (cycles replayed", "cycle 1, level 0 of ",
                 "cycle start (right-hand side of the correction)", "not finite"]
else:
    expected += ["tet solver: ", "non-finite", "after 1 good step(s) with relative residuals"]
missing = [m for m in expected if m not in message]
assert not missing, (missing, message)

series = [d.get("file") for d in E.parse(f"{out}/simulation.pvd").getroot().iter("DataSet")]
stem, ext = ("grid", "vti") if mode == "grid" else ("tet", "vtu")
assert series == [f"{s}_{k:04d}.{e}" for k in range(3) for s, e in ((stem, ext), ("surface", "vtp"))], series
for name in series:
    values = vtk_xml.read(os.path.join(out, name))[1]["displacement"]
    assert values and all(math.isfinite(v) for v in values), name
assert not os.path.exists(f"{out}/{stem}_0003.{ext}")
assert not [f for f in os.listdir(out) if f.endswith(".tmp")]
data = open(f"{out}/checkpoint.mgck", "rb").read()
assert data[:8] == b"MGECKPT\0"
# Payload: u32 engine length, engine, u64 fingerprint, i32 threads, i32 frame.
n = int.from_bytes(data[28:32], "little")
frame = int.from_bytes(data[32 + n + 12: 32 + n + 16], "little", signed=True)
assert frame == 2, frame
print("ok", mode)
