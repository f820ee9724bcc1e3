"""Schemas of the machine on its foundation: POST /v1/machines/isolation and /v1/machines/isolation/design."""

from __future__ import annotations

import importlib
import math
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, JsonValue
from pydantic.config import JsonDict

from .analysis import AnalysisIn
from .motor import MotorIn
from ._engine import np
from .common import (
    MAX_INERTIA_KGM2,
    MAX_MASS_KG,
    StrictModel,
    ValidityCheckOut,
    Vec2,
    WarningOut,
    degree_array,
    ensure_finite,
    validity_out,
    warnings_out,
)

#: Stiffness beyond any isolator or foundation bolt [N/m]; a larger value is a typo.
MAX_STIFFNESS_N_M = 1e13
MAX_DAMPING_NS_M = 1e10
MAX_ISOLATORS = 64


def _engine() -> Any:
    """The foundation module of the engine, imported on first use (the schemas load without the engine)."""
    return importlib.import_module("synth.machine.foundation")


COMPRESSOR_EXAMPLE: JsonDict = {
    "type": "slider_crank", "crank_length_m": 0.06, "rod_length_m": 0.24,
    "links": {"crank": {"mass_kg": 3, "com_m": [0.02, 0], "inertia_kgm2": 0.004},
              "rod": {"mass_kg": 4, "com_m": [0.08, 0], "inertia_kgm2": 0.03}, "slider": {"mass_kg": 9}},
}
FRAME_EXAMPLE: JsonDict = {"mass_kg": 400, "inertia_kgm2": 60, "centre_m": [0.1, -0.25]}
ISOLATORS_EXAMPLE: list[JsonValue] = [
    {"position_m": [-0.3, -0.5], "kx_N_m": 5e4, "ky_N_m": 1e5, "damping_ratio": 0.08},
    {"position_m": [0.5, -0.5], "kx_N_m": 5e4, "ky_N_m": 1e5, "damping_ratio": 0.08},
]


class FrameIn(StrictModel):
    """The machine as one rigid body on its isolators: the bed with everything on it, the linkage's links too."""

    mass_kg: float = Field(gt=0, le=MAX_MASS_KG, description="Mass of the whole machine [kg].", examples=[400])
    inertia_kgm2: float = Field(gt=0, le=MAX_INERTIA_KGM2, description="Inertia about its centre of mass, about "
                                "z [kg·m²].", examples=[60])
    centre_m: Vec2 = Field(description="Its centre of mass in the linkage's coordinates (crank pivot at the origin, "
                           "y up) [m].", examples=[[0.1, -0.25]])

    def to_engine(self) -> Any:
        """Engine frame."""
        return _engine().Frame(self.mass_kg, self.inertia_kgm2, (self.centre_m[0], self.centre_m[1]))


class IsolatorIn(StrictModel):
    """One isolator: where it holds the frame, its stiffness along x and y, its damping as coefficients or as a
    ratio of the mass it carries."""

    position_m: Vec2 = Field(description="Where it holds the frame, in the linkage's coordinates [m].",
                             examples=[[-0.3, -0.5]])
    kx_N_m: float = Field(ge=0, le=MAX_STIFFNESS_N_M, description="Stiffness along x [N/m].", examples=[2e5])
    ky_N_m: float = Field(ge=0, le=MAX_STIFFNESS_N_M, description="Stiffness along y [N/m].", examples=[4e5])
    cx_Ns_m: float = Field(0.0, ge=0, le=MAX_DAMPING_NS_M, description="Damping coefficient along x [N·s/m].")
    cy_Ns_m: float = Field(0.0, ge=0, le=MAX_DAMPING_NS_M, description="Damping coefficient along y [N·s/m].")
    damping_ratio: float | None = Field(
        None, ge=0, le=10, description="Damping as a ratio instead of coefficients [-]: c = 2·ζ·sqrt(k·m_share) "
        "along x and y, m_share the machine's mass times this isolator's part of the summed vertical stiffness.",
        examples=[0.08])

    def to_engine(self) -> Any:
        """Engine isolator."""
        return _engine().Isolator((self.position_m[0], self.position_m[1]), self.kx_N_m, self.ky_N_m,
                                  self.cx_Ns_m, self.cy_Ns_m, self.damping_ratio)


class RunUpIn(StrictModel):
    """The drive that runs the machine up from rest, for the frame's passage through resonance."""

    motor: MotorIn = Field(description="The motor through its train (gear ratio, efficiency); a starting torque "
                           "comes with a catalogue motor.")
    constant_inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Rotor, train and flywheel "
                                         "reduced to the crank [kg·m²].")


class IsolationIn(AnalysisIn):
    """A linkage at its crank speed, and the machine's frame on isolators: the linkage's shaking force and
    moment over the steady cycle drive the frame."""

    frame: FrameIn = Field(description="The machine as a rigid body.")
    isolators: list[IsolatorIn] = Field(max_length=MAX_ISOLATORS, description="The isolators under the frame "
                                        "(enough to hold x, y and rotation).")
    run_up: RunUpIn | None = Field(None, description="Also follow the frame while the machine runs up from rest "
                                   "(the start-up simulation's speed history).")

    def run_up_engine(self) -> tuple[Any, float] | None:
        """Engine motor and constant inertia of the run-up, or None."""
        if self.run_up is None:
            return None
        return self.run_up.motor.to_engine(), self.run_up.constant_inertia_kgm2

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"mechanism": COMPRESSOR_EXAMPLE, "speed_rpm": 480, "samples": 360, "frame": FRAME_EXAMPLE,
         "isolators": ISOLATORS_EXAMPLE},
    ]})

    def to_frame(self) -> tuple[Any, tuple[Any, ...]]:
        """Engine frame and isolators."""
        return self.frame.to_engine(), tuple(i.to_engine() for i in self.isolators)


