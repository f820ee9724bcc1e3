"""POST /v1/balancing/engine: the multi-cylinder engine in, its orders and balance out."""

from __future__ import annotations

import math

import synth

from mechsynth_client.schemas.engines import EngineIn, EngineOut, OrderOut


def engine_from(body: EngineIn) -> synth.EngineSpec:
    """Engine spec; degrees become radians, rev/min rad/s."""
    given = [x is not None for x in (body.arrangement, body.cylinders, body.firing_order)]
    if sum(given) != 1:
        raise synth.InvalidInput("give one of arrangement, cylinders or firing_order", field="cylinders")
    if body.arrangement is not None:
        cylinders = synth.engine_layout(body.arrangement, body.pitch_m)
    elif body.firing_order is not None:
        cylinders = synth.inline_from_firing_order(body.firing_order, body.pitch_m, body.strokes)
    else:
        cylinders = tuple(synth.Cylinder(math.radians(c.crank_angle_deg), math.radians(c.bank_angle_deg),
                                         c.axial_position_m) for c in body.cylinders or [])
    return synth.EngineSpec(body.crank_radius_m, body.rod_length_m, body.reciprocating_mass_kg,
                            body.rotating_mass_kg, body.speed_rpm * math.pi / 30, cylinders, body.orders,
                            body.reference_z_m)


def order_out(o: synth.OrderShaking, tol: float) -> OrderOut:
    """Schema from one engine order."""
    return OrderOut(order=o.order, largest=o.largest, smallest=o.smallest, forward=abs(o.forward),
                    backward=abs(o.backward), balanced=o.largest <= tol, forward_mass_radius=o.forward_mr,
                    forward_angle_deg=math.degrees(o.forward_angle), backward_mass_radius=o.backward_mr,
                    backward_angle_deg=math.degrees(o.backward_angle))


def engine_out(r: synth.EngineShaking) -> EngineOut:
    """Schema from the engine result."""
    tol = r.balanced_tolerance
    span = max(1.0, max(c.axial_position for c in r.spec.cylinders) - min(c.axial_position
                                                                          for c in r.spec.cylinders))
    return EngineOut(
        cylinders=len(r.spec.cylinders), speed_rad_s=r.spec.speed, reference_z_m=r.reference_z,
        force_orders=[order_out(o, tol) for o in r.force_orders],
        moment_orders=[order_out(o, tol * span) for o in r.moment_orders],
        largest_force_N=float(max(abs(complex(*f)) for f in r.force)),
        largest_moment_Nm=float(max(abs(complex(*m)) for m in r.moment)),
        reconstruction_error_N=r.reconstruction_error, residual_force_N=r.residual_force,
        residual_moment_Nm=r.residual_moment, remaining_force_N=r.remaining_force,
        remaining_moment_Nm=r.remaining_moment,
    )
