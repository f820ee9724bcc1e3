"""The motor's schema, shared by the flywheel, the machine's foundation and its elastic drive."""

from __future__ import annotations


from pydantic import Field

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