Objective = Literal["amplitude", "force"]


class IsolationDesignIn(AnalysisIn):
    """A linkage at its crank speed and the machine's frame: choose one isolator type for the given positions
    (and optionally an inertia block under the frame's centre)."""

    frame: FrameIn = Field(description="The machine as a rigid body, without the block.")
    positions_m: list[Vec2] = Field(min_length=1, max_length=MAX_ISOLATORS, description="Where the isolators hold "
                                    "the frame, in the linkage's coordinates [m].")
    objective: Objective = Field(description="`amplitude`: the least frame amplitude with the peak force to the "
                                 "foundation under `max_force_N`; `force`: the least peak force with the amplitude "
                                 "under `max_amplitude_m`.")
    max_force_N: float | None = Field(None, gt=0, le=1e12, description="Limit of the peak force to the foundation "
                                      "[N].")
    max_amplitude_m: float | None = Field(None, gt=0, le=10, description="Limit of the frame's amplitude: the "
                                          "largest movement of its centre or an isolator point [m].")
    stiffness_ratio: float = Field(1.0, gt=0, le=1e3, description="k_x over k_y of the isolator type [-].")
    min_stiffness_N_m: float = Field(1e3, gt=0, le=MAX_STIFFNESS_N_M, description="Least k_y of an isolator [N/m].")
    max_stiffness_N_m: float = Field(1e8, gt=0, le=MAX_STIFFNESS_N_M, description="Largest k_y [N/m].")
    min_damping_ratio: float = Field(0.02, ge=0, le=2, description="Least damping ratio [-].")
    max_damping_ratio: float = Field(0.3, ge=0, le=2, description="Largest damping ratio [-].")
    max_static_deflection_m: float | None = Field(None, gt=0, le=10, description="Largest deflection under the "
                                                  "machine's weight [m].")
    max_block_mass_kg: float = Field(0.0, ge=0, le=MAX_MASS_KG, description="Largest inertia block under the "
                                     "frame's centre [kg]; 0: none.")
    block_radius_m: float | None = Field(None, gt=0, le=1e3, description="The block's radius of gyration [m]; "
                                         "default the frame's.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"mechanism": COMPRESSOR_EXAMPLE, "speed_rpm": 480, "samples": 360, "frame": FRAME_EXAMPLE,
         "positions_m": [[-0.3, -0.5], [0.5, -0.5]], "objective": "amplitude", "max_force_N": 600,
         "max_static_deflection_m": 0.02, "max_block_mass_kg": 400},
    ]})

    def to_spec(self) -> Any:
        """Engine design spec."""
        return importlib.import_module("synth.machine.foundation_design").IsolationDesignSpec(
            tuple((p[0], p[1]) for p in self.positions_m), self.objective, self.max_force_N, self.max_amplitude_m,
            self.stiffness_ratio, self.min_stiffness_N_m, self.max_stiffness_N_m, self.min_damping_ratio,
            self.max_damping_ratio, self.max_static_deflection_m, self.max_block_mass_kg, self.block_radius_m)


class RunUpOut(BaseModel):
    """The frame while the machine runs up from rest."""

    time_s: list[float] = Field(description="Output times [s].")
    crank_speed_rpm: list[float] = Field(description="Crank speed at those times [rev/min].")
    amplitude_m: list[float] = Field(description="Displacement magnitude of the frame's centre [m].")
    peak_amplitude_m: float = Field(description="The largest, on the way up or just after [m].")
    peak_time_s: float = Field(description="When [s].")
    peak_speed_rpm: float = Field(description="Crank speed then [rev/min].")
    steady_amplitude_m: float = Field(description="The steady cycle's peak at the speed the run-up "
                                      "ends at (the motor's) [m].")
    ratio: float | None = Field(description="Peak over steady [-]; null when the steady cycle stands still (no "
                                "shaking).")
    crossed_frequencies_Hz: list[float] = Field(description="Natural frequencies some harmonic passed through.")


class ModeOut(BaseModel):
    """One natural mode of the frame on its isolators."""

    frequency_Hz: float = Field(description="Undamped natural frequency [Hz].")
    shape_x_m: float = Field(description="Mode shape: the centre's x, scaled so that the largest of |x|, |y| and "
                             "|θ|·ρ (ρ the radius of gyration) is 1 [m].")
    shape_y_m: float = Field(description="Mode shape: the centre's y [m].")
    shape_theta_rad: float = Field(description="Mode shape: rotation about the centre [rad].")
    damping_ratio: float = Field(description="From the damped eigenvalue λ: -Re λ / |λ| [-].")


class HarmonicOut(BaseModel):
    """One harmonic of the steady cycle: what the linkage shakes with and what the foundation feels."""

    order: int = Field(description="Multiple of the crank speed.")
    frequency_Hz: float = Field(description="[Hz].")
    shaking_force_N: float = Field(description="Amplitude of the shaking force, |(F_x, F_y)| of the complex "
                                   "amplitudes [N].")
    shaking_moment_Nm: float = Field(description="Amplitude of the shaking moment about the frame's centre [N·m].")
    transmitted_force_N: float = Field(description="Amplitude of the force passed to the foundation [N].")
    transmitted_moment_Nm: float = Field(description="Amplitude of the moment passed, about the frame's centre "
                                         "[N·m].")
    force_transmissibility: float | None = Field(description="Transmitted over shaking force [-]; null where the "
                                                 "shaking force has no such harmonic.")
    moment_transmissibility: float | None = Field(description="Transmitted over shaking moment [-]; null where "
                                                  "the shaking moment has no such harmonic.")


