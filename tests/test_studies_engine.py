"""Design studies in the engine: paths, sampling, the size bound and the Pareto front against a brute force."""

from __future__ import annotations

import itertools
import time

import numpy as np
import pytest

import synth
from synth.studies import get_path, quantise, set_path, variant_request

BASE = {"mechanism": {"crank_length_m": 0.1, "links": {"crank": {"mass_kg": 1.0}}}, "sweep": [{"a": 1.0}]}


def test_dotted_paths_read_and_write_dicts_and_lists() -> None:
    data = {"a": {"b": [10.0, {"c": 3.0}]}}
    assert get_path(data, "a.b.1.c") == 3.0
    set_path(data, "a.b.0", 11.0)
    set_path(data, "a.new.deep", 1.0)          # missing dictionaries are made on the way
    assert data == {"a": {"b": [11.0, {"c": 3.0}], "new": {"deep": 1.0}}}
    with pytest.raises(synth.InvalidInput, match="has no 'x'") as err:
        get_path(data, "a.x")
    assert err.value.field == "a.x"
    with pytest.raises(synth.InvalidInput):
        set_path(data, "a.b.5", 1.0)           # past the end of a list
    with pytest.raises(synth.InvalidInput):
        get_path(data, "a..b")


def _study(**kw: object) -> synth.Study:
    spec = {"base": BASE, "parameters": [{"path": "mechanism.crank_length_m", "range": [0.05, 0.15], "count": 3},
                                         {"path": "mechanism.links.crank.mass_kg", "values": [1.0, 2.0]},
                                         {"path": "sweep.0.a", "values": [5, 6]}],
            "metrics": ["m"], **kw}
    return synth.study_from_dict(spec)


def test_grid_is_the_product_in_order_and_requests_carry_the_values() -> None:
    study = _study()
    sampler = synth.Sampler(study)
    expected = list(itertools.product(list(np.linspace(0.05, 0.15, 3)), [1.0, 2.0], [5, 6]))  # first slowest
    assert sampler.count == study.variant_count == 12
    assert [tuple(sampler.values(i)) for i in range(12)] == expected
    request = variant_request(study.base, study.parameter_paths, sampler.values(7))
    assert request["mechanism"]["crank_length_m"] == expected[7][0]
    assert request["sweep"][0]["a"] == expected[7][2]
    assert BASE["mechanism"]["crank_length_m"] == 0.1   # the base is never modified


def test_latin_hypercube_is_stratified_and_seeded() -> None:
    n = 40
    study = synth.study_from_dict({"base": BASE, "sampling": "lhs", "samples": n, "seed": 7, "metrics": ["m"],
                                   "parameters": [{"path": "mechanism.crank_length_m", "range": [0.05, 0.15]},
                                                  {"path": "sweep.0.a", "range": [-1.0, 1.0]}]})
    values = np.array([synth.Sampler(study).values(i) for i in range(n)])
    # A Latin hypercube puts exactly one sample in each of the n equal slices of every parameter's range.
    for column, (lo, hi) in zip(values.T, [(0.05, 0.15), (-1.0, 1.0)]):
        slices = np.floor((column - lo) / (hi - lo) * n).astype(int)
        assert sorted(slices) == list(range(n))
    again = np.array([synth.Sampler(study).values(i) for i in range(n)])
    assert np.array_equal(values, again)
    other = synth.study_from_dict({**study_spec(study), "seed": 8})
    assert not np.array_equal(values, np.array([synth.Sampler(other).values(i) for i in range(n)]))


def study_spec(study: synth.Study) -> dict[str, object]:
    return {"base": dict(study.base), "sampling": study.sampling, "samples": study.samples, "metrics": ["m"],
            "parameters": [{"path": p.path, "range": list(p.range or ())} for p in study.parameters]}


def test_random_values_stay_in_range_and_lists_are_drawn_from() -> None:
    study = synth.study_from_dict({"base": BASE, "sampling": "random", "samples": 200, "seed": 1, "metrics": ["m"],
                                   "parameters": [{"path": "mechanism.crank_length_m", "range": [0.05, 0.15]},
                                                  {"path": "sweep.0.a", "values": ["x", "y", "z"]},
                                                  {"path": "mechanism.links.crank.mass_kg", "range": [1, 9],
                                                   "integer": True}]})
    rows = [synth.Sampler(study).values(i) for i in range(200)]
    assert all(0.05 <= r[0] <= 0.15 for r in rows)
    assert {r[1] for r in rows} == {"x", "y", "z"}
    assert {r[2] for r in rows} <= set(range(1, 10)) and all(isinstance(r[2], int) for r in rows)


