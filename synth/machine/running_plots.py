"""The design record's page on how the machine really runs: run-up, motor torque over the start, run-down and
the efficiency of each stage."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from ..plots import literal_text  # noqa: E402
from .chain import MachineDesign  # noqa: E402
from .running import MachineRunning  # noqa: E402

_A4 = (11.69, 8.27)
RPM = np.pi / 30


def _fmt(value: float | None, unit: str = "") -> str:
    return "-" if value is None else f"{value:.4g}{unit}"


def _residual(value: float | None) -> str:
    """The energy balance's relative residual, as met below 1e-9 (integration noise, not a figure)."""
    if value is None:
        return "-"
    return "below 1e-9" if abs(value) < 1e-9 else f"{value:.1e}"


def _run_up(ax: Axes, r: MachineRunning) -> None:
    up = r.startup
    if up.run is None:
        ax.text(0.5, 0.5, "the motor cannot start the machine", ha="center", va="center", transform=ax.transAxes)
    else:
        ax.plot(up.run.time, up.run.omega / RPM, lw=1.2, label="crank speed")
        if up.steady_time is not None:
            ax.axvline(up.steady_time, color="k", ls=":", lw=1, label=f"steady after {up.steady_time:.3g} s")
        ax.axhline(up.steady.mean_speed / RPM, color="g", ls="--", lw=1, label="steady mean speed")
        ax.legend(fontsize=7)
    ax.set_title("run-up from rest")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("crank speed [rpm]")
    ax.grid(alpha=0.3)


def _start_torque(ax: Axes, d: MachineDesign, r: MachineRunning) -> None:
    up, motor = r.startup, d.motor
    if up.run is not None:
        ax.plot(up.run.time, up.run.motor_torque, lw=1.2, label="motor torque")
        ax.axhline(up.rms_motor_torque, color="g", ls="--", lw=1, label=f"RMS until steady {up.rms_motor_torque:.4g}")
    ax.axhline(motor.rated_torque, color="g", ls=":", lw=1, label=f"rated {motor.rated_torque:.4g}")
    if motor.starting_torque is not None:
        ax.axhline(motor.starting_torque, color="m", ls=":", lw=1, label=f"starting {motor.starting_torque:.4g}")
    if motor.breakdown_torque is not None:
        ax.axhline(motor.breakdown_torque, color="r", ls=":", lw=1, label=f"breakdown {motor.breakdown_torque:.4g}")
    ax.legend(fontsize=7)
    ax.set_title(f"motor {d.drive.motor.name} over the start")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("torque on the motor shaft [N·m]")
    ax.grid(alpha=0.3)


def _run_down(ax: Axes, r: MachineRunning) -> None:
    down = r.rundown
    ax.plot(down.run.time, np.maximum(down.run.omega, 0.0) / RPM, lw=1.2, label="crank speed")
    if down.stop_time is not None:
        ax.axvline(down.stop_time, color="k", ls=":", lw=1, label=f"at rest after {down.stop_time:.3g} s")
    ax.legend(fontsize=7, title=f"brake {down.brake_torque:.4g} N·m at the crank", title_fontsize=7)
    ax.set_title("run-down, motor off")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("crank speed [rpm]")
    ax.grid(alpha=0.3)


def running_figure(d: MachineDesign) -> Figure | None:
    """Run-up speed, motor torque over the start and run-down speed, with each stage's efficiency and the start
    check in a table; None when the design has no running figures."""
    r = d.running
    if r is None:
        return None
    fig, axes = plt.subplots(2, 2, figsize=_A4)
    _run_up(axes[0, 0], r)
    _start_torque(axes[0, 1], d, r)
    _run_down(axes[1, 0], r)
    e, up = r.efficiency, r.startup
    held = float(up.check.resisting_torque.max())
    held = 0.0 if abs(held) <= 1e-9 * abs(up.check.starting_torque) else held  # rounding noise, not a torque
    rows = [["efficiency, linkage", _fmt(e.linkage)], ["efficiency, gears", _fmt(e.gears)],
            ["efficiency, overall", _fmt(e.overall)],
            ["starting torque at the crank", _fmt(up.check.starting_torque, " N·m")],
            ["largest torque at rest", _fmt(held, " N·m")
             + f" at {np.degrees(up.check.worst_angle):.4g} deg"],
            ["run-up to steady", _fmt(up.steady_time, " s")],
            ["motor peak / RMS over the start", f"{up.peak_motor_torque:.4g} / {up.rms_motor_torque:.4g} N·m"],
            ["run-down to rest", _fmt(r.rundown.stop_time, " s")],
            ["energy balance, run-up", _residual(up.run.energy_residual if up.run is not None else None)],
            ["time quadrature check, run-down", _residual(r.rundown.time_error)]]
    ax = axes[1, 1]
    ax.axis("off")
    table = ax.table(cellText=rows, colLabels=["quantity", "value"], loc="upper left", cellLoc="right",
                     colLoc="right")
    table.auto_set_font_size(False)
    table.set_fontsize(8)
    table.scale(1.0, 1.3)
    fig.suptitle("how the machine runs: efficiency, start-up and run-down")
    literal_text(fig).tight_layout(rect=(0, 0.03, 1, 1))
    return fig