class IsolatorLoadOut(BaseModel):
    """What one isolator passes to the foundation."""

    force_N: list[list[float]] = Field(description="Force on the foundation at every crank angle, [F_x, F_y] [N].")
    peak_force_N: float = Field(description="Largest magnitude over the cycle [N].")
    static_deflection_m: list[float] = Field(description="Compression under the machine's weight (y down), "
                                             "[x, y] [m].")
    static_load_N: list[float] = Field(description="Load under the machine's weight, compression positive, "
                                       "[x, y] [N].")


class IsolationChecksOut(BaseModel):
    """The harmonic answer against an independent time integration of the same equations."""

    max_displacement_diff_m: float = Field(description="Largest difference in the centre's displacement [m].")
    max_rotation_diff_rad: float = Field(description="Largest difference in the rotation [rad].")
    max_force_diff_N: float = Field(description="Largest difference in the force to the foundation [N].")
    relative_diff: float = Field(description="The largest of those over the harmonic answer's peak [-].")
    series_residual: float = Field(description="The harmonics kept against the analysis' samples, largest "
                                   "difference over the largest force or moment [-].")
    method: str = Field(description="How the time integration ran.")


class IsolationOut(BaseModel):
    """The frame's steady motion on its isolators and what the foundation feels over one cycle."""

    crank_angle_deg: list[float] = Field(description="Crank angle at every sample [deg].")
    time_s: list[float] = Field(description="Time from the first sample at the constant crank speed [s].")
    displacement_m: list[list[float]] = Field(description="The frame centre's displacement [x, y] at every sample [m].")
    rotation_rad: list[float] = Field(description="The frame's rotation at every sample, counter-clockwise [rad].")
    force_N: list[list[float]] = Field(description="Force passed to the foundation by all isolators, as the "
                                       "foundation feels "
                         "it, [F_x, F_y] at every sample [N] (the weight left out).")
    moment_Nm: list[float] = Field(description="Moment of those forces about the crank pivot O at every sample [N·m].")
    shaking_force_N: list[list[float]] = Field(description="The linkage's shaking force: what a frame bolted "
                                               "rigidly to the "
                                 "foundation would pass on [N].")
    shaking_moment_Nm: list[float] = Field(description="The linkage's shaking moment about O [N·m].")
    isolators: list[IsolatorLoadOut] = Field(description="Per isolator, in the request's order.")
    modes: list[ModeOut] = Field(description="The three natural modes, lowest first.")
    harmonics: list[HarmonicOut] = Field(description="The harmonics kept (those at least 1e-7 of the largest), "
                                         "lowest first.")
    peak_displacement_m: float = Field(description="Largest displacement of the frame's centre [m].")
    peak_rotation_rad: float = Field(description="Largest rotation [rad].")
    peak_isolator_displacement_m: float = Field(description="Largest movement of any isolator point [m].")
    peak_force_N: float = Field(description="Largest magnitude of the force to the foundation [N].")
    peak_moment_Nm: float = Field(description="Largest magnitude of its moment about O [N·m].")
    peak_shaking_force_N: float = Field(description="Largest magnitude of the shaking force [N].")
    force_ratio: float = Field(description="Peak force to the foundation over peak shaking force [-]: below 1 the "
                               "isolators help.")
    settle_time_s: float | None = Field(description="Time for a start's transient to fall to 1 % (the slowest "
                                        "mode's decay) [s]; null without damping.")
    checks: IsolationChecksOut = Field(description="The harmonic answer against an independent time integration.")
    run_up: RunUpOut | None = Field(None, description="The run-up, when the request asks for it.")
    warnings: list[WarningOut] = Field(default_factory=list, description="Where the model stops: "
                                       "transmissibility_high, frequency_ratio_low, resonance_damping_low, "
                                       "isolator_in_tension, isolator_lift_off.")
    validity: list[ValidityCheckOut] = Field(default_factory=list, description="Each condition the model needs "
                                             "against its limit.")

    @classmethod
    def from_engine(cls, r: Any) -> IsolationOut:
        """Schema from an engine isolation."""
        iso = [IsolatorLoadOut.model_construct(force_N=r.isolator_force[i],
                                               peak_force_N=float(r.peak_isolator_force[i]),
                               static_deflection_m=[float(v) for v in r.static_deflection[i]],
                               static_load_N=[float(v) for v in r.static_load[i]])
               for i in range(len(r.isolators))]
        c = r.check
        ensure_finite(r.displacement, r.rotation, r.force, r.moment, r.isolator_force)
        values: dict[str, Any] = dict(
            crank_angle_deg=degree_array(r.phi), time_s=r.time, displacement_m=r.displacement,
            rotation_rad=r.rotation, force_N=r.force, moment_Nm=r.moment, shaking_force_N=r.shaking_force,
            shaking_moment_Nm=r.shaking_moment, isolators=iso,
            modes=[ModeOut(frequency_Hz=m.frequency, shape_x_m=m.shape[0], shape_y_m=m.shape[1],
                           shape_theta_rad=m.shape[2], damping_ratio=m.damping_ratio) for m in r.modes],
            harmonics=[HarmonicOut(order=h.order, frequency_Hz=h.frequency, shaking_force_N=h.shaking_force,
                                   shaking_moment_Nm=h.shaking_moment, transmitted_force_N=h.transmitted_force,
                                   transmitted_moment_Nm=h.transmitted_moment,
                                   force_transmissibility=h.force_transmissibility,
                                   moment_transmissibility=h.moment_transmissibility) for h in r.harmonics],
            peak_displacement_m=r.peak_displacement, peak_rotation_rad=r.peak_rotation,
            peak_isolator_displacement_m=r.peak_isolator_displacement, peak_force_N=r.peak_force,
            peak_moment_Nm=r.peak_moment, peak_shaking_force_N=r.peak_shaking_force,
            force_ratio=r.peak_force / r.peak_shaking_force if r.peak_shaking_force > 0 else 0.0,
            settle_time_s=r.settle_time if math.isfinite(r.settle_time) else None,
            checks=IsolationChecksOut(max_displacement_diff_m=c.displacement_diff,
                                      max_rotation_diff_rad=c.rotation_diff,
                                      max_force_diff_N=c.force_diff, relative_diff=c.relative_diff,
                                      series_residual=c.series_residual, method=c.method),
            warnings=warnings_out(r.warnings), validity=validity_out(r.checks),
        )
        ru = r.run_up
        values["run_up"] = None if ru is None else RunUpOut.model_construct(
            time_s=ru.time, crank_speed_rpm=ru.speed * 30 / math.pi, amplitude_m=ru.amplitude,
            peak_amplitude_m=ru.peak_amplitude, peak_time_s=ru.peak_time, peak_speed_rpm=ru.peak_speed * 30 / math.pi,
            steady_amplitude_m=ru.steady_amplitude, ratio=ru.ratio, crossed_frequencies_Hz=list(ru.crossed))
        return cls.model_construct(**values)


