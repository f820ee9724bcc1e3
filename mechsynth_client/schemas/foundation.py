"""Schemas of the machine on its foundation: POST /v1/machines/isolation and /v1/machines/isolation/design."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, JsonValue
from pydantic.config import JsonDict

from .analysis import AnalysisIn
from .motor import MotorIn
from .common import MAX_INERTIA_KGM2, MAX_MASS_KG, StrictModel, ValidityCheckOut, Vec2, WarningOut

#: Stiffness beyond any isolator or foundation bolt [N/m]; a larger value is a typo.
MAX_STIFFNESS_N_M = 1e13
MAX_DAMPING_NS_M = 1e10
MAX_ISOLATORS = 64


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

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"mechanism": COMPRESSOR_EXAMPLE, "speed_rpm": 480, "samples": 360, "frame": FRAME_EXAMPLE,
         "isolators": ISOLATORS_EXAMPLE},
    ]})


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

# ---------------------------------------------------------------------------------------------------------------
# The blocks of POST /v1/machines/design: the same capabilities for the designed machine.


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


class MachineRegulationOut(RegulationOut):
    """The designed machine after the load step, and the inertia it ran with."""

    constant_inertia_kgm2: float = Field(description="Rotor, train and flywheel reduced to the crank [kg·m²].")