def test_size_is_bounded_before_anything_is_generated() -> None:
    study = synth.study_from_dict({"base": BASE, "metrics": ["m"], "parameters": [
        {"path": "mechanism.crank_length_m", "range": [0.05, 0.15], "count": 100_000},
        {"path": "sweep.0.a", "range": [0.0, 1.0], "count": 100_000}]})
    t0 = time.perf_counter()
    with pytest.raises(synth.TooLarge) as err:
        study.check_size(100_000)
    assert (err.value.limit, err.value.got) == (100_000, 10**10)
    assert time.perf_counter() - t0 < 1.0   # a generous bound: 10^10 variants were never built


@pytest.mark.parametrize("bad", [
    {"objectives": {"nope": "min"}},
    {"constraints": [{"metric": "nope", "max": 1.0}]},
    {"parameters": [{"path": "mechanism.crank_length_m", "range": [0.05, 0.15]}]},   # grid without a count
    {"sampling": "lhs"},                                                                  # no samples
    {"parameters": [{"path": "mechanism.crank_length_m.deeper", "values": [1.0]}]},    # into a number
])
def test_bad_studies_are_invalid_input(bad: dict[str, object]) -> None:
    spec = {"base": BASE, "metrics": ["m"],
            "parameters": [{"path": "mechanism.crank_length_m", "values": [0.1]}], **bad}
    with pytest.raises(synth.InvalidInput):
        synth.study_from_dict(spec)


def _brute_force_front(points: np.ndarray, senses: list[str]) -> np.ndarray:
    """Independent of the engine's sweep: test every pair for dominance."""
    cost = points * np.array([1.0 if s == "min" else -1.0 for s in senses])
    keep = np.ones(len(cost), dtype=bool)
    for i, p in enumerate(cost):
        for q in cost:
            if np.all(q <= p) and np.any(q < p):
                keep[i] = False
                break
    return keep


@pytest.mark.parametrize("seed,senses", [(0, ["min", "min"]), (1, ["min", "max"]), (2, ["max", "min", "min"])])
def test_pareto_front_equals_a_brute_force_dominance_filter(seed: int, senses: list[str]) -> None:
    rng = np.random.default_rng(seed)
    # Small integers make ties and duplicates, the cases a sweep gets wrong first.
    points = rng.integers(0, 12, size=(150, len(senses))).astype(float)
    mask = synth.pareto_mask(points, senses)
    assert np.array_equal(mask, _brute_force_front(points, senses))
    assert mask.any()


def test_pareto_compares_to_significant_digits_of_each_objective_when_asked() -> None:
    # Equal designs but for solver noise: a budget met to 1e-11 kg, residual forces of 1e-12 N next to 160 N.
    points = np.array([[98.8, 1.0000000000095], [152.0, 1.0000000000009], [160.0, 2.0],
                       [1e-12, 4.5], [3e-12, 4.0]])
    assert list(synth.pareto_mask(points, ["min", "min"], noise=0.0)) == [True, True, False, True, True]
    assert list(synth.pareto_mask(points, ["min", "min"])) == [True, False, False, False, True]
    # two digits of 98.9 N is 1 N: 98.8 and 98.9 N are then one force, and the lighter design beats the other
    coarse = np.array([[98.8, 1.0], [98.9, 0.5]])
    assert list(synth.pareto_mask(coarse, ["min", "min"], digits=2)) == [False, True]
    assert list(synth.pareto_mask(coarse, ["min", "min"])) == [True, True]
    # Nine digits of 160 N is a micronewton; nine digits of 4.5 kg is 10 micrograms.
    assert quantise(points, 9)[:, 0] == pytest.approx([98.8, 152.0, 160.0, 0.0, 0.0], abs=1e-15, rel=1e-15)
    assert quantise(points, 9)[:, 1] == pytest.approx([1.0, 1.0, 2.0, 4.5, 4.0], abs=0, rel=1e-15)


def test_tasks_shrink_toward_the_end_so_the_workers_finish_together() -> None:
    # Guided self-scheduling: the measured size while much is left, a sixth of what is left (three tasks in
    # flight, two rounds of them) near the end, never below an eighth of the measured size, never below one.
    from synth.studies.runner import _tail_size

    assert _tail_size(330, 10_000, 3) == 330
    assert _tail_size(330, 600, 3) == 100
    assert _tail_size(330, 60, 3) == 41
    assert _tail_size(8, 5, 3) == 1
    # Every variant of a study run in tasks sized so: the tasks cover them, and the last are the smallest.
    unsent, size, sizes = 10_000, 330, []
    while unsent:
        sizes.append(min(_tail_size(size, unsent, 3), unsent))
        unsent -= sizes[-1]
    assert sizes[0] == 330 and sizes[-1] <= 41 and sizes == sorted(sizes, reverse=True)