class IsolationDesignOut(BaseModel):
    """The isolators chosen, and the frame on them."""

    ky_N_m: float = Field(description="Vertical stiffness of each isolator [N/m].")
    kx_N_m: float = Field(description="Horizontal stiffness of each isolator [N/m].")
    damping_ratio: float = Field(description="Damping ratio of each isolator [-].")
    block_mass_kg: float = Field(description="Inertia block under the frame's centre [kg].")
    amplitude_m: float = Field(description="Largest movement of the centre or an isolator point [m].")
    peak_force_N: float = Field(description="Largest force to the foundation [N].")
    static_deflection_m: float = Field(description="Deflection under the weight, block included [m].")
    objective: Objective = Field(description="What was minimised: amplitude or force.")
    objective_value: float = Field(description="The objective at the design (m or N).")
    grid_best: float = Field(description="The objective at the best grid candidate, before refinement.")
    candidates: int = Field(description="Candidates solved (grid and refinement).")
    refined: bool = Field(description="The refinement improved on the grid.")
    method: str = Field(description="How the design was searched, in words.")
    isolation: IsolationOut = Field(description="The frame on the chosen isolators, with its time-integration "
                                    "check.")

    @classmethod
    def from_engine(cls, d: Any) -> IsolationDesignOut:
        """Schema from an engine design."""
        return cls.model_construct(
            ky_N_m=d.ky, kx_N_m=d.kx, damping_ratio=d.damping_ratio, block_mass_kg=d.block_mass,
            amplitude_m=d.amplitude, peak_force_N=d.peak_force, static_deflection_m=d.static_deflection,
            objective=d.objective, objective_value=d.objective_value, grid_best=d.grid_best,
            candidates=d.candidates, refined=d.refined, method=d.method,
            isolation=IsolationOut.from_engine(d.isolation))




def _drive_engine() -> Any:
    return importlib.import_module("synth.machine.elastic_drive")


class ElasticElementIn(StrictModel):
    """One element of the elastic link between motor and machine: a shaft or a coupling."""

    type: Literal["shaft", "coupling"] = Field(description="`shaft`: from its diameter, length and shear modulus; "
                                               "`coupling`: its catalogue stiffness.")
    speed_ratio: float = Field(1.0, gt=0, le=1e5, description="Its shaft's speed over the crank's [-] (the motor "
                               "shaft's is the gear ratio).")
    diameter_m: float | None = Field(None, gt=0, le=10, description="Shaft diameter [m].")
    length_m: float | None = Field(None, gt=0, le=100, description="Shaft length between the masses [m].")
    shear_modulus_Pa: float = Field(81e9, gt=0, le=1e12, description="Shear modulus [Pa] (steel 81 GPa).")
    stiffness_Nm_rad: float | None = Field(None, gt=0, le=1e12, description="A coupling's torsional stiffness "
                                           "on its shaft [N·m/rad].")

    def to_engine(self, k: int) -> Any:
        """Engine element; InvalidInput naming a missing field."""
        if self.type == "shaft":
            if self.diameter_m is None or self.length_m is None:
                raise _invalid("a shaft needs diameter_m and length_m", f"elements.{k}.diameter_m")
            return _drive_engine().ElasticElement("shaft", self.speed_ratio, self.diameter_m, self.length_m,
                                                  self.shear_modulus_Pa)
        if self.stiffness_Nm_rad is None:
            raise _invalid("a coupling needs stiffness_Nm_rad", f"elements.{k}.stiffness_Nm_rad")
        return _drive_engine().ElasticElement("coupling", self.speed_ratio, stiffness=self.stiffness_Nm_rad)


def _invalid(message: str, field: str) -> Exception:
    error: Exception = importlib.import_module("synth.errors").InvalidInput(message, field=field)
    return error


MOTOR_EXAMPLE: JsonDict = {"synchronous_speed_rpm": 1500, "rated_speed_rpm": 1440, "rated_torque_Nm": 30,
                           "gear_ratio": 3.0, "efficiency": 0.95, "rotor_inertia_kgm2": 0.02,
                           "breakdown_torque_Nm": 70}


