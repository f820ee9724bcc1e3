"""Arrays of floats written as JSON text by numpy, all numbers at once, with the digits their accuracy carries.

The engine's arrays over the crank angles come from closed forms and stacked linear solves, accurate to about
1e-12 of each array's largest magnitude; the digits beyond are round-off. An array is written in fixed point
with :data:`CARRIED_DIGITS` significant digits of its largest magnitude (so a value 1e-15 of the largest, which
is round-off, is written as 0.0), trailing zeros dropped: each number becomes an integer of at most that many
digits, cut into characters column by column, and the padding is squeezed out in one pass. A full-precision
answer (the shortest text that reads back as the same double, for every float) is orjson's own.
"""

from __future__ import annotations

import math

import numpy as np
import orjson

from synth.model import FloatArray

CARRIED_DIGITS = 12
# Beyond these the fixed-point text would be longer than orjson's (tiny or huge scales): orjson writes it.
_MAX_DECIMALS = 20
_ZERO, _DOT, _MINUS, _COMMA, _OPEN, _CLOSE = (ord(c) for c in "0.-,[]")


def _fixed_point(values: FloatArray, digits: int, cols: int) -> bytes | None:
    """JSON text of ``values`` (flat, finite) in rows of ``cols`` numbers (0: one flat list) in fixed point, or
    None when the array's scale needs more decimals than :data:`_MAX_DECIMALS` or fewer than none."""
    top = float(np.max(np.abs(values)))
    decimals = digits - 1 - math.floor(math.log10(top)) if top > 0.0 else 1
    if not 0 <= decimals <= _MAX_DECIMALS:
        return None
    scaled = np.rint(values * 10.0**decimals).astype(np.int64)
    # |scaled| <= 10**digits (the largest may round up to it), and at least one digit before the point.
    whole = max(digits + 1, decimals + 1) - decimals
    fraction = max(decimals, 1)
    n = values.size
    chars = np.zeros((n, 1 + whole + 1 + fraction + 3), dtype=np.uint8)
    magnitude = np.abs(scaled)
    for col in [*range(1 + whole + decimals, 1 + whole, -1), *range(whole, 0, -1)]:
        quotient = magnitude // 10
        chars[:, col] = magnitude - 10 * quotient
        magnitude = quotient
    chars[:, 1:2 + whole + fraction] += _ZERO
    chars[:, 1 + whole] = _DOT
    # Leading zeros of the integer part (all but its last digit) and trailing zeros of the fraction (all but
    # its first digit) become padding, squeezed out below.
    absolute = np.abs(scaled)
    units = absolute // 10**decimals
    shown = 1 + np.searchsorted(10 ** np.arange(1, whole, dtype=np.int64), units, side="right")
    chars[:, 1:1 + whole][np.arange(whole)[None, :] < (whole - shown)[:, None]] = 0
    if decimals > 1:
        rest = absolute - units * 10**decimals
        zeros = np.zeros(n, dtype=np.int64)
        for j in range(1, decimals):
            zeros += rest % 10**j == 0
        kept = decimals - np.minimum(zeros, decimals - 1)
        chars[:, 2 + whole:2 + whole + fraction][np.arange(fraction)[None, :] >= kept[:, None]] = 0
    chars[:, 0] = np.where(scaled < 0, _MINUS, 0)
    chars[:, -3] = _COMMA
    if cols:
        # The last number of each row closes it and opens the next: "],[".
        chars[cols - 1::cols, -3:] = (_CLOSE, _COMMA, _OPEN)
    flat = chars.reshape(-1)
    text = flat[flat != 0].tobytes()
    return b"[[" + text[:-3] + b"]]" if cols else b"[" + text[:-1] + b"]"


def array_json(values: FloatArray, digits: int = CARRIED_DIGITS) -> bytes:
    """JSON text of a finite, non-empty float array of one or two dimensions, each number with ``digits``
    significant digits of the array's largest magnitude."""
    array = np.asarray(values, dtype=float)
    text = None
    if array.size and array.ndim in (1, 2):
        text = _fixed_point(np.ascontiguousarray(array).reshape(-1), digits, array.shape[1] if array.ndim == 2 else 0)
    if text is None:
        return orjson.dumps(np.ascontiguousarray(array), option=orjson.OPT_SERIALIZE_NUMPY)
    return text


def fragments(value: object, digits: int = CARRIED_DIGITS) -> object:
    """A plain answer (dicts, lists, arrays) with every float array of one or two dimensions replaced by its
    text as an orjson fragment, written with ``digits`` digits."""
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "f" and value.ndim in (1, 2) and value.size:
            return orjson.Fragment(array_json(value, digits))
        return value
    if isinstance(value, dict):
        return {key: fragments(item, digits) for key, item in value.items()}
    if isinstance(value, list):
        return [fragments(item, digits) for item in value]
    return value
