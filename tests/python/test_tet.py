"""The tet engine through the module: per-vertex and per-tet fields, a bone driven from Python."""
import numpy as np
import pytest

import mgelastic
from conftest import SOURCE_DIR


@pytest.fixture(scope="module")
def twisted_bar():
    document = mgelastic.Scene.load(SOURCE_DIR / "examples/scenes/tet_twisted_bar.json").to_dict()
    document["tet"]["resolution"] = 6
    document["time"]["frames"] = 3
    return mgelastic.Scene.from_dict(document)


def test_tet_fields(twisted_bar):
    sim = mgelastic.Simulation(twisted_bar, threads=1)
    assert sim.engine == "tet"
    positions = sim.positions()
    rest = positions.copy()
    u = sim.displacement()
    sim.run()
    assert positions.shape == u.shape and positions.shape[1] == 3
    np.testing.assert_allclose(u, positions - rest, atol=1e-12)
    assert np.abs(sim.velocity()).max() > 0
    assert sim.von_mises().ndim == 1 and (sim.von_mises() >= 0).all()
    vertices, triangles = sim.surface()
    assert vertices.shape[1] == 3 and triangles.max() < len(vertices)
    with pytest.raises(mgelastic.Error, match="no pressure"):
        sim.pressure()


def test_tet_region_pose_from_python(twisted_bar):
    sim = mgelastic.Simulation(twisted_bar, threads=1)
    sim.set_region_pose(1, translate=(0.1, 0, 0), rotate=(1, 0, 0, 0))
    sim.step()
    x = sim.positions()
    end = x[:, 0] > x[:, 0].max() - 0.02
    assert x[end, 0].min() > 0.55  # the driven end moved +0.1 m from x = 0.5