class ElasticDriveIn(AnalysisIn):
    """A linkage at its crank speed driven by a motor through an elastic link (two-mass model, reduced to the
    crank)."""

    motor: MotorIn = Field(description="The motor through its train; its rotor inertia is the first mass.")
    stiffness_Nm_rad: float | None = Field(None, gt=0, le=1e12, description="The link's torsional stiffness "
                                           "reduced to the crank [N·m/rad]; or give `elements`.")
    elements: list[ElasticElementIn] = Field(default_factory=list, max_length=16, description="Shafts and "
                                             "couplings of the link, in series, each reduced by its speed ratio "
                                             "squared.")
    machine_inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Constant inertia on the "
                                        "machine's side (flywheel, gears) reduced to the crank [kg·m²].")
    motor_side_inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Inertia on the motor "
                                           "shaft besides the rotor (coupling half, pinion) [kg·m²].")
    damping_ratio: float = Field(0.05, ge=0, le=2, description="The link's damping as a ratio of the two-mass "
                                 "mode's critical damping [-].")
    start: bool = Field(True, description="Also simulate the run-up from rest with the elastic link.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"mechanism": COMPRESSOR_EXAMPLE, "speed_rpm": 480, "samples": 360,
         "loads": [{"type": "window", "force_N": 2500, "start_deg": 0, "end_deg": 180}],
         "motor": MOTOR_EXAMPLE, "machine_inertia_kgm2": 0.3,
         "elements": [{"type": "shaft", "speed_ratio": 3.0, "diameter_m": 0.03, "length_m": 0.4},
                      {"type": "coupling", "speed_ratio": 1.0, "stiffness_Nm_rad": 2e4}]},
    ]})

    def to_elements(self) -> tuple[Any, ...]:
        """Engine elements."""
        return tuple(e.to_engine(k) for k, e in enumerate(self.elements))


class LoadHarmonicOut(BaseModel):
    """A harmonic of the machine's load torque against the link's natural frequency."""

    order: int = Field(description="Multiple of the mean crank speed.")
    frequency_Hz: float = Field(description="[Hz].")
    amplitude_Nm: float = Field(description="Amplitude of the load torque's harmonic at the crank [N·m].")
    frequency_ratio: float = Field(description="Over the natural frequency [-].")
    near_resonance: bool = Field(description="Within 15 % of it and at least 2 % of the largest harmonic.")


class ElasticRunOut(BaseModel):
    """The run-up from rest with the elastic link."""

    time_s: list[float] = Field(description="Time from rest [s].")
    crank_speed_rpm: list[float] = Field(description="Crank speed [rev/min].")
    rotor_speed_rpm: list[float] = Field(description="The rotor's speed reduced to the crank [rev/min].")
    elastic_torque_Nm: list[float] = Field(description="Torque in the link, at the crank [N·m].")
    peak_elastic_torque_Nm: float = Field(description="Largest |torque in the link| during the run-up [N·m].")
    rigid_peak_torque_Nm: float = Field(description="The rigid model's largest motor torque during its run-up, "
                                        "reduced to the crank [N·m].")
    energy_residual: float = Field(description="Motor work + load work - damping loss - energy gained, over "
                                   "the largest of them [-].")


class ElasticDriveChecksOut(BaseModel):
    """Independent checks of the elastic drive."""

    eigen_frequency_Hz: float = Field(description="The natural frequency from the two-mass matrix's eigenvalues.")
    closed_form_diff: float = Field(description="Relative difference to the closed form sqrt(c(J1+J2)/(J1 J2)).")
    steady_energy_residual: float = Field(description="Energy balance over the steady cycle, relative [-].")
    revolutions: int = Field(description="Revolutions integrated until the state at the same crank angle "
                             "repeated.")


class ElasticDriveOut(BaseModel):
    """The drive with an elastic link, reduced to the crank."""

    stiffness_Nm_rad: float = Field(description="The link's stiffness reduced to the crank [N·m/rad].")
    damping_Nms_rad: float = Field(description="The link's damping coefficient at the crank [N·m·s/rad].")
    rotor_inertia_kgm2: float = Field(description="J1: rotor (and motor-side inertia) reduced to the crank.")
    machine_inertia_kgm2: list[float] = Field(description="J2: mean, least and largest over the cycle [kg·m²].")
    natural_frequency_Hz: float = Field(description="Free-free two-mass frequency at the mean J2 [Hz].")
    natural_frequency_range_Hz: list[float] = Field(description="At the largest and least J2 [Hz].")
    mean_speed_rpm: float = Field(description="The steady cycle's mean crank speed [rev/min].")
    crank_angle_deg: list[float] = Field(description="Crank angle of each sample of the steady cycle [deg].")
    elastic_torque_Nm: list[float] = Field(description="Torque in the link over the steady cycle [N·m].")
    rigid_torque_Nm: list[float] = Field(description="What the rigid model passes between rotor and machine, "
                                         "M_d - J1·alpha [N·m].")
    crank_speed_rpm: list[float] = Field(description="Crank speed over the steady cycle [rev/min].")
    rotor_speed_rpm: list[float] = Field(description="The rotor's speed reduced to the crank over the steady "
                                         "cycle [rev/min].")
    peak_elastic_torque_Nm: float = Field(description="Largest |torque in the link| over the steady cycle [N·m].")
    peak_rigid_torque_Nm: float = Field(description="Largest |torque| the rigid model passes [N·m].")
    dynamic_factor: float = Field(description="Peak |elastic torque| over peak |rigid torque| [-].")
    harmonics: list[LoadHarmonicOut] = Field(description="Harmonics of the load torque at the mean speed against "
                                             "the natural frequency.")
    warnings: list[WarningOut] = Field(description="Load harmonics near the natural frequency, each named.")
    checks: ElasticDriveChecksOut = Field(description="The two-mass closed form against the eigenvalues, the "
                                          "energy balance.")
    start: ElasticRunOut | None = Field(description="The run-up from rest with the link; null when not asked for.")

    @classmethod
    def from_engine(cls, d: Any) -> ElasticDriveOut:
        """Schema from an engine elastic drive."""
        rpm = 30 / math.pi
        st = d.steady
        ensure_finite(st.elastic_torque, d.rigid_torque, st.crank_speed, st.rotor_speed)
        near = [h for h in d.harmonics if h.near]
        warnings = [WarningOut(code="load_harmonic_near_resonance", field="stiffness_Nm_rad", value=h.ratio, unit="",
                               message=f"harmonic {h.order} of the load torque ({h.frequency:.4g} Hz, "
                               f"{h.amplitude:.4g} N·m) lies within 15 % of the link's natural frequency "
                               f"({d.natural_frequency:.4g} Hz): change the stiffness or the inertias")
                    for h in near]
        start = None
        if d.start is not None:
            r = d.start
            start = ElasticRunOut.model_construct(
                time_s=r.time, crank_speed_rpm=r.crank_speed * rpm, rotor_speed_rpm=r.rotor_speed * rpm,
                elastic_torque_Nm=r.elastic_torque, peak_elastic_torque_Nm=d.start_peak_torque,
                rigid_peak_torque_Nm=d.rigid_start_peak_torque, energy_residual=r.energy_residual)
        values: dict[str, Any] = dict(
            stiffness_Nm_rad=d.stiffness, damping_Nms_rad=d.damping, rotor_inertia_kgm2=d.rotor_inertia,
            machine_inertia_kgm2=list(d.machine_inertia), natural_frequency_Hz=d.natural_frequency,
            natural_frequency_range_Hz=list(d.natural_frequency_range),
            mean_speed_rpm=d.mean_speed * rpm,
            crank_angle_deg=degree_array(d.phi), elastic_torque_Nm=st.elastic_torque, rigid_torque_Nm=d.rigid_torque,
            crank_speed_rpm=st.crank_speed * rpm, rotor_speed_rpm=st.rotor_speed * rpm,
            peak_elastic_torque_Nm=float(np.max(np.abs(st.elastic_torque))),
            peak_rigid_torque_Nm=float(np.max(np.abs(d.rigid_torque))), dynamic_factor=d.dynamic_factor,
            harmonics=[LoadHarmonicOut(order=h.order, frequency_Hz=h.frequency, amplitude_Nm=h.amplitude,
                                       frequency_ratio=h.ratio, near_resonance=h.near) for h in d.harmonics],
            warnings=warnings,
            checks=ElasticDriveChecksOut(
                eigen_frequency_Hz=d.eigen_frequency,
                closed_form_diff=abs(d.eigen_frequency - d.natural_frequency) / d.natural_frequency,
                steady_energy_residual=st.energy_residual, revolutions=d.revolutions),
            start=start)
        return cls.model_construct(**values)


