"""Figures of the machine on its foundation: the force it passes on, the frame's orbit, the transmissibility per
harmonic; the speed and torque of a regulated machine after a load step."""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from .foundation import Isolation  # noqa: E402


def _bytes(fig: Figure, fmt: str) -> bytes:
    buffer = io.BytesIO()
    fig.savefig(buffer, format=fmt, dpi=110)
    plt.close(fig)
    return buffer.getvalue()


def isolation_figure(r: Isolation, fmt: str = "png") -> bytes:
    """Force to the foundation against the shaking force over the cycle, the frame centre's orbit, and the force
    transmissibility per harmonic, as PNG, SVG or PDF."""
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.4), layout="constrained")
    deg = np.degrees(r.phi)
    ax = axes[0]
    ax.plot(deg, np.linalg.norm(r.shaking_force, axis=1), lw=1.2, label="shaking force (rigid floor)")
    ax.plot(deg, np.linalg.norm(r.force, axis=1), lw=1.2, label="force to the foundation")
    ax.set(xlabel="crank angle [deg]", ylabel="|F| [N]", title="Force the foundation feels")
    ax.legend(fontsize=8)
    ax = axes[1]
    ax.plot(r.displacement[:, 0] * 1e3, r.displacement[:, 1] * 1e3, lw=1.2)
    ax.plot(r.displacement[0, 0] * 1e3, r.displacement[0, 1] * 1e3, "o", ms=4, label="first sample")
    ax.set(xlabel="x [mm]", ylabel="y [mm]", title=f"Frame centre's orbit (peak {r.peak_displacement * 1e3:.3g} mm)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=8)
    ax = axes[2]
    orders = [h.order for h in r.harmonics if h.force_transmissibility is not None]
    values = [h.force_transmissibility for h in r.harmonics if h.force_transmissibility is not None]
    ax.bar(orders, values, color="C1")
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    crank_hz = 1.0 / (r.time[1] * r.time.size)
    for m in r.modes:
        ax.axvline(m.frequency / crank_hz, color="C3", lw=0.8, ls=":")
    ax.set(xlabel="harmonic order (modes dotted)", ylabel="transmitted / shaking [-]", yscale="log",
           title="Force transmissibility per harmonic")
    return _bytes(fig, fmt)
