"""POST /v1/analysis: counter-rotors in, the analysis answer out (summaries, checks, friction, instant centres,
path curvature)."""

from __future__ import annotations

import math
from typing import Any
from typing import TypeVar

import numpy as np
from pydantic import BaseModel

import synth

from api.translate.linkage import crank_angles, degree_array, ensure_finite, summary_out, warnings_out
from mechsynth_client.schemas.analysis import (
    AnalysisIn,
    AnalysisOut,
    CentresOut,
    ChecksOut,
    CounterRotorIn,
    CurvatureOut,
    FrictionChecksOut,
    FrictionOut,
    GRASHOF_CLASSES,
    LinkMotionOut,
    PairFrictionOut,
    PointOut,
)
from mechsynth_client.schemas.common import one_of


M = TypeVar("M", bound=BaseModel)


def _unchecked(model: type[M], **values: Any) -> M:
    """``model`` holding the engine's arrays as they are (``api.media.json_bytes`` writes them), unvalidated."""
    return model.model_construct(**values)


def counter_rotor_from(rotor: CounterRotorIn) -> synth.CounterRotor:
    """Engine counter-rotor."""
    return synth.CounterRotor(rotor.link, rotor.inertia_kgm2, rotor.ratio)


def rotors_from(body: AnalysisIn) -> tuple[synth.CounterRotor, ...]:
    """Engine counter-rotors, from this request and its balancing answer."""
    given = [counter_rotor_from(r) for r in body.counter_rotors]
    if body.balancing is not None and body.balancing.counter_rotors:
        given += [counter_rotor_from(r) for r in body.balancing.counter_rotors]
    return tuple(given)


def friction_out(fr: synth.FrictionAnalysis, joints: dict[str, str]) -> FrictionOut:
    """Schema from the engine's friction analysis; ``joints`` gives each pair's kind."""
    ensure_finite(fr.unknowns, fr.driving_torque, fr.loss_torque)
    pairs = {}
    for name, value in fr.friction.items():
        revolute = joints[name] == "revolute"
        pairs[name] = _unchecked(
            PairFrictionOut, kind=one_of(("revolute", "prismatic"), joints[name]),
            friction_moment_Nm=value if revolute else None, friction_force_N=None if revolute else value,
            power_loss_W=fr.power_loss[name], mean_power_loss_W=float(np.mean(fr.power_loss[name])))
    total = sum(fr.power_loss.values(), np.zeros(fr.driving_torque.size))
    return _unchecked(
        FrictionOut, driving_torque_Nm=fr.driving_torque, loss_torque_Nm=fr.loss_torque,
        joint_reactions_N=dict(fr.reactions), prismatic_couples_Nm=dict(fr.couples), pairs=pairs,
        efficiency=[None if not math.isfinite(e) else float(e) for e in fr.efficiency],
        cycle_efficiency=fr.cycle_efficiency, mean_power_loss_W=float(np.mean(total)),
        checks=FrictionChecksOut(newton_residual=fr.residual, newton_iterations=fr.iterations,
                                 virtual_power_max_diff_Nm=fr.power_check))


def analysis_out(an: synth.Analysis, geometry: tuple[bool, bool, bool] = (False, False, False)
                ) -> AnalysisOut:
    """Schema from an engine analysis (radians become degrees here).

    Built without re-validating the engine's arrays (they are float arrays by construction), after one
    check that nothing non-finite would reach the response. The array fields hold the engine's numpy
    arrays as they are: ``api.media.json_bytes`` writes them; ``to_lists`` gives the plain pydantic model.
    """
    m, k, r = an.motion, an.kinetostatics, an.reduced
    ensure_finite(k.unknowns, k.shaking_force, k.shaking_moment, r.inertia, an.virtual_power_torque)
    mech = an.linkage.mechanism
    tau = an.transmission_angle
    return _unchecked(
        AnalysisOut,
        crank_angle_deg=degree_array(m.phi),
        driving_torque_Nm=k.driving_torque,
        virtual_power_torque_Nm=an.virtual_power_torque,
        shaking_force_N=k.shaking_force,
        shaking_moment_Nm=k.shaking_moment,
        reduced_inertia_kgm2=r.inertia,
        reduced_inertia_slope_kgm2_per_rad=r.inertia_slope,
        reduced_load_torque_Nm=r.load_torque,
        kinetic_energy_J=r.kinetic_energy,
        joint_reactions_N={name: v for name, v in k.reactions.items()},
        prismatic_couples_Nm={name: v for name, v in k.couples.items()},
        links={
            name: _unchecked(
                LinkMotionOut,
                angle_deg=degree_array(m.link_angle[name]),
                angular_velocity_rad_s=m.link_omega[name],
                angular_acceleration_rad_s2=m.link_alpha[name],
            )
            for name in mech.topology.links
        },
        points={
            name: _unchecked(
                PointOut,
                position_m=m.point_pos[name],
                velocity_m_s=m.point_vel[name],
                acceleration_m_s2=m.point_acc[name],
            )
            for name in m.point_pos
        },
        transmission_angle_deg=None if tau is None else degree_array(tau),
        grashof=one_of(GRASHOF_CLASSES, mech.grashof) if isinstance(mech, synth.FourBar) else None,
        summary=summary_out(an.summary()),
        checks=ChecksOut.model_construct(
            virtual_power_torque_max_diff_Nm=an.torque_check,
            loop_closure_m=mech.closure_residual(m.point_pos, m.link_angle)
            if isinstance(mech, synth.PlanarLinkage) else None),
        friction=None if an.friction is None else friction_out(
            an.friction, {j.name: j.kind for j in mech.topology.joints}),
        warnings=warnings_out(synth.check_analysis(an)),
        assumptions=list(mech.assumptions()) if isinstance(mech, synth.PlanarLinkage) else [],
        centres=_centres(an, geometry[1]) if geometry[0] else None,
        curvature=_curvature(an) if geometry[2] else None,
    )


def plot_angle(body: AnalysisIn, angle_deg: float | None) -> float:
    """Crank angle [rad] at which to draw the mechanism: the requested one, or the first sample."""
    if angle_deg is not None:
        return math.radians(angle_deg)
    phi = crank_angles(body)
    return 0.0 if phi is None else float(phi[0])


def _centres(an: synth.Analysis, relative: bool) -> CentresOut:
    links = list(an.motion.link_origin)
    coupler = "coupler" if "coupler" in links else None
    c = synth.instant_centres(an.motion, relative, coupler)
    return CentresOut(
        absolute={k: v.tolist() for k, v in c.absolute.items()},
        relative={k: v.tolist() for k, v in c.relative.items()},
        coupler=c.coupler,
        fixed_centrode=None if c.fixed_centrode is None else c.fixed_centrode.tolist(),
        moving_centrode=None if c.moving_centrode is None else c.moving_centrode.tolist(),
        kennedy_check=c.kennedy,
    )


def _curvature(an: synth.Analysis) -> dict[str, CurvatureOut]:
    curvature, stopped = synth.path_curvature(an.motion)
    phi = np.degrees(an.motion.phi)
    return {name: CurvatureOut(curvature_1_m=k.tolist(), stopped_deg=phi[stopped[name]].tolist())
            for name, k in curvature.items()}