class RegulatorIn(StrictModel):
    """A PI controller on a frequency-converter drive: tuned for a settling time and overshoot, or given gains."""

    settling_time_s: float | None = Field(None, gt=0, le=1e4, description="Target settling time [s] (tuning).")
    overshoot: float | None = Field(None, ge=0, lt=1, description="Target overshoot as a fraction [-] (tuning).")
    kp: float | None = Field(None, ge=-1e6, le=1e6, description="Proportional gain on the crank speed's error "
                             "[-] (rad/s of no-load speed per rad/s of error); with `ki` instead of tuning.")
    ki: float | None = Field(None, gt=0, le=1e9, description="Integral gain [1/s].")
    filter_time_s: float = Field(0.0, ge=0, le=100, description="Time constant of the speed measurement [s].")
    reference_speed_rpm: float | None = Field(None, gt=0, le=1e6, description="Speed to hold [rev/min]; default "
                                              "the mean speed before the step.")

    def to_engine(self) -> tuple[Any, tuple[float, float, float] | None]:
        """Engine controller (gains) or tuning targets; InvalidInput naming the missing field."""
        tuned = self.settling_time_s is not None or self.overshoot is not None
        given = self.kp is not None or self.ki is not None
        if tuned == given:
            raise _invalid("give the regulator either settling_time_s and overshoot (tuned) or kp and ki",
                           "regulator")
        if tuned:
            if self.settling_time_s is None or self.overshoot is None:
                raise _invalid("tuning needs both settling_time_s and overshoot", "regulator.settling_time_s")
            return None, (self.settling_time_s, self.overshoot, self.filter_time_s)
        if self.kp is None or self.ki is None:
            raise _invalid("gains need both kp and ki", "regulator.kp")
        ref = None if self.reference_speed_rpm is None else self.reference_speed_rpm * math.pi / 30
        return importlib.import_module("synth.machine.regulation").PIController(
            self.kp, self.ki, self.filter_time_s, ref), None


class RegulationIn(AnalysisIn):
    """A linkage at its crank speed, its motor and a step in the process load: the speed's answer."""

    motor: MotorIn = Field(description="The motor through its train; its linear characteristic drives.")
    constant_inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Rotor, train and flywheel "
                                         "reduced to the crank [kg·m²].")
    load_step_Nm: float = Field(ge=-1e9, le=1e9, description="Step in the load torque at the crank [N·m], "
                                "positive resists (more load).", examples=[40])
    delta: float | None = Field(None, gt=0, lt=1, description="A settling band delta·w/2 [-] instead of "
                                "settling_band; one as wide as the step's dip is replaced by settling_band (with "
                                "the warning settling_band_wide).")
    settling_band: float = Field(0.02, gt=0, lt=1, description="The band the settling is judged in, as a "
                                 "fraction of the step's dip (the largest deviation of the smoothed speed) [-].")
    regulator: RegulatorIn | None = Field(None, description="A PI controller on a frequency converter; null: "
                                          "self-regulation through the characteristic.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"mechanism": COMPRESSOR_EXAMPLE, "speed_rpm": 480, "samples": 180,
         "loads": [{"type": "window", "force_N": 2500, "start_deg": 0, "end_deg": 180}],
         "motor": MOTOR_EXAMPLE, "constant_inertia_kgm2": 0.5, "load_step_Nm": 40},
        {"mechanism": COMPRESSOR_EXAMPLE, "speed_rpm": 480, "samples": 180,
         "loads": [{"type": "window", "force_N": 2500, "start_deg": 0, "end_deg": 180}],
         "motor": MOTOR_EXAMPLE, "constant_inertia_kgm2": 0.5, "load_step_Nm": 20,
         "regulator": {"settling_time_s": 0.2, "overshoot": 0.05}},
    ]})


