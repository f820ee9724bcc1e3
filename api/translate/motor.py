"""An induction motor's data as the engine's motor model."""

from __future__ import annotations

import math

import synth

from mechsynth_client.schemas.motor import MotorIn


def motor_from(motor_in: MotorIn) -> synth.Motor:
    """Engine motor; rev/min become rad/s here."""
    points = (motor_in.synchronous_speed_rpm, motor_in.rated_speed_rpm, motor_in.rated_torque_Nm)
    if motor_in.name is not None:
        if any(p is not None for p in points):
            raise synth.InvalidInput("name a catalogue motor or give its characteristic, not both",
                                     field="motor.name")
        motor = synth.Motor.from_catalogue(synth.find_motor(motor_in.name), motor_in.gear_ratio, motor_in.efficiency)
        return synth.Motor(
            motor.synchronous_speed, motor.rated_speed, motor.rated_torque, motor.gear_ratio, motor.efficiency,
            motor.rotor_inertia if motor_in.rotor_inertia_kgm2 is None else motor_in.rotor_inertia_kgm2,
            motor.breakdown_torque if motor_in.breakdown_torque_Nm is None else motor_in.breakdown_torque_Nm,
        )
    if any(p is None for p in points):
        raise synth.InvalidInput("give the motor's name from the catalogue (GET /v1/gears/motors), or all of "
                                 "synchronous_speed_rpm, rated_speed_rpm and rated_torque_Nm", field="motor")
    sync, rated, torque = (float(p) for p in points if p is not None)
    return synth.Motor(
        synchronous_speed=sync * math.pi / 30,
        rated_speed=rated * math.pi / 30,
        rated_torque=torque,
        gear_ratio=motor_in.gear_ratio,
        efficiency=motor_in.efficiency,
        rotor_inertia=motor_in.rotor_inertia_kgm2 or 0.0,
        breakdown_torque=motor_in.breakdown_torque_Nm,
    )
