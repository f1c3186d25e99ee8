"""Ctrl-C (SIGINT) raises KeyboardInterrupt: during a run, and inside one long step, where it
stops the solve between multigrid cycles and leaves the simulation at the last completed frame;
the simulation stays usable."""
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


# A frame of exactly 6000 cycles (~1 s here, the interrupt comes at 0.3 s): 2000 backward-Euler
# steps of 3 cycles each (fixed cycle counts run every cycle; an unreachable tolerance would stop
# at the round-off floor).
LONG_FRAME = {"dt": 0.1, "frames": 3, "quasistatic": False, "substeps": 2000, "vcycles_per_step": 3}


def test_sigint_interrupts_a_step_between_cycles(cantilever):
    cantilever["time"] = dict(LONG_FRAME)
    sim = mgelastic.Simulation(mgelastic.Scene.from_dict(cantilever), threads=1)
    before = sim.displacement().copy()
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.step()
    timer.join()
    # Stopped inside frame 0: no frame completed, the fields are still the rest state.
    assert sim.frame == 0
    assert sim.stats.frame == -1
    np.testing.assert_array_equal(sim.displacement(), before)
    # Python's handler is back: a SIGINT between steps raises KeyboardInterrupt as before.
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    # Uninterrupted, the same step runs all its cycles: the interrupt came before its end.
    stats = sim.step()
    assert stats.frame == 0 and sim.frame == 1
    assert stats.cycles == 6000
    assert np.isfinite(sim.displacement()).all()


def test_a_handler_of_the_user_runs_instead(cantilever):
    cantilever["time"] = dict(LONG_FRAME)
    sim = mgelastic.Simulation(mgelastic.Scene.from_dict(cantilever), threads=1)

    class Stop(Exception):
        pass

    def handler(signum, frame):
        raise Stop()

    previous = signal.signal(signal.SIGINT, handler)
    try:
        timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
        timer.start()
        with pytest.raises(Stop):
            sim.step()
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert sim.frame == 0