class RegulationOut(BaseModel):
    """The machine's speed after the load step."""

    time_s: list[float] = Field(description="Time from the start of the record; the step comes at step_time_s [s].")
    crank_speed_rpm: list[float] = Field(description="Crank speed [rev/min].")
    smoothed_speed_rpm: list[float] = Field(description="The speed with the cycle's own fluctuation taken off "
                                            "[rev/min].")
    motor_torque_Nm: list[float] = Field(description="Motor torque at the crank [N·m].")
    load_torque_Nm: list[float] = Field(description="Load torque at the crank, the step included (positive "
                                        "drives) [N·m].")
    converter_shift_rpm: list[float] = Field(description="The converter's shift of the no-load crank speed "
                                             "[rev/min]; zeros without a regulator.")
    step_time_s: float = Field(description="When the load steps [s].")
    speed_before_rpm: float = Field(description="Mean crank speed of the steady cycle before the step [rev/min].")
    speed_after_rpm: float = Field(description="Mean speed of the new steady cycle without a regulator "
                                   "[rev/min].")
    drop_rpm: float = Field(description="Speed drop of self-regulation, simulated [rev/min].")
    drop_closed_form_rpm: float = Field(description="dM/s, s the characteristic's slope at the crank [rev/min].")
    time_constant_s: float = Field(description="J_mean/s [s].")
    band_rpm: float = Field(description="The settling band: settling_band of the dip, or delta·w/2 [rev/min].")
    settling_time_s: float | None = Field(description="After the step until the smoothed speed stays in the band "
                                          "[s]; null: not within the run.")
    settling_closed_form_s: float | None = Field(description="tau·ln(dw/band) for self-regulation [s].")
    overshoot: float = Field(description="Largest excursion past the final speed over the change [-].")
    max_deviation_rpm: float = Field(description="Largest |smoothed - final| after the step [rev/min].")
    kp: float | None = Field(None, description="The PI controller's proportional gain [-]; null without one.")
    ki_1_s: float | None = Field(None, description="Its integral gain [1/s].")
    filter_time_s: float | None = Field(None, description="Its speed measurement's time constant [s].")
    reference_speed_rpm: float | None = Field(None, description="The speed it holds [rev/min].")
    poles_real_1_s: list[float] | None = Field(None, description="Closed-loop poles, real parts [1/s].")
    poles_imag_1_s: list[float] | None = Field(None, description="Closed-loop poles, imaginary parts [1/s].")
    breakdown_torque_Nm: float | None = Field(None, description="The motor's breakdown torque at the crank "
                                              "[N·m]; null without one.")
    warnings: list[WarningOut] = Field(default_factory=list, description="Where the model stops: the motor "
                                       "pulling out (motor_breakdown), a lightly damped loop, a tuned loop "
                                       "missing its targets, a band wider than the dip.")
    validity: list[ValidityCheckOut] = Field(default_factory=list, description="Each condition the model "
                                             "needs against its limit: motor_stalls, motor_breakdown, "
                                             "regulator_damping, regulator_settling_time, regulator_overshoot.")

    @classmethod
    def from_engine(cls, r: Any) -> RegulationOut:
        """Schema from an engine regulation."""
        rpm = 30 / math.pi
        ensure_finite(r.omega, r.smoothed, r.motor_torque)
        c = r.controller
        values: dict[str, Any] = dict(
            time_s=r.time, crank_speed_rpm=r.omega * rpm, smoothed_speed_rpm=r.smoothed * rpm,
            motor_torque_Nm=r.motor_torque, load_torque_Nm=r.load_torque, converter_shift_rpm=r.shift * rpm,
            step_time_s=r.step_time, speed_before_rpm=r.speed_before * rpm, speed_after_rpm=r.speed_after * rpm,
            drop_rpm=r.drop * rpm, drop_closed_form_rpm=r.drop_closed_form * rpm, time_constant_s=r.time_constant,
            band_rpm=r.band * rpm, settling_time_s=r.settling_time, settling_closed_form_s=r.settling_closed_form,
            overshoot=r.overshoot, max_deviation_rpm=r.max_deviation * rpm,
            kp=None if c is None else c.kp, ki_1_s=None if c is None else c.ki,
            filter_time_s=None if c is None else c.filter_time,
            reference_speed_rpm=None if c is None or c.reference is None else c.reference * rpm,
            poles_real_1_s=None if r.poles is None else [float(p.real) for p in r.poles],
            poles_imag_1_s=None if r.poles is None else [float(p.imag) for p in r.poles],
            breakdown_torque_Nm=r.breakdown_torque if math.isfinite(r.breakdown_torque) else None,
            warnings=warnings_out(r.warnings), validity=validity_out(r.checks))
        return cls.model_construct(**values)


# ---------------------------------------------------------------------------------------------------------------
# The blocks of POST /v1/machines/design: the same capabilities for the designed machine.

def _chain_engine() -> Any:
    return importlib.import_module("synth.machine.foundation_chain")


class MachineFoundationIn(StrictModel):
    """The designed machine's frame on isolators: its shaking force and moment after balancing (the Lanchester
    balancers' included) at the working speed drive the frame, as POST /v1/machines/isolation answers."""

    frame: FrameIn = Field(description="The machine as a rigid body.")
    isolators: list[IsolatorIn] = Field(max_length=MAX_ISOLATORS, description="The isolators under the frame "
                                        "(enough to hold x, y and rotation).")
    max_force_N: float | None = Field(None, gt=0, le=1e12, description="Limit of the peak force to the "
                                      "foundation [N]: check foundation_force; null: not checked.")
    max_amplitude_m: float | None = Field(None, gt=0, le=10, description="Limit of the frame centre's peak "
                                          "displacement [m]: check foundation_amplitude; null: not checked.")
    run_up: bool = Field(False, description="Also follow the frame while the designed machine runs up from rest "
                         "(its motor through the train, rotor, train and flywheel).")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"frame": FRAME_EXAMPLE, "isolators": ISOLATORS_EXAMPLE, "max_force_N": 600}]})

    def to_engine(self) -> Any:
        """Engine foundation choice."""
        return _chain_engine().FoundationChoice(
            self.frame.to_engine(), tuple(i.to_engine() for i in self.isolators), self.max_force_N,
            self.max_amplitude_m, self.run_up)


