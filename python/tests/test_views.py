"""Particle arrays from Python against the engine's reallocation and re-sorting at every step: a kept
array stays correct, and a zero-copy view blocks stepping instead of reading stale or freed memory."""
import gc
import threading

import numpy as np
import pytest

import mesodpd
from conftest import SMALL


def test_an_array_kept_across_steps_keeps_the_state_it_was_read_at():
    sim = mesodpd.Simulation.from_string(SMALL)
    p = sim.particles
    x, ident = p.x, p.id
    before = sim.snapshot()
    sim.step(3)
    # Unchanged and inside the box (a view of the engine's re-sorted buffers held other fields' values).
    assert np.all((x >= 0) & (x < 6.0))
    order = np.argsort(ident)
    assert np.array_equal(ident[order], before["id"]) and np.array_equal(x[order], before["x"])
    # Reading again gives the new state.
    after = sim.snapshot()
    assert np.array_equal(p.x[np.argsort(p.id)], after["x"]) and not np.array_equal(after["x"], before["x"])


def test_arrays_are_read_only_copies_made_once_per_step():
    sim = mesodpd.Simulation.from_string(SMALL)
    p = sim.particles
    a = p.vx
    assert a.flags.owndata and not a.flags.writeable
    with pytest.raises(ValueError):
        a[0] = 1.0
    assert p.vx is a  # a second read in the same step shares the copy
    sim.step(1)
    assert p.vx is not a


def test_a_zero_copy_view_blocks_stepping_until_it_is_dropped():
    sim = mesodpd.Simulation.from_string(SMALL)
    v = sim.particles.view("x")
    assert not v.flags.owndata and not v.flags.writeable and np.array_equal(v, sim.particles.x)
    head = v[:10]  # a view of the view holds the memory too
    del v
    with pytest.raises(RuntimeError, match=r"view\('x'\) taken at step 0 is still referenced"):
        sim.step(1)
    with pytest.raises(RuntimeError, match="still referenced"):
        sim.run()
    assert sim.current_step == 0
    del head
    assert sim.step(2) and sim.current_step == 2
    # A copy of a view does not hold the engine's memory.
    kept = np.array(sim.particles.view("fx"))
    sim.step(1)
    assert kept.flags.owndata
    with pytest.raises(KeyError):
        sim.particles.view("nope")


def test_a_view_in_a_garbage_cycle_does_not_block():
    sim = mesodpd.Simulation.from_string(SMALL)
    cycle = {"view": sim.particles.view("y")}
    cycle["self"] = cycle
    del cycle
    sim.step(1)  # step() collects the cycle before it decides
    gc.collect()


def test_a_view_keeps_the_simulation_alive():
    sim = mesodpd.Simulation.from_string(SMALL)
    v = sim.particles.view("z")
    expected = np.array(v)
    del sim
    gc.collect()
    assert np.array_equal(v, expected)


def test_reading_from_another_thread_during_a_step_is_refused():
    spec = mesodpd.Spec.from_string(SMALL)
    spec["system"]["box"] = [12.0, 12.0, 12.0]
    sim = mesodpd.Simulation(spec)
    errors, done = [], threading.Event()

    def reader():
        while not done.is_set():
            try:
                sim.particles.view("x")
            except RuntimeError as e:
                errors.append(str(e))
                return

    t = threading.Thread(target=reader)
    t.start()
    try:
        for _ in range(200):
            if errors:
                break
            try:
                sim.step(1)
            except RuntimeError:
                pass  # the reader's view was alive at this step's start: refused, as it should be
    finally:
        done.set()
        t.join()
    assert errors and "advancing in another thread" in errors[0]
