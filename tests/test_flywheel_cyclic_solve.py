"""The periodic Newton solve's linear algebra: the cyclic bidiagonal system by its compiled recurrence and by
sparse LU on a pattern built once per sample count."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse import csc_array
from scipy.sparse.linalg import spsolve

from synth.flywheel.motor import _cyclic_pattern, _cyclic_solve, _sparse_cyclic_solve

SAMPLES = (2, 3, 72, 360, 3600)


def _system(n: int, damping: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A cyclic system shaped like the collocation's Jacobian: |diag/sup| a little below ``damping`` (the motor's
    damping keeps it below one)."""
    rng = np.random.default_rng(n)
    sup = 1.0 + rng.random(n)
    diag = -damping * sup * (1.0 - 0.001 * rng.random(n))
    return diag, sup, rng.standard_normal((n, 2))


def _matrix_from_triplets(diag: np.ndarray, sup: np.ndarray) -> csc_array:
    """The matrix from (row, column) triplets, the way scipy canonicalises them: an independent construction."""
    n = diag.size
    rows = np.arange(n)
    cols = np.concatenate([rows, np.roll(rows, -1)])
    return csc_array((np.concatenate([diag, sup]), (np.concatenate([rows, rows]), cols)), shape=(n, n))


@pytest.mark.parametrize("n", SAMPLES)
def test_cached_pattern_equals_one_built_afresh(n: int) -> None:
    indices, indptr = _cyclic_pattern(n)
    fresh = _matrix_from_triplets(np.arange(1.0, n + 1), np.arange(-1.0, -n - 1, -1))
    assert fresh.has_canonical_format
    np.testing.assert_array_equal(indices, fresh.indices)
    np.testing.assert_array_equal(indptr, fresh.indptr)
    assert indices.dtype == indptr.dtype == np.intc  # SuperLU's own index type: spsolve passes them on as they are
    assert _cyclic_pattern(n) is _cyclic_pattern(n) and not indices.flags.writeable


@pytest.mark.parametrize("n", SAMPLES)
def test_sparse_solve_is_the_triplet_matrix_solve_to_the_bit(n: int) -> None:
    diag, sup, rhs = _system(n, 0.9)
    z = _sparse_cyclic_solve(diag, sup, rhs)
    assert z is not None
    # the same matrix handed to SuperLU gives the same bits; and it solves the system (identity, residual)
    assert np.array_equal(z, np.asarray(spsolve(_matrix_from_triplets(diag, sup), rhs)).reshape(rhs.shape))
    residual = diag[:, None] * z + sup[:, None] * np.roll(z, -1, axis=0) - rhs
    assert np.max(np.abs(residual)) <= 1e-12 * np.max(np.abs(rhs))


@pytest.mark.parametrize("n", SAMPLES)
@pytest.mark.parametrize("damping", [0.999, 0.5])
def test_recurrence_and_lu_solve_the_cyclic_system(n: int, damping: float) -> None:
    # at 0.999 the recurrence's products stay above 1e-6 up to 3 600 samples (a few thousandths there); at 0.5
    # they fall below it beyond 20 samples and the LU answers: both must solve the system (a dense solve as the
    # reference)
    diag, sup, rhs = _system(n, damping)
    products = np.cumprod(-diag / sup)
    assert (np.min(np.abs(products)) > 1e-6) == (damping == 0.999 or n <= 3)
    z = _cyclic_solve(diag, sup, rhs)
    assert z is not None
    if n <= 360:
        dense = np.diag(diag) + np.roll(np.diag(sup), 1, axis=1)
        np.testing.assert_allclose(z, np.linalg.solve(dense, rhs), rtol=1e-9, atol=1e-12)
    residual = diag[:, None] * z + sup[:, None] * np.roll(z, -1, axis=0) - rhs
    assert np.max(np.abs(residual)) <= 1e-9 * np.max(np.abs(rhs))


def test_the_compiled_iteration_finds_the_band_s_speeds_as_numpy_does() -> None:
    # The least and largest speeds (the band's row) by numpy's rule: the first of equal values, the first NaN.
    import numpy as np

    from synth.flywheel.motor import _arg_extremes

    rng = np.random.default_rng(1)
    for _ in range(500):
        x = rng.integers(0, 5, rng.integers(1, 12)).astype(float)   # small integers: many ties
        if rng.random() < 0.2:
            x[rng.integers(0, x.size)] = np.nan
        assert _arg_extremes(x) == (int(np.argmin(x)), int(np.argmax(x))), x
