"""The curves' JSON text at one quantum per array, held to an independent decimal formatter (Python's ``decimal``
on each float's exact value) and to the bound the docs state: every value read back within half the quantum."""

from __future__ import annotations

import json
from decimal import ROUND_HALF_UP, Decimal

import numpy as np
import orjson
import pytest

from api.curve_text import curve_bytes, curve_fragment


def _quantum(values: np.ndarray) -> Decimal:
    """10^(e-7) for the largest magnitude in [10^e, 10^(e+1)), found exactly (Decimal's adjusted exponent)."""
    m = max((abs(Decimal(float(x))) for x in values.reshape(-1)), default=Decimal(0))
    e = m.adjusted() if m else 0
    return Decimal(1).scaleb(e - 7)


def _texts(x: float, q: Decimal) -> set[str]:
    """The shortest decimal of round(x/q)·q (half away from zero); both neighbours where x/q lies within 1e-6 of
    a tie, which the writer's x·10^-k in float64 (0.5 ulp of up to 10^8) may round either way."""
    exact = Decimal(x) / q
    tie = abs(abs(exact) % 1 - Decimal("0.5")) < Decimal("1e-6")
    n = int(exact.to_integral_value(ROUND_HALF_UP))
    return {_text(n, q), _text(n - (1 if n > 0 else -1), q)} if tie else {_text(n, q)}


def _text(n: int, q: Decimal) -> str:
    """The shortest decimal of n·q, as the docs describe it: positional with at least one digit each side of the
    point for quanta from 1e-12 to 1e6, else the integer without its trailing zeros and an exponent."""
    if n == 0:
        return "0.0"
    k = q.adjusted()
    if -12 <= k <= 6:
        text = format(Decimal(n).scaleb(k), "f")
        if "." in text:
            text = text.rstrip("0")
        return text + "0" if text.endswith(".") else (text if "." in text else text + ".0")
    zeros = len(str(abs(n))) - len(str(abs(n)).rstrip("0"))
    return f"{n // 10**zeros}e{k + zeros}"


def _numbers(text: bytes) -> list[str]:
    return [t for t in text.decode().replace("[", "").replace("]", "").split(",") if t]


def _check(values: np.ndarray) -> None:
    text = curve_bytes(values)
    q = _quantum(values)
    written = _numbers(text)
    assert len(written) == values.size
    assert all(t in _texts(float(x), q) for t, x in zip(written, values.reshape(-1)))
    got = np.array(json.loads(text), dtype=float).reshape(values.shape)
    assert got.shape == values.shape
    # half the quantum, plus the float64 round-off of x/q (x·10^-k in float, 10^8 at most) and of reading back
    bound = float(q) / 2 * (1 + 1e-7) + np.spacing(np.abs(values))
    assert np.all(np.abs(got - values) <= bound)


@pytest.mark.parametrize("scale", [1e-30, 1e-14, 1e-9, 3e-4, 0.05, 0.4, 7.0, 359.9, 8e4, 3e7, 2e12, 1e30])
def test_random_curves_read_back_within_half_the_quantum(scale: float) -> None:
    # normal values spread over a few decades below the largest one, and a few exact zeros among them; more
    # values than the writer takes in one chunk (4096), as one curve and as rows of two
    rng = np.random.default_rng(int(np.log10(scale) + 40))
    values = rng.normal(scale=scale, size=9000) * rng.choice([1.0, 1e-2, 1e-5, 1e-9], size=9000)
    values[::97] = 0.0
    _check(values)
    _check(values.reshape(-1, 2))


@pytest.mark.parametrize("values", [
    [0.0, 0.0, 0.0],                                  # all zeros: "0.0" each
    [-0.0, 0.0],
    [7.25, 7.25, 7.25],                               # all equal
    [-1.5, -2.0, -0.001],                             # all negative
    [1000.0, 0.001, -999.99999],                      # the largest at a power of ten
    [0.001, -0.0001],
    [1e-5, 3.0e-6],
    [99999999.7, 0.4],                                # rounds up to 10^8, a ninth digit
    [0.999999996, 0.5],                               # rounds up to the next power of ten
    [-4.9e-9, 0.99],                                  # a negative value that rounds to zero is "0.0"
    [0.1, 359.9, 120.0, 0.0],                         # the crank's angles
    [1e-30, -3.3e-31, 2.5e-37],
    [1e30, -2.5e29, 7.0],
    [1.7e308, -5e-324],                               # the ends of float64
    [5e-324],
    [123456789012345.0, 1.0],
    [1234567.0, 0.5, -0.05],
])
def test_edge_cases(values: list[float]) -> None:
    _check(np.array(values))


def test_two_columns_are_rows_and_empty_arrays_are_empty_lists() -> None:
    pairs = np.array([[1.0, -2.5], [0.0, 3.25]])
    assert curve_bytes(pairs) == b"[[1.0,-2.5],[0.0,3.25]]"
    assert json.loads(curve_bytes(pairs)) == pairs.tolist()
    assert curve_bytes(np.empty(0)) == b"[]"
    assert curve_bytes(np.empty((0, 2))) == b"[]"
    assert curve_bytes(np.empty((2, 0))) == b"[[],[]]"
    # a strided view (a column of the reaction unknowns) and float32 are written from their values
    wide = np.arange(12.0).reshape(3, 4)
    assert curve_bytes(wide[:, 1:3]) == curve_bytes(np.ascontiguousarray(wide[:, 1:3]))
    assert json.loads(curve_bytes(np.array([0.5, 0.25], dtype=np.float32))) == [0.5, 0.25]
    with pytest.raises(ValueError, match="3-D"):
        curve_bytes(np.zeros((2, 2, 2)))


def test_a_fragment_is_spliced_into_the_document_as_it_is() -> None:
    values = np.array([0.125, -3.5])
    document = orjson.dumps({"a": curve_fragment(values), "b": 1.5})
    assert document == b'{"a":[0.125,-3.5],"b":1.5}'


def test_every_digit_of_the_integers_below_ten_to_the_eight() -> None:
    # The digits come from multiplications and shifts (no division); integers below 10^8 in steps that visit
    # every digit in every place, and the ends of the 2- and 4-digit groups, each written at the quantum 1e-8 of
    # a curve whose largest value is just below 1 (the ninth digit, 10^8, is among the edge cases).
    n = np.concatenate([np.arange(0, 10**8, 9973), [9, 10, 99, 100, 9999, 10_000, 999_999, 10**6],
                        np.arange(10**8 - 200, 10**8)])
    _check(n / 1e8)
