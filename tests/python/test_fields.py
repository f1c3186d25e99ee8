"""Fields are live, read-only numpy views; stats and stepping API."""
import numpy as np
import pytest

import mgelastic


def dynamic(cantilever, frames=3):
    cantilever["time"] = {"dt": 0.01, "frames": frames, "quasistatic": False}
    return mgelastic.Simulation(mgelastic.Scene.from_dict(cantilever), threads=1)


def test_view_sees_the_next_step(cantilever):
    sim = dynamic(cantilever)
    sim.step()
    u = sim.displacement()
    v = sim.velocity()
    before = u.copy()
    pointer = u.__array_interface__["data"][0]
    sim.step()
    assert not np.array_equal(u, before)  # the same array now shows frame 1
    assert np.array_equal(u, sim.displacement())
    assert sim.displacement().__array_interface__["data"][0] == pointer
    assert np.abs(v).max() > 0


def test_views_are_read_only(cantilever):
    sim = dynamic(cantilever)
    with pytest.raises(ValueError):
        sim.displacement()[0, 0, 0, 0] = 1.0


def test_view_outlives_the_simulation_object(cantilever):
    sim = dynamic(cantilever)
    sim.step()
    u = sim.displacement()
    expected = u.copy()
    del sim
    assert np.array_equal(u, expected)


def test_stats_and_clock(cantilever):
    sim = dynamic(cantilever, frames=4)
    assert sim.stats.frame == -1 and sim.frame == 0
    stats = sim.step()
    assert stats.frame == 0 and stats.steps == 1 and stats.cycles >= 1
    assert stats.time == pytest.approx(0.01)
    assert sim.stats.cycles == stats.cycles
    seen = []
    sim.run(callback=lambda s, st: seen.append(st.frame))
    assert seen == [1, 2, 3] and sim.frame == 4

    again = dynamic(cantilever, frames=4)
    again.advance_to(0.03)
    assert again.frame == 3
    again.run(callback=lambda s, st: False)  # stops after one frame
    assert again.frame == 4
