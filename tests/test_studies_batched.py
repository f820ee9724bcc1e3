"""Studies through an endpoint's batched path: the rows of the per-variant function (the independent computation)
on serial, local-pool and Dask execution, and the per-variant function again when the batched path fails."""

from __future__ import annotations

from typing import Any

import pytest

import synth
from api.execution.plans import Limits
from api.studies.tasks import batch_function, run_endpoint_batch, variant_function
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from synth.execution import DaskExecutor, Executor, LocalPoolExecutor, SerialExecutor

ENDPOINT = "/v1/balancing/static"
LIMITS = Limits(max_samples=20_000, max_stages=6, solver_time_limit_s=20.0)
# 60 variants by Latin hypercube over three link lengths and the budget: answers, budgets below the least
# static-balance mass, four-bars that do not close near 0 deg.
SPEC: dict[str, Any] = {
    "endpoint": ENDPOINT,
    "base": {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 90,
             "max_radius_m": {"crank": 0.1, "rocker": 0.25}},
    "parameters": [{"path": "mechanism.crank_length_m", "range": [0.05, 0.14]},
                   {"path": "mechanism.coupler_length_m", "range": [0.30, 0.42]},
                   {"path": "mechanism.rocker_length_m", "range": [0.18, 0.30]},
                   {"path": "mass_budget_kg", "range": [2.0, 6.0]}],
    "sampling": "lhs", "samples": 60, "seed": 3,
    "metrics": ["summary_after.rms_shaking_force_N", "summary_after.rms_driving_torque_Nm", "total_added_mass_kg",
                "summary_before.max_bearing_force_N", "checks.residual_shaking_moment_Nm"],
    "constraints": [{"metric": "summary_after.rms_driving_torque_Nm", "max": 30.0}],
}


class _Counted:
    """The batch function, counting its calls and variants (in this process: serial execution only)."""

    def __init__(self, fn: Any) -> None:
        self.fn, self.calls, self.variants = fn, 0, 0

    def __call__(self, requests: list[dict[str, Any]]) -> Any:
        self.calls += 1
        self.variants += len(requests)
        return self.fn(requests)


def _run(executor: Executor, batch_fn: Any) -> tuple[list[synth.VariantRow], synth.RunReport]:
    rows: list[synth.VariantRow] = []
    report = synth.run_study(synth.study_from_dict(SPEC), variant_function(ENDPOINT, LIMITS), executor, rows.extend,
                             batch_fn=batch_fn)
    return sorted(rows, key=lambda r: r.index), report


def _serial(batch_fn: Any) -> list[synth.VariantRow]:
    executor = SerialExecutor()
    try:
        return _run(executor, batch_fn)[0]
    finally:
        executor.shutdown()


@pytest.fixture(scope="module")
def per_variant_rows() -> list[synth.VariantRow]:
    return _serial(None)


def _same(rows: list[synth.VariantRow], expected: list[synth.VariantRow]) -> None:
    """The same variants, problems and feasibility; metrics within 1e-9 relative, or 1e-9 of the variant's
    largest metric for figures at rounding noise (a balanced linkage's residual shaking moment is not noise,
    its residual force would be)."""
    assert [r.index for r in rows] == [r.index for r in expected]
    for got, want in zip(rows, expected, strict=True):
        assert (got.values, got.problem_type, got.detail, got.feasible) == (
            want.values, want.problem_type, want.detail, want.feasible), got.index
        if want.metrics is None:
            assert got.metrics is None
            continue
        assert got.metrics is not None
        scale = max(abs(m) for m in want.metrics if m is not None)
        assert got.metrics == pytest.approx(want.metrics, rel=1e-9, abs=1e-9 * scale), got.index


def test_serial_batched_rows_are_the_per_variant_rows(per_variant_rows: list[synth.VariantRow]) -> None:
    counted = _Counted(batch_function(ENDPOINT, LIMITS))
    rows = _serial(counted)
    _same(rows, per_variant_rows)
    kinds = {r.problem_type for r in per_variant_rows}
    assert {None, "infeasible", "not-assemblable"} <= kinds
    # Every task after the first (one variant, sized alone) went through the batched path.
    assert counted.calls >= 1 and counted.variants >= len(rows) - 8


def test_a_batched_path_that_fails_leaves_each_variant_to_the_variant_function(
        per_variant_rows: list[synth.VariantRow]) -> None:
    def broken(requests: list[dict[str, Any]]) -> list[Any]:
        raise RuntimeError("the batched path is broken")

    _same(_serial(broken), per_variant_rows)

    def short(requests: list[dict[str, Any]]) -> list[Any]:
        return run_endpoint_batch(ENDPOINT, LIMITS, requests)[:-1]

    _same(_serial(short), per_variant_rows)


def test_pool_and_dask_run_the_batched_path_to_the_same_rows(per_variant_rows: list[synth.VariantRow]) -> None:
    from distributed import Client, LocalCluster

    batch_fn = batch_function(ENDPOINT, LIMITS)
    pool = LocalPoolExecutor(2)
    try:
        rows, report = _run(pool, batch_fn)
    finally:
        pool.shutdown()
    _same(rows, per_variant_rows)
    assert report.tasks < len(rows)          # batches of several variants were sent to the workers
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster, \
            Client(cluster, set_as_default=False) as client:
        rows, report = _run(DaskExecutor(client=client), batch_fn)
    _same(rows, per_variant_rows)
    assert report.tasks < len(rows)