class MachineElasticDriveIn(StrictModel):
    """The designed machine driven through an elastic link between the motor's rotor and the train (two-mass
    model reduced to the crank), as POST /v1/machines/elastic-drive answers; the gear stages are then sized for
    the link's torque where it is larger than the rigid machine's."""

    stiffness_Nm_rad: float | None = Field(None, gt=0, le=1e12, description="The link's torsional stiffness "
                                           "reduced to the crank [N·m/rad]; or give `elements`.")
    elements: list[ElasticElementIn] = Field(default_factory=list, max_length=16, description="Shafts and "
                                             "couplings of the link, in series, each reduced by its speed ratio "
                                             "squared.")
    motor_side_inertia_kgm2: float = Field(0.0, ge=0, le=MAX_INERTIA_KGM2, description="Inertia on the motor "
                                           "shaft besides the rotor (coupling half) [kg·m²]; a flywheel on the "
                                           "motor shaft joins it.")
    damping_ratio: float = Field(0.05, ge=0, le=2, description="The link's damping as a ratio of the two-mass "
                                 "mode's critical damping [-].")
    start: bool = Field(True, description="Also simulate the run-up from rest with the elastic link.")
    max_dynamic_factor: float | None = Field(None, gt=0, le=1e3, description="Limit of the dynamic factor [-]: "
                                             "check dynamic_factor; null: not checked.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"elements": [{"type": "shaft", "speed_ratio": 3.0, "diameter_m": 0.03, "length_m": 0.4},
                      {"type": "coupling", "speed_ratio": 3.0, "stiffness_Nm_rad": 2e3}],
         "max_dynamic_factor": 1.5}]})

    def to_engine(self) -> Any:
        """Engine elastic-drive choice."""
        return _chain_engine().ElasticDriveChoice(
            self.stiffness_Nm_rad, tuple(e.to_engine(k) for k, e in enumerate(self.elements)),
            self.motor_side_inertia_kgm2, self.damping_ratio, self.start, self.max_dynamic_factor)


class MachineRegulationIn(StrictModel):
    """A step in the designed machine's process load: its self-regulation through the chosen motor's
    characteristic, or a PI controller on a frequency converter, as POST /v1/machines/regulation answers."""

    load_step_Nm: float = Field(ge=-1e9, le=1e9, description="Step in the load torque at the crank [N·m], "
                                "positive resists (more load).", examples=[40])
    delta: float | None = Field(None, gt=0, lt=1, description="A settling band delta·w/2 [-]; default 2 % of "
                                "the step's dip.")
    regulator: RegulatorIn | None = Field(None, description="A PI controller on a frequency converter; null: "
                                          "self-regulation through the characteristic.")
    max_settling_time_s: float | None = Field(None, gt=0, le=1e4, description="Limit of the time to settle in "
                                              "the band after the step [s]: check regulation_settling_time; null: "
                                              "not checked.")
    max_speed_drop_rad_s: float | None = Field(None, gt=0, le=1e4, description="Limit of the mean crank speed's "
                                               "drop (with a regulator: its largest deviation) [rad/s]: check "
                                               "regulation_speed_drop; null: not checked.")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"load_step_Nm": 40, "max_settling_time_s": 2.0},
        {"load_step_Nm": 40, "regulator": {"settling_time_s": 0.5, "overshoot": 0.05}}]})

    def to_engine(self) -> Any:
        """Engine regulation choice."""
        controller, tuning = (None, None) if self.regulator is None else self.regulator.to_engine()
        return _chain_engine().RegulationChoice(self.load_step_Nm, self.delta, controller, tuning,
                                                self.max_settling_time_s, self.max_speed_drop_rad_s)


class MachineElasticDriveOut(ElasticDriveOut):
    """The designed machine's elastic drive, and what it was given."""

    motor_side_inertia_kgm2: float = Field(description="On the motor shaft besides the rotor, the flywheel there "
                                           "included [kg·m²].")
    machine_constant_inertia_kgm2: float = Field(description="Train (and the flywheel elsewhere) reduced to the "
                                                 "crank, on the machine's side of the link [kg·m²].")
    gear_torque_basis: Literal["rigid", "elastic"] = Field(description="`elastic`: the gear stages were sized for "
                                                           "the elastic link's torque, carried to each shaft, "
                                                           "where it is larger than the rigid machine's; `rigid`: "
                                                           "it is nowhere larger, or no stage is sized.")

    @classmethod
    def from_design(cls, e: Any) -> MachineElasticDriveOut:
        """Schema from the engine's elastic drive of a design."""
        base = ElasticDriveOut.from_engine(e.drive)
        return cls.model_construct(**dict(base), motor_side_inertia_kgm2=e.motor_side_inertia,
                                   machine_constant_inertia_kgm2=e.machine_constant_inertia,
                                   gear_torque_basis=e.gear_torque_basis)


class MachineRegulationOut(RegulationOut):
    """The designed machine after the load step, and the inertia it ran with."""

    constant_inertia_kgm2: float = Field(description="Rotor, train and flywheel reduced to the crank [kg·m²].")

    @classmethod
    def from_design(cls, g: Any) -> MachineRegulationOut:
        """Schema from the engine's load step of a design."""
        base = RegulationOut.from_engine(g.regulation)
        return cls.model_construct(**dict(base), constant_inertia_kgm2=g.constant_inertia)
