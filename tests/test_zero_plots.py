"""Figures of a fully balanced linkage: its shaking force and moment are rounding (1e-13 N), read as zero on axes a
thousandth of the linkage's own force scale wide, not autoscaled onto the noise."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pytest

from mechsynth_client.client import SynthClient
from mechsynth_client.schemas.balancing import FullBalanceIn
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from synth.plots import ZERO_SPAN, read_zero


def test_full_balance_reads_as_zero_in_matplotlib(client: SynthClient) -> None:
    body = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 180}
    balanced = client.balance_full(FullBalanceIn.model_validate(body))
    after = client.http.post("/v1/analysis", json={**body, "balancing": balanced.model_dump(mode="json")}).json()
    force = np.asarray(after["shaking_force_N"])
    # the linkage's force scale written here: every mass (links and counterweights) × ω² × the cycle's extent
    links = FOURBAR_EXAMPLE["links"]
    mass = sum(v["mass_kg"] for v in links.values()) + sum(c.mass_kg for c in balanced.counterweights)  # type: ignore[union-attr]
    cloud = np.vstack([np.asarray(p["position_m"]) for p in after["points"].values()])
    scale = mass * (300 * math.pi / 30) ** 2 * float(np.ptp(cloud, axis=0).max())
    peak = float(np.hypot(*force.T).max())
    assert 0 < peak < 1e-9 * scale
    fig, ax = plt.subplots()
    ax.plot(force[:, 0], force[:, 1])
    assert read_zero(ax, peak, scale, "N", polar=True)
    assert ax.get_ylim() == pytest.approx((-ZERO_SPAN * scale, ZERO_SPAN * scale), rel=1e-12)
    assert ax.get_xlim() == pytest.approx((-ZERO_SPAN * scale, ZERO_SPAN * scale), rel=1e-12)
    assert any(t.get_text().startswith("≈ 0") for t in ax.texts)
    # an unbalanced force is drawn as it is
    fig2, ax2 = plt.subplots()
    assert not read_zero(ax2, 1e-3 * scale, scale, "N")
    plt.close(fig)
    plt.close(fig2)
