"""The design report of a whole machine: a multi-page PDF (matplotlib's PdfPages) and a one-page PNG summary."""

from __future__ import annotations

import io
from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.backends.backend_pdf import PdfPages  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from ..plots import draw_mechanism, figure_png, shaking_polar  # noqa: E402
from .chain import Alternative, MachineDesign  # noqa: E402

_A4 = (11.69, 8.27)
RPM = np.pi / 30


def _grid(ax: Axes, title: str, xlabel: str, ylabel: str) -> None:
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)


def _torque(ax: Axes, d: MachineDesign) -> None:
    deg = np.degrees(d.before.motion.phi)
    ax.plot(deg, d.before.kinetostatics.driving_torque, label="as given")
    if d.balancing.mode != "none":
        ax.plot(deg, d.balanced.kinetostatics.driving_torque, "--", label=f"after {d.balancing.mode} balancing")
    ax.legend(fontsize=7)
    _grid(ax, "driving torque at constant speed", "crank angle [deg]", "torque [N·m]")


def _speed(ax: Axes, d: MachineDesign) -> None:
    m = d.motion
    mid = 0.5 * (float(m.omega.max()) + float(m.omega.min())) / RPM
    ax.plot(np.degrees(m.phi), m.omega / RPM, lw=1.4, label=f"simulated: delta {m.delta:.4g}")
    ax.axhline(mid * (1 + d.spec.delta / 2), color="k", ls=":", lw=1)
    ax.axhline(mid * (1 - d.spec.delta / 2), color="k", ls=":", lw=1, label=f"target band, delta {d.spec.delta:.4g}")
    ax.legend(fontsize=7, title=f"working speed {d.spec.speed / RPM:.4g} rpm", title_fontsize=7)
    _grid(ax, "crank speed, simulated machine", "crank angle [deg]", "crank speed [rpm]")


def _polar(ax: Axes, d: MachineDesign) -> None:
    shaking_polar(ax, d.before.kinetostatics.shaking_force, "as given")
    if d.balancing.mode != "none":
        after = d.balanced.kinetostatics.shaking_force
        if d.balancing.slider_crank is not None and d.balancing.mode == "full":
            after = d.balancing.slider_crank.after_force
        shaking_polar(ax, after, f"after {d.balancing.mode}", ls="--")
    ax.legend(fontsize=7)


def _moment(ax: Axes, d: MachineDesign) -> None:
    deg = np.degrees(d.before.motion.phi)
    ax.plot(deg, d.before.kinetostatics.shaking_moment, label="as given")
    if d.balancing.mode != "none":
        ax.plot(deg, d.balanced.kinetostatics.shaking_moment, "--", label=f"after {d.balancing.mode}")
    ax.legend(fontsize=7)
    _grid(ax, "shaking moment about O", "crank angle [deg]", "moment [N·m]")


def _energy_mass(ax: Axes, d: MachineDesign) -> None:
    f = d.flywheel
    cycle, tan = f.cycle, f.tangents
    phi = cycle.dense(4000)
    inertia, _, work = cycle.evaluate(phi)
    ax.plot(inertia, work, lw=1.5, label="energy-mass curve")
    x = np.linspace(min(0.0, float(inertia.min())), float(inertia.max()) * 1.05 + 1e-12, 50)
    ax.plot(x, tan.slope_max * x + tan.intercept_max, "r--", lw=1, label="tangent w_max²/2")
    ax.plot(x, tan.slope_min * x + tan.intercept_min, "b--", lw=1, label="tangent w_min²/2")
    ax.legend(fontsize=7)
    _grid(ax, "energy-mass diagram", "reduced inertia J_red [kg·m²]", "excess work [J]")


