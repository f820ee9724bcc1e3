"""The executors: the same task gives bit-identical results serially and on worker processes; a task past its
timeout, a crashed worker and an exhausted memory limit each fail only their own task, and the pool goes on."""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Iterator

import numpy as np
import pytest

import synth
from synth.execution import LocalPoolExecutor, SerialExecutor

FOURBAR = synth.FourBar(0.3, 0.1, 0.35, 0.25)


def _linkage() -> synth.Linkage:
    links = {"crank": synth.MassProps(2.0, (0.05, 0.0), 0.002), "coupler": synth.MassProps(3.0, (0.17, 0.01), 0.03),
             "rocker": synth.MassProps(2.5, (0.12, 0.0), 0.02)}
    return synth.Linkage(FOURBAR, links)


def _crash() -> None:
    os.kill(os.getpid(), signal.SIGKILL)


def _allocate(n_bytes: int) -> int:
    return int(np.ones(n_bytes // 8).sum())


@pytest.fixture(scope="module")
def pool() -> Iterator[LocalPoolExecutor]:
    executor = LocalPoolExecutor(1, memory_limit_mb=1024)
    yield executor
    executor.shutdown()


def test_pool_and_serial_give_bit_identical_balancing(pool: LocalPoolExecutor) -> None:
    args = (_linkage(), 10.0, synth.CounterweightSpec())
    serial = SerialExecutor()
    try:
        here = serial.submit(synth.balance_static, *args, samples=90).result()
    finally:
        serial.shutdown()
    there = pool.submit(synth.balance_static, *args, samples=90, timeout=60).result()
    assert [c.mass for c in here.counterweights] == [c.mass for c in there.counterweights]
    assert np.array_equal(here.analysis_after.kinetostatics.shaking_force,
                          there.analysis_after.kinetostatics.shaking_force)


def test_engine_errors_cross_the_process_boundary_with_their_data(pool: LocalPoolExecutor) -> None:
    # Crank 0.2 on a 0.3 frame with coupler 0.15 and rocker 0.1: |AQ| > 0.25 near 180 deg, so it cannot close there.
    future = pool.submit(synth.analyse, synth.Linkage(synth.FourBar(0.3, 0.2, 0.15, 0.1)), 1.0, samples=36)
    with pytest.raises(synth.NotAssemblable) as err:
        future.result(timeout=60)
    assert err.value.ranges_deg and err.value.extras()["failing_samples"] > 0


def test_a_task_past_its_timeout_is_stopped_and_the_pool_goes_on(pool: LocalPoolExecutor) -> None:
    start = time.monotonic()
    with pytest.raises(synth.SolverTimeout):
        pool.submit(time.sleep, 60, timeout=0.5).result(timeout=30)
    assert time.monotonic() - start < 10
    assert pool.submit(abs, -2.0, timeout=30).result() == 2.0


def test_a_crashed_worker_fails_only_its_task(pool: LocalPoolExecutor) -> None:
    with pytest.raises(synth.WorkerLost) as err:
        pool.submit(_crash, timeout=30).result(timeout=30)
    assert err.value.exit_code == -signal.SIGKILL
    assert pool.submit(abs, -3.0, timeout=30).result() == 3.0


def test_memory_exhaustion_is_a_typed_error(pool: LocalPoolExecutor) -> None:
    with pytest.raises(synth.TooLarge) as err:
        pool.submit(_allocate, 4 * 2**30, timeout=30).result(timeout=30)
    assert err.value.limit == 1024 * 2**20
    assert pool.submit(_allocate, 8 * 2**20, timeout=30).result() == 2**20


def test_cancelling_a_running_task_stops_its_worker(pool: LocalPoolExecutor) -> None:
    future = pool.submit(time.sleep, 60, timeout=120)
    time.sleep(1.0)
    assert future.cancel()
    start = time.monotonic()
    assert pool.submit(abs, -4.0, timeout=30).result() == 4.0
    assert time.monotonic() - start < 10


def test_an_answer_is_freed_as_soon_as_its_future_is_dropped(pool: LocalPoolExecutor) -> None:
    # A future linked to the pool's in a reference cycle would hold every answer (megabytes of JSON in the
    # service) until the cyclic garbage collector ran: a web process under load grew by hundreds of MB. With the
    # collector off, dropping the future and the answer must free the answer by reference counting alone.
    import gc
    import weakref

    gc.collect()
    gc.disable()
    try:
        future = pool.submit(np.ones, 1000)
        answer = future.result(timeout=30)
        ref = weakref.ref(answer)
        del future, answer
        # The pool's result thread keeps its last task until the next one arrives.
        pool.submit(int, 0).result(timeout=30)
        deadline = time.monotonic() + 5
        while ref() is not None and time.monotonic() < deadline:
            time.sleep(0.01)
        assert ref() is None
    finally:
        gc.enable()


def _heap_state() -> tuple[int, bool]:
    import gc

    return gc.get_freeze_count(), gc.isenabled()


def test_a_worker_exempts_what_it_keeps_for_life_after_its_first_task(pool: LocalPoolExecutor) -> None:
    # Past the first task the imports stay for the worker's life: they are frozen out of later full
    # collections, and the collector itself stays on for what the tasks make.
    pool.submit(int, 0).result(timeout=30)
    frozen, enabled = pool.submit(_heap_state).result(timeout=30)
    assert frozen > 1000 and enabled


def test_a_process_that_never_shuts_its_pool_down_still_exits(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """Workers ignore SIGTERM, and multiprocessing waits at exit for the children it terminated: without the
    pool's own exit hook this program never ends (measured: still running after 60 s)."""
    import subprocess
    import sys

    script = tmp_path / "forgets_the_pool.py"
    script.write_text("from synth.execution import LocalPoolExecutor\n"
                      "if __name__ == '__main__':\n"
                      "    pool = LocalPoolExecutor(2)\n"
                      "    print(pool.submit(sum, [1, 2]).result(timeout=60), flush=True)\n")
    started = time.monotonic()
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "3"
    assert time.monotonic() - started < 60.0


#: Set by :func:`_warm_up` in the worker that runs it: its process id and when it finished.
_WARMED: dict[str, float] = {}


def _warm_up() -> None:
    time.sleep(0.3)
    _WARMED.update(pid=os.getpid(), at=time.monotonic())


def _warmed_in_this_process() -> bool:
    return _WARMED.get("pid") == os.getpid()


def test_a_worker_warms_up_before_its_first_task_and_so_does_its_replacement() -> None:
    warm = LocalPoolExecutor(1, memory_limit_mb=1024, warm=_warm_up)
    try:
        assert warm.wait_warm(60)
        assert warm.status()["workers_warm"] == 1
        assert warm.submit(_warmed_in_this_process, timeout=30).result(timeout=30)
        # a worker that dies is replaced by one that warms before it takes the next task
        with pytest.raises(synth.WorkerLost):
            warm.submit(_crash, timeout=30).result(timeout=30)
        assert warm.submit(_warmed_in_this_process, timeout=30).result(timeout=60)
        assert warm.restarts == 1
    finally:
        warm.shutdown()


def _failing_warm_up() -> None:
    raise RuntimeError("a program that does not build")


def test_a_warm_up_that_fails_leaves_a_worker_that_works() -> None:
    broken = LocalPoolExecutor(1, memory_limit_mb=1024, warm=_failing_warm_up)
    try:
        assert broken.wait_warm(60)
        assert broken.submit(abs, -5.0, timeout=30).result(timeout=30) == 5.0
    finally:
        broken.shutdown()


def test_a_task_goes_to_the_worker_it_prefers_when_that_one_is_free_and_to_another_when_it_is_busy() -> None:
    # An optimisation's later stages prefer the worker that kept a member's analysis from an earlier one: an
    # idle preferred worker takes the task (the other, idle too, leaves it), a busy one loses it to a free one.
    two = LocalPoolExecutor(2, memory_limit_mb=1024)
    try:
        assert two.wait_warm(60)  # both workers up: a task preferring one still starting goes to the other
        names = ["synth-worker-0", "synth-worker-1"]
        ran = []
        for k in range(10):
            future = two.submit(os.getpid, timeout=30, prefer=names[k % 2])
            future.result(timeout=30)
            ran.append(future.worker)  # type: ignore[attr-defined]
        # a worker looks at its own process between two waits for a task (every quarter second): a task handed
        # out in that instant goes to the other, so one of ten may
        assert sum(w == names[k % 2] for k, w in enumerate(ran)) >= 9, ran
        busy = two.submit(time.sleep, 1.0, timeout=30, prefer=names[0])
        while busy.worker is None:  # type: ignore[attr-defined]
            time.sleep(0.01)
        stolen = two.submit(os.getpid, timeout=30, prefer=names[0])
        stolen.result(timeout=30)
        assert stolen.worker == names[1] and not busy.done()  # type: ignore[attr-defined]
        busy.result(timeout=30)
    finally:
        two.shutdown()
