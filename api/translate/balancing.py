"""POST /v1/balancing/*: the balancing specification and weights in; counterweights, rotors and slider-crank
balances out."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

import synth

from api.translate.linkage import counterweight_in, summary_out, warnings_out
from mechsynth_client.schemas.balancing import (
    BALANCE_MODES,
    BalanceChecksOut,
    BalanceIn,
    BalanceOut,
    CorrectionOut,
    CounterRotorOut,
    CounterweightPlacementOut,
    LanchesterOut,
    OptimalBalanceOut,
    RotorIn,
    RotorOut,
    SliderCrankBalanceOut,
    WeightsIn,
)
from mechsynth_client.schemas.common import one_of


def balance_spec(body: BalanceIn) -> synth.CounterweightSpec:
    """Engine counterweight spec (degrees become radians here)."""
    return synth.CounterweightSpec(
        tuple(body.counterweight_links or ()), dict(body.max_radius_m),
        {k: math.radians(v) for k, v in body.angle_deg.items()} or None,
        dict(body.radius_m) or None,
    )


def weights_from(weights: WeightsIn) -> synth.Weights:
    """Engine weights."""
    return synth.Weights(**weights.model_dump())


def balance_out(r: synth.BalanceResult) -> BalanceOut:
    """Schema from an engine result."""
    placements = []
    for cw in r.counterweights:
        props = r.analysis_after.linkage.mass_props(cw.link)
        placements.append(CounterweightPlacementOut(
            link=cw.link, radius_m=float(np.hypot(*cw.position)),
            angle_deg=round(math.degrees(math.atan2(cw.position[1], cw.position[0])), 9) + 0.0,
            link_com_m=list(props.com), link_mass_kg=props.mass,
        ))
    return BalanceOut(
        mode=one_of(BALANCE_MODES, r.mode),
        counterweights=[counterweight_in(c) for c in r.counterweights],
        placements=placements,
        total_added_mass_kg=r.total_added_mass,
        added_inertia_kgm2=r.added_inertia,
        summary_before=summary_out(r.before),
        summary_after=summary_out(r.after),
        checks=BalanceChecksOut(
            residual_shaking_force_N=r.residual_force, residual_shaking_force_rel=r.residual_force_rel,
            residual_shaking_moment_Nm=r.residual_moment, residual_shaking_moment_rel=r.residual_moment_rel,
        ),
        coupler_inertia_kgm2=r.coupler_inertia,
        counter_rotors=None if r.mode != "full" else [
            CounterRotorOut(link=c.link, inertia_kgm2=c.inertia, ratio=c.ratio) for c in r.counter_rotors
        ],
        objective=r.objective,
        weights=None if r.weights is None else WeightsIn(**dataclasses.asdict(r.weights)),
        weight_scale=r.weight_scale,
        warnings=warnings_out(synth.check_balance(r)),
    )


def optimal_balance_out(results: list[synth.BalanceResult]) -> OptimalBalanceOut:
    """The first result is the design for `weights`; the rest are the sweep's points."""
    return OptimalBalanceOut(**balance_out(results[0]).model_dump(),
                             tradeoff=[balance_out(r) for r in results[1:]])


def rotor_from(body: RotorIn) -> list[synth.RotorMass]:
    """Engine masses (degrees become radians here)."""
    return [synth.RotorMass(m.mass_kg, m.radius_m, math.radians(m.angle_deg), m.axial_position_m)
            for m in body.masses]


def rotor_out(r: synth.RotorBalance, warnings: list[synth.DesignWarning] | None = None) -> RotorOut:
    """Schema from an engine result."""
    return RotorOut(
        corrections=[CorrectionOut(mass_kg=c.mass, radius_m=c.radius,
                                   angle_deg=round(math.degrees(c.angle), 9) + 0.0, axial_position_m=c.axial)
                     for c in r.corrections],
        unbalance_before_kgm=r.unbalance_before, moment_unbalance_before_kgm2=r.moment_before,
        residual_unbalance_kgm=r.residual_unbalance, residual_moment_unbalance_kgm2=r.residual_moment,
        warnings=warnings_out(warnings or []),
    )


def slider_crank_balance_out(r: synth.SliderCrankBalance,
                             warnings: list[synth.DesignWarning] | None = None) -> SliderCrankBalanceOut:
    """Schema from an engine result."""
    return SliderCrankBalanceOut(
        rotating_mass_kg=r.rotating_mass, reciprocating_mass_kg=r.reciprocating_mass,
        crank_counterweight=counterweight_in(r.crank_counterweight),
        lanchester=[LanchesterOut(order=p.order, mass_kg=p.mass, radius_m=p.radius, amplitude_N=p.amplitude,
                                  phase_deg=math.degrees(p.phase)) for p in r.pairs],
        balancer_line_y_m=r.balancer_line_y, first_order_amplitude_N=r.first_order_amplitude,
        second_order_amplitude_N=r.second_order_amplitude,
        summary_before=summary_out(r.before),
        residual_shaking_force_N=r.residual, residual_shaking_force_rel=r.residual_rel,
        residual_by_order_N=list(r.residual_by_order),
        residual_shaking_moment_Nm=r.residual_moment, residual_shaking_moment_rel=r.residual_moment_rel,
        balancer_moment_Nm=r.balancer_moment,
        warnings=warnings_out(warnings or []),
    )