def _motor(ax: Axes, d: MachineDesign) -> None:
    m, motor = d.motion, d.motor
    ax.plot(np.degrees(m.phi), m.motor_torque, label="motor torque")
    ax.axhline(motor.rated_torque, color="g", ls=":", label=f"rated {motor.rated_torque:.4g} N·m")
    ax.axhline(m.motor_rms_torque, color="g", ls="--", lw=1, label=f"RMS {m.motor_rms_torque:.4g} N·m")
    if motor.breakdown_torque is not None:
        ax.axhline(motor.breakdown_torque, color="r", ls=":", label=f"breakdown {motor.breakdown_torque:.4g} N·m")
    ax.legend(fontsize=7)
    _grid(ax, f"motor {d.drive.motor.name} on its shaft", "crank angle [deg]", "torque [N·m]")


def _table(ax: Axes, title: str, header: Sequence[str], rows: Sequence[Sequence[str]]) -> None:
    ax.axis("off")
    ax.set_title(title, loc="left")
    if rows:
        table = ax.table(cellText=[list(r) for r in rows], colLabels=list(header), loc="upper left",
                         cellLoc="right", colLoc="right")
        table.auto_set_font_size(False)
        table.set_fontsize(8)
        table.scale(1.0, 1.3)


def _key_figures(d: MachineDesign) -> list[list[str]]:
    fw, motor = d.placement, d.drive.motor
    rows = [
        ["mean crank power", f"{d.output_power:.4g} W"],
        ["motor", f"{motor.name}, {motor.rated_power:.0f} W, {motor.rated_speed / RPM:.0f} rpm"],
        ["train ratio (teeth)", f"{d.train_ratio:.5g} = " + " × ".join(f"{u:.4g}" for u in d.stage_ratios)],
        ["balancing", d.balancing.mode],
        ["flywheel on crank", f"{d.flywheel_inertia:.4g} kg·m²"],
        ["flywheel body", "none needed" if fw is None else
         f"{fw.shape} on {fw.shaft}: D {fw.outer_diameter:.3g} m, {fw.mass:.3g} kg"],
    ]
    rows += [[f"check {c.name}", f"{c.value:.4g} / {c.limit:.4g} {'ok' if c.passed else 'FAILS'}"]
             for c in d.checks]
    return rows


