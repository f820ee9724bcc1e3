"""Worker side of design studies: one variant of a study is one request to a design endpoint, run as that
endpoint runs it and answered as the plain JSON it would send.

:func:`run_endpoint` is a module-level function of plain data (with the endpoint's path and the service limits
bound by ``functools.partial``), so the engine's study runner sends it to a local worker or a Dask worker as it
is. Each endpoint's plan below makes the same engine call as its router.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import partial
from typing import Any

from pydantic import BaseModel, ValidationError

import synth
from synth.errors import InvalidInput

from .media import Render
from .schemas.analysis import AnalysisIn, AnalysisOut
from .schemas.balancing import (
    BalanceIn,
    BalanceOut,
    FullBalanceIn,
    OptimalBalanceIn,
    OptimalBalanceOut,
    RotorIn,
    RotorOut,
    SliderCrankBalanceIn,
    SliderCrankBalanceOut,
)
from .schemas.flywheel import FlywheelIn, FlywheelOut
from .schemas.gearing import DriveIn, DriveOut, SplitIn, SplitOut, TeethIn, TeethOut
from .settings import Settings
from .tasks import flywheel_for_linkage


@dataclass(frozen=True, slots=True)
class Limits:
    """The service limits a variant is run under, the same as a single request's."""

    max_samples: int
    max_stages: int
    solver_time_limit_s: float

    @classmethod
    def from_settings(cls, settings: Settings) -> Limits:
        """The limits of a service instance."""
        return cls(settings.max_samples, settings.max_stages, settings.solver_time_limit_s)


Plan = tuple[Render, Callable[..., Any], tuple[Any, ...], dict[str, Any]]


def _analysis(b: AnalysisIn, lim: Limits) -> Plan:
    return (Render(AnalysisOut.from_engine), synth.analyse, (b.to_linkage(), b.omega_rad_s),
            dict(samples=b.samples, phi=b.phi(), crank_acceleration=b.crank_acceleration_rad_s2,
                 max_samples=lim.max_samples, points=b.trace()))


def _static(b: BalanceIn, lim: Limits) -> Plan:
    return (Render(BalanceOut.from_engine), synth.balance_static, (b.to_linkage(), b.omega_rad_s, b.spec()),
            dict(samples=b.samples, objective=b.objective, mass_budget=b.mass_budget_kg,
                 time_limit_s=lim.solver_time_limit_s))


def _full(b: FullBalanceIn, lim: Limits) -> Plan:
    return (Render(BalanceOut.from_engine), synth.balance_full, (b.to_linkage(), b.omega_rad_s, b.spec()),
            dict(samples=b.samples, ratios=b.rotor_ratios, time_limit_s=lim.solver_time_limit_s))


def _optimal(b: OptimalBalanceIn, lim: Limits) -> Plan:
    weight_sets = [w.to_engine() for w in [b.weights, *b.sweep]]
    return (Render(OptimalBalanceOut.from_results), synth.tradeoff,
            (b.to_linkage(), b.omega_rad_s, b.spec(), weight_sets),
            dict(mass_budget=b.mass_budget_kg, samples=b.samples, time_limit_s=lim.solver_time_limit_s))


def _rotor(b: RotorIn, lim: Limits) -> Plan:
    if b.mode == "static":
        return (Render(RotorOut.from_engine), synth.balance_rotor_static,
                (b.to_engine(), b.correction_radius_m, b.correction_plane_m), {})
    return (Render(RotorOut.from_engine), synth.balance_rotor_dynamic,
            (b.to_engine(), (b.planes_m[0], b.planes_m[1]), (b.radii_m[0], b.radii_m[1])), {})


def _slider_crank(b: SliderCrankBalanceIn, lim: Limits) -> Plan:
    return (Render(SliderCrankBalanceOut.from_engine), synth.balance_slider_crank, (b.to_linkage(), b.omega_rad_s),
            dict(counterweight_radius=b.counterweight_radius_m,
                 balancer_radii=(b.balancer_radii_m[0], b.balancer_radii_m[1]), orders=b.orders,
                 samples=b.samples))


