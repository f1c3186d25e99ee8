"""mgelastic.Scene: loading, dict round trip, schema errors as SceneError."""
import json

import pytest

import mgelastic
from conftest import SOURCE_DIR


def test_load_and_round_trip_through_dict():
    scene = mgelastic.Scene.load(SOURCE_DIR / "examples/scenes/skeleton_arm.json")
    document = scene.to_dict()
    again = mgelastic.Scene.from_dict(document, directory=scene.directory)
    assert again.to_dict() == document
    assert (again.engine, again.frames, again.dt, again.constraints) == ("grid", 72, scene.dt, 2)


def test_from_dict_fills_defaults(cantilever):
    document = mgelastic.Scene.from_dict(cantilever).to_dict()
    assert document["time"]["frames"] == 1
    assert document["material"]["poisson_ratio"] == 0.3


def test_error_hierarchy():
    assert issubclass(mgelastic.SceneError, mgelastic.Error)
    assert issubclass(mgelastic.SceneError, ValueError)
    assert issubclass(mgelastic.Error, RuntimeError)


def test_load_error_names_file_and_line(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text('{"engine": "grid",\n "geometry": }\n')
    with pytest.raises(mgelastic.SceneError, match=r"broken\.json:2"):
        mgelastic.Scene.load(path)


def test_json_pointer_in_dict_errors(cantilever):
    cantilever["material"]["poisson_ratio"] = 0.5
    with pytest.raises(mgelastic.SceneError, match="/material/poisson_ratio"):
        mgelastic.Scene.from_dict(cantilever)