def _summary_figure(d: MachineDesign) -> Figure:
    fig, axes = plt.subplots(2, 3, figsize=(16, 9))
    # a third of the way round, where no linkage is folded flat on its line of centres
    phi = d.before.motion.phi
    draw_mechanism(axes[0, 0], d.balanced, float(phi[len(phi) // 6]))
    _torque(axes[0, 1], d)
    _speed(axes[0, 2], d)
    _polar(axes[1, 0], d)
    _motor(axes[1, 1], d)
    _table(axes[1, 2], "design", ["quantity", "value"], _key_figures(d))
    fig.suptitle(f"machine design: {'every check met' if d.passed else 'a check fails'}")
    fig.tight_layout()
    return fig


def design_summary_png(design: MachineDesign) -> bytes:
    """One page: the mechanism, driving torque, simulated speed, shaking force, motor torque, key figures [PNG]."""
    return figure_png(_summary_figure(design), dpi=90)


def _gear_rows(d: MachineDesign) -> list[list[str]]:
    """One row per stage of the strength sizing; a stage that is not sized says so."""
    rows = []
    for k, s in enumerate(d.spec.drive.stages):
        g = None if d.gears is None else d.gears.stages[k]
        if g is None:
            rows.append([str(k + 1), "not sized" if d.gears is not None else "sizing off", "", "", "", "", "", ""])
            continue
        rows.append([str(k + 1), f"{g.module * 1e3:g}", f"{g.face_width * 1e3:.1f}",
                     f"{g.centre_distance * 1e3:.1f}", f"{g.diameters[0] * 1e3:.1f} / {g.diameters[1] * 1e3:.1f}",
                     f"{g.safety_contact[0]:.2f} / {g.safety_contact[1]:.2f}",
                     f"{g.safety_root[0]:.2f} / {g.safety_root[1]:.2f}", g.binding])
    return rows


def design_report_pdf(design: MachineDesign, alternatives: Sequence[Alternative] = ()) -> bytes:
    """The design report: summary; balancing (polar diagrams, shaking moment, driving torque); flywheel
    (energy-mass diagram, simulated speed, motor torque); the gear train, its gears sized for strength (module,
    face width, centre distance, safety factors) and every shaft; the alternatives [PDF]."""
    d = design
    buf = io.BytesIO()
    with PdfPages(buf, metadata={"Title": "Machine design report", "Creator": "mechsynth"}) as pdf:
        pdf.savefig(_summary_figure(d))
        fig, axes = plt.subplots(1, 3, figsize=_A4)
        _polar(axes[0], d)
        _moment(axes[1], d)
        _torque(axes[2], d)
        fig.suptitle("balancing")
        fig.tight_layout()
        pdf.savefig(fig)
        fig, axes = plt.subplots(1, 3, figsize=_A4)
        _energy_mass(axes[0], d)
        _speed(axes[1], d)
        _motor(axes[2], d)
        fig.suptitle("flywheel and motor")
        fig.tight_layout()
        pdf.savefig(fig)
        fig, axes = plt.subplots(4, 1, figsize=_A4)
        stages = d.spec.drive.stages
        meshes = d.teeth.stages if d.teeth is not None else ()
        teeth = {k: m for k, m in zip([i for i, s in enumerate(stages) if s.toothed], meshes, strict=True)}
        _table(axes[0], "gear train, motor side first", ["stage", "type", "split ratio", "teeth", "real ratio",
                                                         "efficiency"],
               [[str(k + 1), s.type, f"{d.drive.split.stage_ratios[k]:.4g}",
                 f"{teeth[k].pinion_teeth}:{teeth[k].gear_teeth}" if k in teeth else "-",
                 f"{d.stage_ratios[k]:.5g}", f"{s.efficiency:.3g}"] for k, s in enumerate(stages)])
        _table(axes[1], "gears sized for strength (ISO 6336 method B, Miner's rule on the cyclic torque)",
               ["stage", "module [mm]", "face width [mm]", "centre distance [mm]", "d1 / d2 [mm]",
                "S_H pinion / gear", "S_F pinion / gear", "binding"],
               _gear_rows(d))
        _table(axes[2], "shafts in the simulated steady motion (torque each passes on)",
               ["shaft", "speed [rpm]", "power [W]", "mean T [N·m]", "peak T [N·m]", "RMS T [N·m]",
                "inertia [kg·m²]", "flywheel"],
               [[s.name, f"{s.mean_speed / RPM:.4g}", f"{s.mean_power:.4g}", f"{s.mean_torque:.4g}",
                 f"{s.peak_torque:.4g}", f"{s.rms_torque:.4g}", f"{s.inertia:.4g}", "yes" if s.carries_flywheel else ""]
                for s in d.shafts])
        _table(axes[3], "checks against the simulated machine", ["check", "value", "limit", "met"],
               [[c.name, f"{c.value:.4g}", f"{c.limit:.4g}", "yes" if c.passed else "NO"] for c in d.checks])
        fig.suptitle("drive")
        fig.tight_layout()
        pdf.savefig(fig)
        plt.close("all")
        if alternatives:
            fig, ax = plt.subplots(figsize=_A4)
            rows = []
            for a in [Alternative(d.balancing.mode + " (this design)", d, None), *alternatives]:
                if a.design is None:
                    rows.append([a.mode, "not available", "", "", "", "", ""])
                    continue
                x = a.design
                rows.append([a.mode, f"{x.balancing.after.rms_shaking_force:.4g}",
                             f"{x.balancing.after.rms_shaking_moment:.4g}", f"{x.flywheel_inertia:.4g}",
                             "-" if x.placement is None else f"{x.placement.mass:.4g} ({x.placement.shaft})",
                             x.drive.motor.name, f"{max(s.peak_torque for s in x.shafts):.4g}"])
            _table(ax, "what each balancing choice costs", ["mode", "RMS force [N]", "RMS moment [N·m]",
                                                            "flywheel [kg·m²]", "flywheel mass [kg]", "motor",
                                                            "peak shaft torque [N·m]"], rows)
            fig.tight_layout()
            pdf.savefig(fig)
            plt.close(fig)
    return buf.getvalue()
