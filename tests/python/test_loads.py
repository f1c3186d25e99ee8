"""Loads changed between steps (set_traction, set_pressure, set_force) act from the next step on;
bad indices and shapes raise mgelastic.Error naming the load."""
import numpy as np
import pytest

import mgelastic


@pytest.fixture
def tip_loaded(cantilever):
    """The cantilever without gravity, a total force on its free end (x = 1)."""
    cantilever["loads"] = {
        "gravity": [0, 0, 0],
        "forces": [{"region": {"box": {"center": [1, 0, 0], "size": [0.05, 0.2, 0.2]}},
                    "normal": [1, 0, 0], "force": [0, -10, 0]}],
    }
    cantilever["solver"]["tolerance"] = 1e-10
    cantilever["solver"]["max_vcycles"] = 200
    cantilever["time"] = {"dt": 0.1, "frames": 3}
    return cantilever


def test_set_force_changes_the_next_step(tip_loaded):
    sim = mgelastic.Simulation(mgelastic.Scene.from_dict(tip_loaded), threads=1)
    sim.step()
    once = sim.displacement().copy()
    assert np.abs(once).max() > 0  # the force bends the bar
    sim.set_force(0, [0, -30, 0])
    sim.step()
    # Linear model: three times the force, three times the displacement (solver tolerance 1e-10;
    # 1e-6 relative leaves room for the lattice's conditioning).
    np.testing.assert_allclose(sim.displacement(), 3 * once, rtol=0,
                               atol=1e-6 * np.abs(3 * once).max())
    assert sim.scene.to_dict()["loads"]["forces"][0]["force"] == [0, -10, 0]  # the document


def test_set_load_errors_name_the_load(tip_loaded):
    sim = mgelastic.Simulation(mgelastic.Scene.from_dict(tip_loaded), threads=1)
    with pytest.raises(mgelastic.Error, match="/loads/forces"):
        sim.set_force(1, [0, 1, 0])
    with pytest.raises(mgelastic.Error, match="/loads/tractions"):
        sim.set_traction(0, [0, 1, 0])
    with pytest.raises(mgelastic.Error, match="force"):
        sim.set_force(0, [0, 1])
    sim.step()  # nothing was changed by the refused calls
    assert sim.stats.converged
