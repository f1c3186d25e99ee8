"""Checkpoint/resume of `mgelastic run` (docs/reliability.md, "Checkpoints and resume").

  check_resume.py CLI TET_EXAMPLE grid|grid_dynamic|grid_corotated|grid_corotated_dynamic|tet
      a run killed with SIGKILL after some frames, then
      resumed with --resume, leaves every output file byte-identical to an uninterrupted run
      (same thread count), the checkpoint included;
  check_resume.py CLI TET_EXAMPLE refusals   damaged, foreign-version, other-scene, other-thread
      and missing checkpoints are refused with exit code 2 and a message naming the file and the
      reason, and the output directory is left byte for byte as it was."""
import filecmp, hashlib, json, os, shutil, signal, subprocess, sys, time

cli, example, mode = sys.argv[1], sys.argv[2], sys.argv[3]
THREADS = ["--threads", "2"]


def grid_scene():
    return {
        "geometry": {"box": {"size": [1, 0.25, 0.25]}},
        "grid": {"resolution": 20},
        "material": {"poisson_ratio": 0.3, "youngs_modulus": 1e5},
        "constraints": [
            {"region": {"box": {"center": [-0.5, 0, 0], "size": [0.1, 1, 1]}}},
            {"region": {"box": {"center": [0.5, 0, 0], "size": [0.1, 1, 1]}},
             "motion": "keyframed", "pivot": [0.5, 0, 0],
             "keyframes": [{"time": 0},
                           {"time": 2.4, "translate": [0.1, 0.05, 0], "rotate_axis": [1, 0, 0],
                            "rotate_degrees": 60}]}],
        "loads": {"gravity": [0, -9.81, 0]},
        "time": {"dt": 0.1, "frames": 24},
        "solver": {"tolerance": 1e-7, "max_vcycles": 60},
        "output": {"formats": ["vtk", "obj"], "checkpoint_every": 3},
    }


def tet_scene():
    scene = json.load(open(example))
    scene["time"].update({"frames": 24, "integrator": "newmark"})  # carries accelerations too
    scene["tet"]["resolution"] = 15  # 810 tets: the element loops run in parallel
    scene["output"] = {"formats": ["vtk", "ply"], "checkpoint_every": 3}
    return scene


def run(scene_file, out, *extra):
    return subprocess.run([cli, "run", scene_file, "--output", out, *THREADS, *extra],
                          capture_output=True, text=True)


def frame_files(out):
    return sorted(f for f in os.listdir(out) if f[-4:] in (".vti", ".vtu", ".vtp", ".obj", ".ply"))


def check_resume(name, scene):
    scene_file = f"resume_{name}.json"
    json.dump(scene, open(scene_file, "w"))
    reference, killed = f"resume_{name}_reference", f"resume_{name}_killed"
    for d in (reference, killed):
        shutil.rmtree(d, ignore_errors=True)
    done = run(scene_file, reference)
    assert done.returncode == 0, done.stderr
    # The same run, killed hard (no handler runs) once a checkpoint and some frames after it exist.
    proc = subprocess.Popen([cli, "run", scene_file, "--output", killed, *THREADS],
                            stdout=subprocess.DEVNULL)
    checkpoint = os.path.join(killed, "checkpoint.mgck")
    deadline = time.time() + 300
    while time.time() < deadline and proc.poll() is None:
        if os.path.exists(checkpoint) and os.path.exists(os.path.join(killed, "simulation.pvd")) \
                and len(frame_files(killed)) >= 2 * 5:
            break
        time.sleep(0.01)
    assert proc.poll() is None, "the run finished before it could be killed; use more frames"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    written = len(frame_files(killed))
    total = len(frame_files(reference))
    assert 0 < written < total, (written, total)
    resumed = run(scene_file, killed, "--resume")
    assert resumed.returncode == 0, resumed.stderr
    assert "resumed from" in resumed.stdout, resumed.stdout[:500]
    first = resumed.stdout.split("resumed from", 1)[1].split("frame ", 1)[1].split()[0]
    # Byte-identical: every frame file, the series and the final checkpoint.
    names = sorted(os.listdir(reference))
    assert sorted(os.listdir(killed)) == names, set(os.listdir(killed)) ^ set(names)
    different = [f for f in names if not filecmp.cmp(os.path.join(reference, f),
                                                     os.path.join(killed, f), shallow=False)]
    assert not different, different
    print(f"ok {name}: killed after {written // 2} frame(s) on disk, resumed after frame "
          f"{first}, {len(names)} files byte-identical to the uninterrupted run")


