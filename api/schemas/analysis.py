"""Schemas of POST /v1/analysis."""

from __future__ import annotations

import math
from typing import Literal, get_args

from pydantic import BaseModel, ConfigDict, Field

from ._engine import np, synth
from .common import FOURBAR_EXAMPLE, LinkageRequest, StrictModel, SummaryOut, Vec2, ensure_finite, one_of


class TracePointIn(StrictModel):
    """A named point fixed in a link (a coupler point, a tool tip) whose motion is reported."""

    name: str = Field(min_length=1, max_length=40, description="Name of the point in the answer's `points`.",
                      examples=["coupler_point"])
    link: str = Field(description="Link the point is fixed in, by name.", examples=["coupler"])
    position_m: Vec2 = Field(description="Position in the link frame [m].", examples=[[0.175, 0.08]])


class AnalysisIn(LinkageRequest):
    """A linkage, its speed, loads and optional counterweights, to analyse over one crank revolution."""

    trace_points: list[TracePointIn] = Field(
        default_factory=list, max_length=20, description="Extra points to report, e.g. coupler points."
    )

    def trace(self) -> dict[str, tuple[str, tuple[float, float]]]:
        """Trace points as the engine takes them: name -> (link, position in the link frame)."""
        return {p.name: (p.link, (p.position_m[0], p.position_m[1])) for p in self.trace_points}

    model_config = ConfigDict(
        json_schema_extra={
            "examples": [
                {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 360},
                {
                    "mechanism": {
                        "type": "slotted_lever",
                        "crank_length_m": 0.1,
                        "ground_length_m": 0.3,
                        "rocker_length_m": 0.6,
                        "ram_height_m": 0.7,
                        "links": {
                            "crank": {"mass_kg": 5.0},
                            "rocker": {"mass_kg": 10.0, "com_m": [0.25, 0.0], "inertia_kgm2": 0.3},
                            "ram": {"mass_kg": 12.0},
                        },
                    },
                    "speed_rpm": 38.197,
                    "gravity": {"g_m_s2": 9.81},
                    "loads": [{"type": "window", "force_N": 1200, "start_deg": -60, "end_deg": 60, "point_m": [0, -0.1]}],
                },
            ]
        }
    )


Grashof = Literal["crank-rocker", "double-crank", "double-rocker", "rocker-crank", "change-point", "triple-rocker"]
GRASHOF_CLASSES: tuple[Grashof, ...] = get_args(Grashof)


class PointOut(BaseModel):
    """A point's position [m], velocity [m/s] and acceleration [m/s²] at every sample, as [x, y] pairs."""

    position_m: list[list[float]]
    velocity_m_s: list[list[float]]
    acceleration_m_s2: list[list[float]]


class LinkMotionOut(BaseModel):
    """A link's angle [deg], angular velocity [rad/s] and angular acceleration [rad/s²] at every sample."""

    angle_deg: list[float]
    angular_velocity_rad_s: list[float]
    angular_acceleration_rad_s2: list[float]


class ChecksOut(BaseModel):
    """Independent check figures carried with the result."""

    virtual_power_torque_max_diff_Nm: float = Field(
        description="Largest difference between the kinetostatic and the virtual-power driving torque."
    )


class AnalysisOut(BaseModel):
    """Kinematics and kinetostatics over the cycle; reactions are forces of a joint's first link on its second."""

    crank_angle_deg: list[float]
    driving_torque_Nm: list[float]
    virtual_power_torque_Nm: list[float]
    shaking_force_N: list[list[float]]
    shaking_moment_Nm: list[float]
    reduced_inertia_kgm2: list[float]
    reduced_inertia_slope_kgm2_per_rad: list[float]
    reduced_load_torque_Nm: list[float]
    kinetic_energy_J: list[float]
    joint_reactions_N: dict[str, list[list[float]]]
    prismatic_couples_Nm: dict[str, list[float]]
    links: dict[str, LinkMotionOut]
    points: dict[str, PointOut]
    transmission_angle_deg: list[float] | None = None
    grashof: Grashof | None = Field(None, description="Grashof class of a four-bar; null for other mechanisms.")
    summary: SummaryOut
    checks: ChecksOut

    @classmethod
    def from_engine(cls, an: synth.Analysis) -> AnalysisOut:
        """Schema from an engine analysis (radians become degrees here).

        Built without re-validating the engine's arrays (they are float arrays by construction), after one
        check that nothing non-finite would reach the response.
        """
        m, k, r = an.motion, an.kinetostatics, an.reduced
        ensure_finite(k.unknowns, k.shaking_force, k.shaking_moment, r.inertia, an.virtual_power_torque)
        mech = an.linkage.mechanism
        tau = an.transmission_angle
        return cls.model_construct(
            crank_angle_deg=np.degrees(m.phi).tolist(),
            driving_torque_Nm=k.driving_torque.tolist(),
            virtual_power_torque_Nm=an.virtual_power_torque.tolist(),
            shaking_force_N=k.shaking_force.tolist(),
            shaking_moment_Nm=k.shaking_moment.tolist(),
            reduced_inertia_kgm2=r.inertia.tolist(),
            reduced_inertia_slope_kgm2_per_rad=r.inertia_slope.tolist(),
            reduced_load_torque_Nm=r.load_torque.tolist(),
            kinetic_energy_J=r.kinetic_energy.tolist(),
            joint_reactions_N={name: v.tolist() for name, v in k.reactions.items()},
            prismatic_couples_Nm={name: v.tolist() for name, v in k.couples.items()},
            links={
                name: LinkMotionOut.model_construct(
                    angle_deg=np.degrees(m.link_angle[name]).tolist(),
                    angular_velocity_rad_s=m.link_omega[name].tolist(),
                    angular_acceleration_rad_s2=m.link_alpha[name].tolist(),
                )
                for name in mech.topology.links
            },
            points={
                name: PointOut.model_construct(
                    position_m=m.point_pos[name].tolist(),
                    velocity_m_s=m.point_vel[name].tolist(),
                    acceleration_m_s2=m.point_acc[name].tolist(),
                )
                for name in m.point_pos
            },
            transmission_angle_deg=None if tau is None else np.degrees(tau).tolist(),
            grashof=one_of(GRASHOF_CLASSES, mech.grashof) if isinstance(mech, synth.FourBar) else None,
            summary=SummaryOut.from_engine(an.summary()),
            checks=ChecksOut.model_construct(virtual_power_torque_max_diff_Nm=an.torque_check),
        )


def plot_angle(body: AnalysisIn, angle_deg: float | None) -> float:
    """Crank angle [rad] at which to draw the mechanism: the requested one, or the first sample."""
    if angle_deg is not None:
        return math.radians(angle_deg)
    phi = body.phi()
    return 0.0 if phi is None else float(phi[0])
