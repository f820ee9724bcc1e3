"""A curve written as JSON text with the digits its accuracy carries: one absolute quantum per array.

An array ``x`` (1-D, or 2-D written as nested lists) whose largest magnitude ``m`` lies in [10^e, 10^(e+1)) is
written at the quantum ``q = 10^(e-7)``: each value as the shortest decimal text of ``round(x/q)·q``, eight
significant digits at the array's largest magnitude and fewer for its smaller values, within ``q/2 <= 5e-8·m``
of the float64 (and the float64 read back from that text within its own half ulp). The engine's round-off in a
curve is absolute, at the scale of its largest values, so digits below ``q`` carry nothing.

Two compiled loops write the whole array. The scale is found once (a logarithm per array, none per number); each
value is then the integer ``n = round(|x|/q)``, at most 10^8, whose eight low digits are spread into the eight
bytes of one 64-bit word by multiplications and shifts (two digits, then four, then eight at a time), split at the
decimal point the array's exponent places, the leading and trailing zeros counted with one bit-scan each: no
division, no table and no branch, so the compiler runs that loop on several values at once. The second loop
places each value's words, eight bytes a store, one after the other. Every value is written as a
JSON float (``0.0``, ``359.9``, ``-0.0012345``, ``12345e-20``), so a parser reads the same type whichever precision
the answer was written in. Values must be finite (the answer is checked before it is written).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar, cast

import numba
import numpy as np
import orjson
from numba.cpython.unsafe.numbers import leading_zeros as _lzcnt, trailing_zeros as _tzcnt

from synth.compiled import compiled

F = TypeVar("F", bound=Callable[..., object])

#: numba's bit-scan intrinsics (one instruction each), as the compiled code calls them.
leading_zeros = cast(Callable[[np.uint64], int], _lzcnt)
trailing_zeros = cast(Callable[[np.uint64], int], _tzcnt)


def _inlined(fn: F) -> F:
    """``fn`` compiled into its compiled callers (numba's IR inlining): a call of its own would pass the output
    buffer with a reference count, an atomic increment and decrement that cost more than writing a number."""
    return cast(F, numba.njit(inline="always", error_model="numpy")(fn))


#: Decimal places of an array's largest magnitude below its leading digit: eight significant digits.
DIGITS_BELOW = 7
#: Quanta written with a decimal point, 10^-12 to 10^6; beyond them the integer and an exponent (``12345e-20``).
POSITIONAL = (-12, 6)
#: 10^i for i from -340 to 340, each the float nearest the decimal.
_POW10_LOW = -340
_POW10 = np.array([float(f"1e{i}") for i in range(_POW10_LOW, 341)])

# numba computes a mix of signed and unsigned integers in floats: the word arithmetic is all uint64.
_U = np.uint64
_U0, _U1, _BYTE = _U(0), _U(1), _U(255)
_E4, _E8 = _U(10**4), _U(10**8)
#: v // 10^4 as (v · 3518437209) >> 45, exact for v below 2^32.
_DIV4, _SHIFT4 = _U(3518437209), _U(45)
#: "0" in each of a word's eight bytes.
_ASCII = _U(0x3030303030303030)
_LANES2 = _U((0x7F << 32) | 0x7F)
_LANES4 = _U((0xF << 48) | (0xF << 32) | (0xF << 16) | 0xF)

#: Values whose words are made before they are placed: a chunk's 24 bytes a value stay in the cache.
_CHUNK = 4096

_ZERO, _DOT, _MINUS, _E = ord("0"), ord("."), ord("-"), ord("e")
_COMMA, _OPEN, _CLOSE = ord(","), ord("["), ord("]")


@compiled
def _exponent(values: np.ndarray, pow10: np.ndarray) -> int:
    """e with 10^e <= max|values| < 10^(e+1); 0 for an array of zeros or an empty one."""
    m = 0.0
    for x in values:
        a = abs(x)
        if a > m:
            m = a
    if m == 0.0:
        return 0
    e = int(np.floor(np.log10(m)))
    # log10 rounds: next to a power of ten it may land on the wrong side of it
    if pow10[e - _POW10_LOW] > m:
        e -= 1
    elif e + 1 - _POW10_LOW < len(pow10) and pow10[e + 1 - _POW10_LOW] <= m:
        e += 1
    return e


@_inlined
def _digits8(v: np.uint64) -> np.uint64:
    """The eight decimal digits of v < 10^8 as the bytes of a word, most significant first in memory (the
    word's low byte); digit values 0-9, not yet characters."""
    high = (v * _DIV4) >> _SHIFT4
    lanes = high | ((v - high * _E4) << _U(32))          # two 4-digit halves, one per 32-bit lane
    top = ((lanes * _U(10486)) >> _U(20)) & _LANES2      # // 100 in each lane
    hundreds = ((lanes - _U(100) * top) << _U(16)) + top  # four 2-digit parts, one per 16-bit lane
    tens = ((hundreds * _U(103)) >> _U(10)) & _LANES4    # // 10 in each lane
    return tens + ((hundreds - _U(10) * tens) << _U(8))


@_inlined
def _put8(out: np.ndarray, pos: int, word: np.uint64) -> None:
    """The word's eight bytes at out[pos:pos + 8], low byte first: one store once compiled."""
    p = _U(pos)
    out[p] = word & _BYTE
    out[p + _U(1)] = (word >> _U(8)) & _BYTE
    out[p + _U(2)] = (word >> _U(16)) & _BYTE
    out[p + _U(3)] = (word >> _U(24)) & _BYTE
    out[p + _U(4)] = (word >> _U(32)) & _BYTE
    out[p + _U(5)] = (word >> _U(40)) & _BYTE
    out[p + _U(6)] = (word >> _U(48)) & _BYTE
    out[p + _U(7)] = (word >> _U(56)) & _BYTE


@compiled
def _texts(values: np.ndarray, scale: float, places: int, head: np.ndarray, tail: np.ndarray,
           sizes: np.ndarray) -> None:
    """Each value written with at most ``places`` (1 to 12) decimal places, |x|·scale <= 10^8 where scale is
    10^places, as two words of text and a byte between them: ``head`` the integer part without leading zeros and
    ``tail`` the fraction without trailing zeros, one digit at least each, the point between them; below 0.1 of
    a unit (nine places or more) ``head`` is "0." and the fraction's first zeros, the byte its ninth digit.
    ``sizes`` holds the two lengths (bits 0-3 and 4-7), the sign (bit 8; a value that rounds to zero is "0.0")
    and the byte (bits 9-16). Loops of arithmetic without a branch, which the compiler runs on several values at
    once (SIMD); :func:`_emit` then places the words."""
    if places <= 8:
        mask = (_U1 << _U(8 * (9 - places))) - _U1 if places > 1 else ~_U0
        drop = _U(8 * (8 - places))
        for i in range(values.size):
            y = values[i] * scale
            n = _U(abs(y) + 0.5)
            ninth = _U(n >= _E8)                           # n is 10^8 at most
            word = _digits8(n - ninth * _E8)
            # the integer part: the ninth digit and the word's first 8 - places, leading zeros dropped
            whole = (ninth | (word << _U(8))) & mask
            lead = min(int(np.int64(trailing_zeros(whole)) >> 3), 8 - places)
            head[i] = (whole >> _U(8 * lead)) + _ASCII
            fraction = word >> drop
            trail = min(int(np.int64(leading_zeros(fraction)) >> 3) - (8 - places), places - 1)
            tail[i] = fraction + _ASCII
            sizes[i] = (9 - places - lead) | ((places - trail) << 4) | (int(y <= -0.5) << 8) | (_DOT << 9)
        return
    # "0." and the places - 9 zeros before the ninth digit's place, as the bytes of a word
    zeros = _U(0)
    for j in range(places - 7):
        zeros |= _U(_DOT if j == 1 else _ZERO) << _U(8 * j)
    for i in range(values.size):
        y = values[i] * scale
        n = _U(abs(y) + 0.5)
        ninth = _U(n >= _E8)
        word = _digits8(n - ninth * _E8)
        digits = 8 - (int(np.int64(leading_zeros(word)) >> 3))   # the word's digits up to its last non-zero
        zero = n == _U0
        head[i] = _U(_ZERO) if zero else zeros
        tail[i] = word + _ASCII
        sizes[i] = ((1 if zero else places - 7) | ((1 if zero else digits) << 4) | (int(y <= -0.5) << 8)
                    | ((_DOT if zero else _ZERO + int(ninth)) << 9))


@_inlined
def _emit(out: np.ndarray, pos: int, head: np.uint64, tail: np.uint64, size: int) -> int:
    """A value's words from :func:`_texts` at out[pos:]: the sign, the head, the byte between, the tail.
    Returns the end; bytes past it may have been written and are overwritten next."""
    out[pos] = _MINUS
    pos += (size >> 8) & 1
    _put8(out, pos, head)
    pos += size & 15
    out[pos] = size >> 9
    _put8(out, pos + 1, tail)
    return pos + 1 + ((size >> 4) & 15)


@_inlined
def _general(x: float, k: int, scale1: float, scale2: float, out: np.ndarray, pos: int,
             digits: np.ndarray) -> int:
    """x at the quantum 10^k where :func:`_texts` does not apply (a quantum of one or more, or beyond the
    positional range) at out[pos:]: the integer, then k zeros and ".0"; or the integer without its trailing zeros
    and an exponent. ``x * scale1 * scale2`` is x / 10^k. Returns the end."""
    y = x * scale1 * scale2
    n = np.int64(abs(y) + 0.5)                             # rounded as :func:`_texts` rounds
    if n == 0:
        out[pos] = _ZERO
        out[pos + 1] = _DOT
        out[pos + 2] = _ZERO
        return pos + 3
    if y < 0.0:
        out[pos] = _MINUS
        pos += 1
    d = 0                                                  # the integer's digits, least significant first
    while n > 0:
        digits[d] = _ZERO + n % 10
        n //= 10
        d += 1
    if POSITIONAL[0] <= k <= POSITIONAL[1]:
        for j in range(d - 1, -1, -1):
            out[pos] = digits[j]
            pos += 1
        for j in range(k):
            out[pos] = _ZERO
            pos += 1
        out[pos] = _DOT
        out[pos + 1] = _ZERO
        return pos + 2
    zeros = 0
    while digits[zeros] == _ZERO:
        zeros += 1
    for j in range(d - 1, zeros - 1, -1):
        out[pos] = digits[j]
        pos += 1
    out[pos] = _E
    pos += 1
    e = k + zeros
    if e < 0:
        out[pos] = _MINUS
        pos += 1
        e = -e
    d = 0
    while True:
        digits[d] = _ZERO + e % 10
        e //= 10
        d += 1
        if e == 0:
            break
    for j in range(d - 1, -1, -1):
        out[pos] = digits[j]
        pos += 1
    return pos


@compiled
def _write(values: np.ndarray, columns: int, pow10: np.ndarray) -> np.ndarray:
    """``values`` (flat, C order) as JSON bytes: a list, or a list of rows of ``columns`` when ``columns`` > 0."""
    n = values.size
    width = max(columns, 1)
    out = np.empty(n * 26 + (n // width) * 3 + 16, dtype=np.uint8)   # 8 bytes of slack for the word stores
    digits = np.empty(24, dtype=np.uint8)
    k = _exponent(values, pow10) - DIGITS_BELOW            # the quantum is 10^k
    # x / 10^k as x * 10^-k, in two factors where 10^-k alone would overflow (curves of subnormal numbers)
    s1 = min(-k, 308)
    scale1, scale2 = pow10[s1 - _POW10_LOW], pow10[-k - s1 - _POW10_LOW]
    places = -k
    words = POSITIONAL[0] <= k < 0                         # decimals of 1 to 12 places: the common case
    # the words of a chunk of rows at a time, so that they stay in the cache between the two passes
    chunk = max(_CHUNK // width, 1) * width
    head = np.empty(min(n, chunk) if words else 0, dtype=np.uint64)
    tail = np.empty_like(head)
    sizes = np.empty(head.size, dtype=np.int64)
    out[0] = _OPEN
    pos = 1
    if words:
        for start in range(0, n, chunk):
            stop = min(start + chunk, n)
            _texts(values[start:stop], scale1, places, head, tail, sizes)
            if columns == 0:
                for i in range(stop - start):              # a curve of one value per sample
                    pos = _emit(out, pos, head[i], tail[i], sizes[i])
                    out[pos] = _COMMA
                    pos += 1
            else:
                for i in range(0, stop - start, width):    # rows: points and forces over the samples
                    out[pos] = _OPEN
                    pos += 1
                    for j in range(i, i + width):
                        pos = _emit(out, pos, head[j], tail[j], sizes[j])
                        out[pos] = _COMMA
                        pos += 1
                    out[pos - 1] = _CLOSE
                    out[pos] = _COMMA
                    pos += 1
    else:
        for i in range(0, n, width):
            if columns > 0:
                out[pos] = _OPEN
                pos += 1
            for j in range(i, i + width):
                pos = _general(values[j], k, scale1, scale2, out, pos, digits)
                out[pos] = _COMMA
                pos += 1
            if columns > 0:
                out[pos - 1] = _CLOSE
                out[pos] = _COMMA
                pos += 1
    pos -= n > 0
    out[pos] = _CLOSE
    return out[:pos + 1]


def curve_bytes(values: np.ndarray) -> bytes:
    """A finite 1-D or 2-D float array as JSON text at its quantum (see the module): a list, or a list of rows."""
    if values.ndim not in (1, 2):
        raise ValueError(f"a curve is 1-D or 2-D, not {values.ndim}-D")
    if values.ndim == 2 and values.shape[1] == 0:
        return b"[" + b",".join(b"[]" for _ in range(values.shape[0])) + b"]"
    flat = np.ascontiguousarray(values, dtype=np.float64).reshape(-1)
    return bytes(_write(flat, values.shape[1] if values.ndim == 2 else 0, _POW10))


def curve_fragment(values: np.ndarray) -> orjson.Fragment:
    """:func:`curve_bytes` as a piece orjson writes into a document as it is."""
    return orjson.Fragment(curve_bytes(values))