def digest(directory):
    return {f: hashlib.sha256(open(os.path.join(directory, f), "rb").read()).hexdigest()
            for f in sorted(os.listdir(directory))}


def expect_refused(scene_file, out, reason, *extra):
    before = digest(out)
    result = run(scene_file, out, "--resume", *extra)
    message = result.stderr
    assert result.returncode == 2, (result.returncode, message)
    assert "checkpoint.mgck" in message and reason in message, message
    assert digest(out) == before, "a refused resume changed the output directory"
    print("refused:", message.strip())


def check_refusals():
    scene = grid_scene()
    scene["time"]["frames"] = 4
    scene["output"]["checkpoint_every"] = 2
    json.dump(scene, open("refuse.json", "w"))
    shutil.rmtree("refuse_out", ignore_errors=True)
    assert run("refuse.json", "refuse_out").returncode == 0
    good = open("refuse_out/checkpoint.mgck", "rb").read()

    def damaged(data, reason, *extra, scene_file="refuse.json"):
        open("refuse_out/checkpoint.mgck", "wb").write(data)
        expect_refused(scene_file, "refuse_out", reason, *extra)

    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x04
    damaged(bytes(flipped), "checksum mismatch")
    damaged(good[: len(good) - 100], "truncated")
    damaged(good[:10], "truncated")
    version = bytearray(good)
    version[8] = 99
    damaged(bytes(version), "format version 99 is not supported")
    damaged(b"garbage, not a checkpoint", "not a mgelastic checkpoint")
    other = grid_scene()
    other["time"]["frames"] = 4
    other["material"]["youngs_modulus"] = 2e5
    json.dump(other, open("refuse_other.json", "w"))
    damaged(good, "belongs to a different scene", scene_file="refuse_other.json")
    tet = tet_scene()
    json.dump(tet, open("refuse_tet.json", "w"))
    damaged(good, "written by the grid engine", scene_file="refuse_tet.json")
    open("refuse_out/checkpoint.mgck", "wb").write(good)
    before = digest("refuse_out")
    threads = subprocess.run([cli, "run", "refuse.json", "--output", "refuse_out", "--resume",
                              "--threads", "1"], capture_output=True, text=True)
    assert threads.returncode == 2 and "written with 2 threads" in threads.stderr, threads.stderr
    assert digest("refuse_out") == before
    shutil.rmtree("refuse_empty", ignore_errors=True)
    os.makedirs("refuse_empty")
    expect_refused("refuse.json", "refuse_empty", "no checkpoint here")
    # A finished run resumed with more frames continues (time.frames is not part of the scene's
    # fingerprint), and the untouched checkpoint is still accepted.
    scene["time"]["frames"] = 5
    json.dump(scene, open("refuse.json", "w"))
    more = run("refuse.json", "refuse_out", "--resume")
    assert more.returncode == 0 and "resumed from" in more.stdout, more.stderr
    assert os.path.exists("refuse_out/grid_0004.vti")
    print("ok refusals")


def grid_dynamic_scene():
    scene = grid_scene()  # backward Euler: the face velocities are carried between frames too
    scene["time"].update({"quasistatic": False, "dt": 1 / 30, "substeps": 2})
    scene["time"]["frames"] = 24
    return scene


def corotated(scene):
    # Frozen rotations lag the displacement by up to k = 5 cycles across frames, and backward-Euler
    # steps recycle Newton corrections: both are carried by the checkpoint.
    scene["material"]["model"] = "corotated"
    return scene


def corotated_static():
    # Without the keyframed 60-degree turn: quasistatic co-rotated frames of it take hundreds of
    # load-stepped cycles (docs/grid-engine.md); a translated, sagging bar takes ~30 per frame.
    scene = corotated(grid_scene())
    del scene["constraints"][1]["keyframes"][1]["rotate_axis"]
    del scene["constraints"][1]["keyframes"][1]["rotate_degrees"]
    scene["time"]["frames"] = 12
    scene["solver"] = {"tolerance": 1e-6, "max_vcycles": 40}
    return scene


if mode == "grid":
    check_resume("grid", grid_scene())
elif mode == "grid_corotated":
    check_resume("grid_corotated", corotated_static())
elif mode == "grid_corotated_dynamic":
    check_resume("grid_corotated_dynamic", corotated(grid_dynamic_scene()))
elif mode == "grid_dynamic":
    check_resume("grid_dynamic", grid_dynamic_scene())
elif mode == "tet":
    check_resume("tet", tet_scene())
else:
    check_refusals()