def _flywheel(b: FlywheelIn, lim: Limits) -> Plan:
    mean_speed, delta = b.mean_speed(), b.target_delta()
    sizing = dict(constant_inertia=b.constant_inertia_kgm2, motor=None if b.motor is None else b.motor.to_engine(),
                  geometry=None if b.geometry is None else b.geometry.to_engine(),
                  time_limit_s=lim.solver_time_limit_s)
    if b.uses_tables():
        assert b.tables is not None
        return (Render(FlywheelOut.from_engine), synth.size_flywheel,
                (b.tables.to_cycle(b.cycle_deg, lim.max_samples), mean_speed, delta), sizing)
    return (Render(FlywheelOut.from_engine), flywheel_for_linkage,
            (b.to_linkage(), mean_speed, b.samples, lim.max_samples, delta), sizing)


def _split(b: SplitIn, lim: Limits) -> Plan:
    stages = synth.make_stages(b.stage_specs(), max_stages=lim.max_stages)
    return (Render(SplitOut.from_engine, model_extra=(stages,)), synth.split_ratio, (b.ratio(), stages, b.objective),
            dict(inertia=b.inertia_model(b.motor_inertia_kgm2), input_torque=b.input_torque_Nm,
                 handbook_factor=b.handbook_factor, snap_r20=b.snap_r20, snap_tolerance=b.snap_tolerance,
                 time_limit_s=lim.solver_time_limit_s))


def _teeth(b: TeethIn, lim: Limits) -> Plan:
    stages = synth.make_stages(b.stage_specs(), max_stages=lim.max_stages)
    return (Render(TeethOut.from_engine), synth.tooth_numbers, (b.total_ratio, stages, b.rules(), b.tolerance), {})


def _drive(b: DriveIn, lim: Limits) -> Plan:
    stages = synth.make_stages(b.stage_specs(), max_stages=lim.max_stages)
    return (Render(DriveOut.from_engine, model_extra=(stages,)), synth.design_drive,
            (b.output_power_W, b.output_speed(), stages),
            dict(reserve_factor=b.reserve_factor, drive_efficiency=b.drive_efficiency,
                 synchronous_speed=b.synchronous_speed(), motor=b.motor, objective=b.objective,
                 torque_basis=b.torque_basis, inertia=b.inertia_model(), snap_r20=b.snap_r20,
                 snap_tolerance=b.snap_tolerance, time_limit_s=lim.solver_time_limit_s))


# Design endpoints a study may vary: path -> (request schema, plan of the engine call).
ENDPOINTS: dict[str, tuple[type[BaseModel], Callable[[Any, Limits], Plan]]] = {
    "/v1/analysis": (AnalysisIn, _analysis),
    "/v1/balancing/static": (BalanceIn, _static),
    "/v1/balancing/full": (FullBalanceIn, _full),
    "/v1/balancing/optimal": (OptimalBalanceIn, _optimal),
    "/v1/balancing/rotor": (RotorIn, _rotor),
    "/v1/balancing/slider-crank": (SliderCrankBalanceIn, _slider_crank),
    "/v1/flywheel": (FlywheelIn, _flywheel),
    "/v1/gears/split": (SplitIn, _split),
    "/v1/gears/teeth": (TeethIn, _teeth),
    "/v1/gears/drive": (DriveIn, _drive),
}


def validate_request(endpoint: str, request: Mapping[str, Any], field: str = "") -> BaseModel:
    """The endpoint's request model of ``request``, parsed as the endpoint parses its JSON body; a bad field is
    :class:`InvalidInput` naming it (prefixed with ``field``)."""
    if endpoint not in ENDPOINTS:
        raise InvalidInput(f"{endpoint!r} is not a design endpoint a study can vary; one of {sorted(ENDPOINTS)}",
                           field="endpoint")
    try:
        return ENDPOINTS[endpoint][0].model_validate_json(json.dumps(request))
    except ValidationError as exc:
        err = exc.errors()[0]
        name = ".".join(str(p) for p in (field, *err.get("loc", ())) if p != "")
        raise InvalidInput(f"{name}: {err.get('msg', 'invalid')}", field=name) from None


def run_endpoint(endpoint: str, limits: Limits, request: dict[str, Any]) -> dict[str, Any]:
    """One variant: validate ``request`` as ``endpoint`` does, run its engine call, answer with its JSON."""
    body = validate_request(endpoint, request)
    render, fn, args, kwargs = ENDPOINTS[endpoint][1](body, limits)
    content, _ = render(fn(*args, **kwargs))
    answer: dict[str, Any] = json.loads(content)
    return answer


def variant_function(endpoint: str, limits: Limits) -> Callable[[dict[str, Any]], dict[str, Any]]:
    """The picklable ``variant_fn(request) -> answer`` of one endpoint."""
    return partial(run_endpoint, endpoint, limits)
