"""The Python path computes what `mgelastic run` computes, bit for bit (same thread count)."""
import json
import pathlib
import subprocess

import numpy as np

import mgelastic


def read_obj_vertices(path):
    rows = [line.split()[1:4] for line in pathlib.Path(path).read_text().splitlines()
            if line.startswith("v ")]
    return np.array(rows, dtype=float)


def test_tip_deflection_matches_cli(tmp_path, cli, cantilever):
    scene_path = tmp_path / "cantilever.json"
    scene_path.write_text(json.dumps(cantilever))
    subprocess.run([cli, "run", str(scene_path), "--threads", "1", "--output", str(tmp_path / "out")],
                   check=True, capture_output=True)
    objs = sorted((tmp_path / "out").rglob("*.obj"))
    assert objs, "the CLI wrote no OBJ frame"
    cli_surface = read_obj_vertices(objs[-1])

    sim = mgelastic.Simulation(mgelastic.Scene.load(scene_path), threads=1)
    sim.run()
    vertices, triangles = sim.surface()
    assert vertices.shape == cli_surface.shape
    # OBJ keeps max_digits10: the text round trip is exact, so the two runs agree to round-off.
    np.testing.assert_allclose(vertices, cli_surface, rtol=0, atol=1e-15)
    tip_python = vertices[:, 1].min()
    tip_cli = cli_surface[:, 1].min()
    assert abs(tip_python - tip_cli) <= 1e-15
    assert -0.1 < tip_python + 0.05 < 0  # it sags (the bar's half height is 0.05 m)

    u = sim.displacement()
    nx, ny, nz = sim.cells
    assert u.shape == (nx + 1, ny + 1, nz + 1, 3)
    assert sim.von_mises().shape == (nx, ny, nz)
    assert sim.pressure().shape == (nx, ny, nz)
    assert triangles.dtype == np.int32 and triangles.max() < len(vertices)


def test_save_and_resume_continue_bit_for_bit(tmp_path, cantilever):
    cantilever["time"] = {"dt": 0.01, "frames": 4, "quasistatic": False}
    scene = mgelastic.Scene.from_dict(cantilever)
    straight = mgelastic.Simulation(scene, threads=1)
    straight.run()
    first = mgelastic.Simulation(scene, threads=1)
    first.run(2)
    first.save(tmp_path / "state.mgck")
    resumed = mgelastic.Simulation.resume(scene, tmp_path / "state.mgck", threads=1)
    assert resumed.frame == 2
    resumed.run()
    assert np.array_equal(resumed.displacement(), straight.displacement())
    assert np.array_equal(resumed.velocity(), straight.velocity())
