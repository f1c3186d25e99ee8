"""Ctrl-C (SIGINT) during a run raises KeyboardInterrupt between frames; the simulation stays
usable."""
import os
import signal
import threading

import numpy as np
import pytest

import mgelastic


def test_sigint_interrupts_run_between_frames(cantilever):
    cantilever["time"] = {"dt": 0.01, "frames": 100000, "quasistatic": False}
    sim = mgelastic.Simulation(mgelastic.Scene.from_dict(cantilever), threads=1)
    started = threading.Event()
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))

    def on_frame(s, stats):
        if not started.is_set():
            started.set()
            timer.start()

    with pytest.raises(KeyboardInterrupt):
        sim.run(callback=on_frame)
    timer.join()
    done = sim.frame
    assert 0 < done < 100000
    assert sim.stats.frame == done - 1
    stats = sim.step()  # still usable: continues from the last completed frame
    assert stats.frame == done
    assert np.isfinite(sim.displacement()).all()
