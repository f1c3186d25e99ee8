"""Bad inputs raise Python exceptions carrying the CLI's messages."""
import json
import subprocess

import pytest

import mgelastic


def test_message_is_what_the_cli_prints(tmp_path, cli, cantilever):
    cantilever["grid"]["resolution"] = -3
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(cantilever))
    result = subprocess.run([cli, "run", str(path), "--output", str(tmp_path / "out")],
                            capture_output=True, text=True)
    assert result.returncode != 0
    with pytest.raises(mgelastic.SceneError) as error:
        mgelastic.Scene.load(path)
    assert result.stderr.strip() == "error: " + str(error.value)
    assert "/grid/resolution" in str(error.value)


def test_unknown_key(cantilever):
    cantilever["material"]["youngs_modulos"] = 1e7
    with pytest.raises(mgelastic.SceneError, match="/material"):
        mgelastic.Scene.from_dict(cantilever)


def test_missing_file(tmp_path):
    with pytest.raises(mgelastic.SceneError, match="nothing.json"):
        mgelastic.Scene.load(tmp_path / "nothing.json")


def test_bad_region_index(cantilever):
    sim = mgelastic.Simulation(mgelastic.Scene.from_dict(cantilever), threads=1)
    with pytest.raises(mgelastic.Error, match="no constraint region 5"):
        sim.set_region_pose(5, (0, 0, 0))
    with pytest.raises(mgelastic.Error, match="rotation"):
        sim.set_region_pose(0, (0, 0, 0), [[2, 0, 0], [0, 1, 0], [0, 0, 1]])


def test_resume_from_a_missing_checkpoint(tmp_path, cantilever):
    with pytest.raises(mgelastic.Error):
        mgelastic.Simulation.resume(mgelastic.Scene.from_dict(cantilever),
                                    tmp_path / "none.mgck", threads=1)


def test_grid_has_no_positions_and_threads_must_be_valid(cantilever):
    scene = mgelastic.Scene.from_dict(cantilever)
    with pytest.raises(mgelastic.Error, match="threads"):
        mgelastic.Simulation(scene, threads=-1)
    with pytest.raises(mgelastic.Error, match="no mesh vertices"):
        mgelastic.Simulation(scene, threads=1).positions()
