"""Long calls: the GIL is released (another thread runs meanwhile), progress reaches a Python
callback on the calling thread, a callback can cancel or raise, and Ctrl-C stops a call with
KeyboardInterrupt, leaving no partial output."""
import os
import signal
import threading
import time

import pytest

import hovox


@pytest.fixture(scope="module")
def stack_job():
    g = hovox.generate.gear()
    m = hovox.voxelize(g, dims=64)
    o = hovox.object(m, hovox.materials(["A", "B"]))
    o.add_ags(feature=hovox.axis(origin=(0, 0, 0), direction=(0, 0, 1)), d_neg=5, d_grad=20, d_pos=5, ms=(1, 0),
              me=(0, 1))
    return g, o.evaluate()


def test_gil_released_during_a_long_call(stack_job, tmp_path):
    mesh, model = stack_job
    done = threading.Event()
    ticks = []

    def other():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)
    t = threading.Thread(target=other)
    t.start()
    time.sleep(0.01)
    before = len(ticks)
    t0 = time.perf_counter()
    model.layers(mesh, tmp_path / "s", layers=(0, 40))
    t1 = time.perf_counter()
    during = [x for x in ticks[before:] if t0 < x < t1]
    done.set()
    t.join()
    # the other thread kept running through the call (with the GIL held it would not tick at all)
    assert t1 - t0 > 0.05
    assert len(during) >= 10, (len(during), t1 - t0)
    gaps = [b - a for a, b in zip(during, during[1:])]
    assert max(gaps) < 0.5 * (t1 - t0) + 0.05


def test_progress_callback(stack_job, tmp_path):
    mesh, model = stack_job
    seen = []
    me = threading.get_ident()

    def progress(stage, fraction):
        seen.append((stage, fraction, threading.get_ident()))
    model.layers(mesh, tmp_path / "s", layers=(0, 8), progress=progress)
    assert seen and all(t == me for _, _, t in seen)
    assert {s for s, _, _ in seen} >= {"layers"}
    assert seen[-1][1] == 1.0 and all(0 <= f <= 1 for _, f, _ in seen)
    seen.clear()
    hovox.voxelize(mesh, dims=48, progress=progress)
    assert seen


def test_progress_cancel_and_raise(stack_job, tmp_path):
    mesh, model = stack_job
    with pytest.raises(hovox.CancelledError):
        model.layers(mesh, tmp_path / "a", layers=(0, 40), progress=lambda s, f: f > 0.1)
    assert not (tmp_path / "a").exists()

    class Stop(Exception):
        pass

    def boom(stage, fraction):
        if fraction > 0:
            raise Stop(stage)
    with pytest.raises(Stop):
        model.layers(mesh, tmp_path / "b", layers=(0, 40), progress=boom)
    assert not (tmp_path / "b").exists()
    with pytest.raises(TypeError):
        model.layers(mesh, tmp_path / "c", progress=3)


def test_ctrl_c_during_a_call(stack_job, tmp_path):
    """SIGINT in the middle of a call (sent from its own progress callback, so deterministically
    while the call runs): the call stops with KeyboardInterrupt and writes nothing."""
    mesh, model = stack_job
    sent = []

    def interrupt(stage, fraction):
        if not sent and fraction > 0:
            sent.append(fraction)
            os.kill(os.getpid(), signal.SIGINT)
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        model.layers(mesh, tmp_path / "s", progress=interrupt)  # all 1,461 layers: about 20 s
    assert sent and time.perf_counter() - t0 < 10
    assert not (tmp_path / "s").exists() and os.listdir(tmp_path) == []
    # Python's handler is back: a later call runs normally
    assert model.layers(mesh, tmp_path / "t", layers=(0, 2))["last"] == 2


def test_ctrl_c_from_another_thread(stack_job, tmp_path):
    mesh, model = stack_job
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    t0 = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        model.layers(mesh, tmp_path / "s")
        time.sleep(5)  # (if the call ended first, the signal still comes)
    timer.join()
    assert time.perf_counter() - t0 < 10
    assert not (tmp_path / "s").exists()


def test_a_python_handler_sees_the_signal(stack_job, tmp_path):
    """The script's own SIGINT handler runs, as it would between calls."""
    mesh, model = stack_job
    got = []
    old = signal.signal(signal.SIGINT, lambda s, f: got.append(s))
    try:
        def interrupt(stage, fraction):
            if fraction > 0 and not got:
                os.kill(os.getpid(), signal.SIGINT)
        with pytest.raises(hovox.CancelledError):
            model.layers(mesh, tmp_path / "s", progress=interrupt)
        assert got == [signal.SIGINT]
    finally:
        signal.signal(signal.SIGINT, old)
