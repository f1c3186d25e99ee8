"""SIGINT during `mgelastic run`: the run finishes the frame in progress, exits with 130, every
frame listed in simulation.pvd is complete (parses, has its fields), and checkpoint.mgck holds
the last of them."""
import json, os, shutil, signal, subprocess, sys, time
import xml.etree.ElementTree as E

import vtk_xml  # tests/app: reads binary and ASCII VTK files

cli, example = sys.argv[1], sys.argv[2]
scene = json.load(open(example))
scene["time"]["frames"] = 400  # far more than the run will reach before the signal
scene["output"]["formats"] = ["vtk", "obj"]
json.dump(scene, open("interrupt_scene.json", "w"))
shutil.rmtree("interrupt_out", ignore_errors=True)
run = subprocess.Popen([cli, "run", "interrupt_scene.json", "--output", "interrupt_out"],
                       stdout=subprocess.PIPE, text=True)
deadline = time.time() + 120
while not os.path.exists("interrupt_out/simulation.pvd") and time.time() < deadline:
    time.sleep(0.05)
run.send_signal(signal.SIGINT)
out, _ = run.communicate(timeout=120)
assert run.returncode == 130, (run.returncode, out[-500:])
assert "interrupted: stopped after frame" in out, out[-500:]
frames = [d.get("file") for d in E.parse("interrupt_out/simulation.pvd").getroot().iter("DataSet")]
assert 0 < len(frames) < 2 * 400, len(frames)
for name in frames:
    assert "displacement" in vtk_xml.read(os.path.join("interrupt_out", name))[1], name
assert not [f for f in os.listdir("interrupt_out") if f.endswith(".tmp")]
# The interrupted run left a checkpoint of its last frame for `run --resume`; payload after the
# 28-byte header: u32 engine length, engine, u64 fingerprint, i32 threads, i32 frame.
data = open("interrupt_out/checkpoint.mgck", "rb").read()
n = int.from_bytes(data[28:32], "little")
assert data[:8] == b"MGECKPT\0" and data[32:32 + n] == b"tet", data[:40]
assert int.from_bytes(data[32 + n + 12:32 + n + 16], "little") == len(frames) // 2 - 1
print("ok", len(frames) // 2, "frames")
