"""A design study of four-bar link lengths and counterweight budgets (static balancing at 90 samples, Latin
hypercube) on the local worker pool with 1 and 2 workers and on a 2-worker Dask LocalCluster, through the
endpoint's batched path (a task's variants stacked into one analysis, one map evaluation and one re-analysis)
and, as the baseline in the same run, through the per-variant function: variants per second, parallel efficiency
from 1 to 2 workers, the Dask cluster's wall time over the 2-worker pool's (goal: at most 1.1), and the
overhead per task against the bare functions timed in this process. Rows go to a SQLite store as in the service.

The overhead is shown two ways: all of it against the bare function's mean over a sample of the variants (this
carries the sample's noise, and the slowdown of workers that share their cores with other work), and the time
outside the tasks (dispatch, transfer, SQLite, polling), which is the runner's own cost. The machine's own
efficiency from 1 to 2 processes (a pure-Python loop alone, then twice at once), printed at the start and the
end, says how much of the second core the machine gave while the study ran.

``python -m bench.studies [variants]`` (default 10 000; the per-variant baseline runs a fifth of them, at least
1 000).
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from functools import partial
from pathlib import Path
from typing import Any

import synth
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from api.execution.plans import Limits
from store import SqlStudyStore, Store, database_url
from api.studies.tasks import batch_function, variant_function
from synth.execution import DaskExecutor, Executor, LocalPoolExecutor, limit_threads
from synth.studies import BatchFn, BatchSpec, run_batch, variant_request

ENDPOINT = "/v1/balancing/static"
LIMITS = Limits(max_samples=20_000, max_stages=6, solver_time_limit_s=20.0)
GOAL_EFFICIENCY = 0.90
GOAL_RATE = 1_500.0   # variants/s on 2 workers
GOAL_DASK = 1.1       # the study's wall time on a 2-worker Dask LocalCluster over the 2-worker local pool


def study_spec(variants: int) -> dict[str, Any]:
    """Link lengths within a frame of 0.30 m and a counterweight budget, drawn as a Latin hypercube."""
    return {
        "endpoint": ENDPOINT,
        "base": {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 90,
                 "max_radius_m": {"crank": 0.1, "rocker": 0.25}},
        "parameters": [{"path": "mechanism.crank_length_m", "range": [0.05, 0.12]},
                       {"path": "mechanism.coupler_length_m", "range": [0.30, 0.40]},
                       {"path": "mechanism.rocker_length_m", "range": [0.20, 0.30]},
                       {"path": "mass_budget_kg", "range": [2.0, 6.0]}],
        "sampling": "lhs", "samples": variants, "seed": 1,
        "metrics": ["summary_after.rms_shaking_force_N", "summary_after.rms_driving_torque_Nm",
                    "total_added_mass_kg"],
        "objectives": {"summary_after.rms_driving_torque_Nm": "min", "total_added_mass_kg": "min"},
    }


def bare_seconds(study: synth.Study, count: int) -> float:
    """Mean time of the variant function called directly in this process over the first ``count`` variants,
    failing ones included as in the study [s]."""
    fn = variant_function(ENDPOINT, LIMITS)
    sampler = synth.Sampler(study)
    fn(variant_request(study.base, study.parameter_paths, sampler.values(0)))   # imports and first builds
    times = []
    for i in range(count):
        request = variant_request(study.base, study.parameter_paths, sampler.values(i))
        t0 = time.perf_counter()
        try:
            fn(request)
        except synth.SynthError:
            pass
        times.append(time.perf_counter() - t0)
    return statistics.fmean(times)


def _spin(_: int) -> float:
    """Seconds of a fixed pure-Python loop: CPU work that shares nothing with other processes."""
    t0 = time.perf_counter()
    total = 0
    for i in range(5_000_000):
        total += i
    return time.perf_counter() - t0


def machine_scaling() -> float:
    """The machine's own parallel efficiency from 1 to 2 processes right now: the same loop alone, then in two
    processes at once (cores shared with other work show here first) [-]."""
    import multiprocessing

    with multiprocessing.get_context("spawn").Pool(2) as pool:
        pool.map(_spin, [0, 0])                       # both started
        alone = min(pool.map(_spin, [0])[0] for _ in range(2))
        both = max(pool.map(_spin, [0, 1]))
    return alone / both


def bare_batched_seconds(study: synth.Study, count: int) -> float:
    """Mean time per variant of the batched function called directly in this process on the first ``count``
    variants in one call [s]."""
    fn = batch_function(ENDPOINT, LIMITS)
    assert fn is not None
    sampler = synth.Sampler(study)
    requests = [variant_request(study.base, study.parameter_paths, sampler.values(i)) for i in range(count)]
    fn(requests[:8])   # imports and first builds
    t0 = time.perf_counter()
    fn(requests)
    return (time.perf_counter() - t0) / count


def timed_run(study: synth.Study, executor: Executor, db: Path, batch_fn: BatchFn | None
              ) -> tuple[float, synth.RunReport]:
    """Wall time of the whole study on ``executor`` with rows written to a fresh store [s]."""
    store = SqlStudyStore(Store(database_url(None, str(db))))
    study_id = store.create({"bench": True}, study.variant_count)
    store.claim(study_id)
    # Workers started and warm (engine and web schemas imported, solvers loaded, the batched path run once)
    # before the clock, as in a service that has answered requests.
    spec = BatchSpec(variant_function(ENDPOINT, LIMITS), dict(study.base), study.parameter_paths, study.metrics,
                     study.constraints, batch_fn)
    sampler = synth.Sampler(study)
    warm = [[(i, sampler.values(i)) for i in range(k, k + 8)] for k in range(0, 24 * executor.workers, 8)]
    for future in [executor.submit(run_batch, spec, items) for items in warm]:
        future.result()
    t0 = time.perf_counter()
    report = synth.run_study(study, variant_function(ENDPOINT, LIMITS), executor,
                             partial(store.write_rows, study_id), batch_fn=batch_fn)
    wall = time.perf_counter() - t0
    assert store.get(study_id).done == study.variant_count  # type: ignore[union-attr]
    return wall, report


def _runs(label: str, study: synth.Study, batch_fn: BatchFn | None, bare: float, tmp: Path) -> dict[str, float]:
    """The study on the pool with 1 and 2 workers and on a 2-worker Dask cluster; variants/s of each."""
    variants = study.variant_count
    rates: dict[str, float] = {}
    walls: dict[int, float] = {}
    for workers in (1, 2):
        pool = LocalPoolExecutor(workers)
        try:
            wall, report = timed_run(study, pool, tmp / f"{label}-pool{workers}.sqlite", batch_fn)
        finally:
            pool.shutdown()
        walls[workers] = wall
        rates[f"pool{workers}"] = variants / wall
        print(f"{label}, local pool, {workers} worker(s): {wall:.2f} s, {variants / wall:.0f} variants/s, "
              f"{report.tasks} tasks of median {report.task_s:.2f} s, {report.failed} failed variants")
        _overheads(wall, workers, variants, bare, report)
    rates["efficiency"] = walls[1] / (2 * walls[2])
    print(f"{label}, parallel efficiency 1 -> 2 workers: {rates['efficiency'] * 100:.0f} % "
          f"(goal >= {GOAL_EFFICIENCY * 100:.0f} %); load average now {os.getloadavg()[0]:.1f}")
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        dask = DaskExecutor(client=client)
        client.run(limit_threads)
        wall, report = timed_run(study, dask, tmp / f"{label}-dask.sqlite", batch_fn)
    rates["dask"] = variants / wall
    ratio = wall / walls[2]
    rates["dask_ratio"] = ratio
    print(f"{label}, Dask LocalCluster, 2 workers: {wall:.2f} s, {variants / wall:.0f} variants/s, "
          f"{report.tasks} tasks; ratio to the 2-worker local pool: {ratio:.2f} (goal <= {GOAL_DASK:g}: "
          f"{'met' if ratio <= GOAL_DASK else 'not met'}); load average now {os.getloadavg()[0]:.1f}")
    _overheads(wall, 2, variants, bare, report)
    return rates


def main(variants: int = 10_000) -> None:
    """Print the figures."""
    limit_threads()
    study = synth.study_from_dict(study_spec(variants))
    baseline = synth.study_from_dict(study_spec(min(variants, max(1_000, variants // 5))))
    sample = min(variants, 200)
    bare = bare_seconds(study, sample)
    bare_batched = bare_batched_seconds(study, sample)
    print(f"study: {variants} variants of {ENDPOINT} at 90 samples (LHS over 3 link lengths and the budget); "
          f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at the start; the machine's own "
          f"efficiency 1 -> 2 processes (a pure-Python loop) {machine_scaling() * 100:.0f} %")
    print(f"bare per-variant function in this process: mean {bare * 1e3:.2f} ms over {sample} variants")
    print(f"bare batched function in this process: {bare_batched * 1e3:.2f} ms per variant over the same {sample} "
          f"in one call ({bare / bare_batched:.1f}x)")
    with tempfile.TemporaryDirectory() as tmp:
        print(f"-- baseline: the per-variant function, {baseline.variant_count} variants")
        base = _runs("per-variant", baseline, None, bare, Path(tmp))
        print(f"-- the batched path, {variants} variants")
        batched = _runs("batched", study, batch_function(ENDPOINT, LIMITS), bare_batched, Path(tmp))
    rate = batched["pool2"]
    print(f"batched, 2 workers: {rate:.0f} variants/s (goal >= {GOAL_RATE:.0f} variants/s: "
          f"{'met' if rate >= GOAL_RATE else 'not met'}), {rate / base['pool2']:.1f}x the per-variant function's "
          f"{base['pool2']:.0f}; efficiency 1 -> 2 workers {batched['efficiency'] * 100:.0f} % "
          f"(goal >= {GOAL_EFFICIENCY * 100:.0f} %: "
          f"{'met' if batched['efficiency'] >= GOAL_EFFICIENCY else 'not met'}); "
          f"Dask {batched['dask']:.0f} variants/s, {batched['dask_ratio']:.2f}x the pool's time; load average now {os.getloadavg()[0]:.1f}, the machine's own "
          f"efficiency 1 -> 2 processes now {machine_scaling() * 100:.0f} %")


def _overheads(wall: float, workers: int, variants: int, bare: float, report: synth.RunReport) -> None:
    # Three views of the cost: all of it against the bare function; the part outside the tasks (dispatch, result
    # transfer, SQLite, polling), which the runner controls; and how busy it kept the workers.
    total = (wall * workers - variants * bare) / report.tasks
    dispatch = (wall * workers - report.busy_s) / report.tasks
    print(f"    overhead per task against the bare function {total * 1e3:.1f} ms "
          f"({total / max(report.task_s, 1e-9) * 100:.1f} % of a median task); outside the tasks "
          f"{dispatch * 1e3:.1f} ms; workers busy {report.busy_s / (wall * workers) * 100:.0f} % of the wall time, "
          f"{report.busy_s / variants * 1e3:.2f} ms per variant inside the tasks")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10_000)
