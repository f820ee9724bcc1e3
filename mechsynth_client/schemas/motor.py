"""The motor's schema, shared by the flywheel, the machine's foundation and its elastic drive."""

from __future__ import annotations

import math

from pydantic import Field

from ._engine import synth
from .common import StrictModel


class MotorIn(StrictModel):
    """Induction motor with a linear static characteristic from synchronous speed to the rated point.

    Name a catalogue motor (``name``, see GET /v1/gears/motors): its rated power, speeds, rotor inertia and
    breakdown torque give the characteristic, the one motor model of the drive and machine endpoints. Or give
    the characteristic's points directly (``synchronous_speed_rpm``, ``rated_speed_rpm``, ``rated_torque_Nm``).
    """

    name: str | None = Field(None, min_length=1, max_length=80,
                             description="A catalogue motor (GET /v1/gears/motors) instead of the three points.")
    synchronous_speed_rpm: float | None = Field(None, gt=0, le=1e5, description="Speed at zero torque [rev/min].")
    rated_speed_rpm: float | None = Field(None, gt=0, le=1e5, description="Speed at the rated torque [rev/min].")
    rated_torque_Nm: float | None = Field(None, gt=0, le=1e9, description="Rated torque on the motor shaft [N·m].")
    gear_ratio: float = Field(1.0, ge=1e-4, le=1e5, description="Motor speed over crank speed [-].")
    efficiency: float = Field(1.0, gt=0, le=1, description="Efficiency of the gearing [-].")
    rotor_inertia_kgm2: float | None = Field(None, ge=0, le=1e9,
                                             description="Rotor inertia on the motor shaft [kg·m²]; default 0, or "
                                             "the catalogue's.")
    breakdown_torque_Nm: float | None = Field(None, gt=0, le=1e9, description="Largest torque of the linear branch "
                                              "[N·m]; default unbounded, or the catalogue's.")

    def to_engine(self) -> synth.Motor:
        """Engine motor; rev/min become rad/s here."""
        points = (self.synchronous_speed_rpm, self.rated_speed_rpm, self.rated_torque_Nm)
        if self.name is not None:
            if any(p is not None for p in points):
                raise synth.InvalidInput("name a catalogue motor or give its characteristic, not both",
                                         field="motor.name")
            motor = synth.Motor.from_catalogue(synth.find_motor(self.name), self.gear_ratio, self.efficiency)
            return synth.Motor(
                motor.synchronous_speed, motor.rated_speed, motor.rated_torque, motor.gear_ratio, motor.efficiency,
                motor.rotor_inertia if self.rotor_inertia_kgm2 is None else self.rotor_inertia_kgm2,
                motor.breakdown_torque if self.breakdown_torque_Nm is None else self.breakdown_torque_Nm,
            )
        if any(p is None for p in points):
            raise synth.InvalidInput("give the motor's name from the catalogue (GET /v1/gears/motors), or all of "
                                     "synchronous_speed_rpm, rated_speed_rpm and rated_torque_Nm", field="motor")
        sync, rated, torque = (float(p) for p in points if p is not None)
        return synth.Motor(
            synchronous_speed=sync * math.pi / 30,
            rated_speed=rated * math.pi / 30,
            rated_torque=torque,
            gear_ratio=self.gear_ratio,
            efficiency=self.efficiency,
            rotor_inertia=self.rotor_inertia_kgm2 or 0.0,
            breakdown_torque=self.breakdown_torque_Nm,
        )
