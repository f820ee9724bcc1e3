"""Schemas of /v1/cams/*: a disc cam's analysis over one turn, the least cam for pressure-angle and curvature
limits, and the table of standard motion laws."""

from __future__ import annotations

import math
from typing import Annotated, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, JsonValue, model_validator

from .common import (
    MAX_INERTIA_KGM2,
    MAX_LENGTH_M,
    MAX_MASS_KG,
    Coordinate,
    Length,
    StrictModel,
    ValidityCheckOut,
    WarningOut,
)

LawName = Literal["cycloidal", "simple_harmonic", "polynomial_345", "polynomial_4567", "modified_trapezoid",
                  "modified_sine", "optimised"]
LawObjective = Literal["peak_acceleration", "peak_jerk", "residual_vibration"]
# The engine's bound (synth.cams.design.MAX_SEGMENTS), spelled here so that the schema loads without the engine.
MAX_SEGMENTS = 24
MAX_FORCE_N = 1e9
Force = Annotated[float, Field(ge=-MAX_FORCE_N, le=MAX_FORCE_N)]


class CamSegmentIn(StrictModel):
    """One part of the follower's program over the cam's turn: a dwell, or a rise or return by a motion law."""

    kind: Literal["dwell", "rise", "return"] = Field(description="dwell, rise or return.", examples=["rise"])
    angle_deg: float = Field(ge=0.0, le=360.0, description="Cam angle the segment takes [deg]; the segments "
                             "together must make 360.", examples=[120.0])
    lift_m: float | None = Field(None, ge=0.0, le=MAX_LENGTH_M,
                                 description="Rise or return of a translating follower [m].", examples=[0.02])
    lift_deg: float | None = Field(None, ge=0.0, le=180.0,
                                   description="Swing of an oscillating follower's arm [deg].")
    law: LawName = Field("cycloidal", description="Motion law of a rise or return; `optimised` takes the spline "
                         "law of least peak acceleration, jerk or residual vibration (see law_options).")

    @model_validator(mode="after")
    def _one_lift(self) -> CamSegmentIn:
        if self.lift_m is not None and self.lift_deg is not None:
            raise ValueError("give lift_m (translating follower) or lift_deg (oscillating), not both")
        return self


class CamFollowerIn(StrictModel):
    """The follower. The cam centre is the origin and the cam turns counter-clockwise. A translating follower
    moves along +y on the line x = offset_m; an oscillating follower's pivot is at (pivot_distance_m, 0) with its
    arm reaching back over the cam on the +y side."""

    motion: Literal["translating", "oscillating"] = Field("translating", description="translating or oscillating.")
    contact: Literal["knife_edge", "roller", "flat_faced"] = Field(
        "roller", description="knife_edge, roller or flat_faced (a translating face is square to the follower's "
                              "axis; an oscillating face lies face_offset_m from the pivot).")
    roller_radius_m: float = Field(0.0, ge=0.0, le=MAX_LENGTH_M, description="Roller radius [m] (roller only).",
                                   examples=[0.01])
    offset_m: Coordinate = Field(0.0, description="Offset of a translating follower's axis from the cam centre "
                                 "[m]; positive to the right, where it lowers the rise's pressure angle.")
    pivot_distance_m: float | None = Field(None, gt=0.0, le=MAX_LENGTH_M,
                                           description="Cam centre to the oscillating follower's pivot [m].")
    arm_length_m: float | None = Field(None, gt=0.0, le=MAX_LENGTH_M,
                                       description="Pivot to the roller centre or knife edge [m].")
    face_offset_m: Coordinate = Field(0.0, description="Distance of an oscillating flat face from its pivot, "
                                      "toward the cam [m].")

    @model_validator(mode="after")
    def _complete(self) -> CamFollowerIn:
        if self.contact == "roller" and not self.roller_radius_m > 0:
            raise ValueError("a roller follower needs roller_radius_m > 0")
        if self.motion == "oscillating":
            if self.pivot_distance_m is None:
                raise ValueError("an oscillating follower needs pivot_distance_m")
            if self.contact != "flat_faced" and self.arm_length_m is None:
                raise ValueError("an oscillating follower needs arm_length_m")
        return self


class CamProcessLoadIn(StrictModel):
    """A process load on the follower against its lift between two cam angles (wrapping past 360 allowed)."""

    from_deg: float = Field(ge=0.0, le=360.0, description="Cam angle where the load starts [deg].", examples=[0.0])
    to_deg: float = Field(ge=0.0, le=360.0, description="Cam angle where it ends [deg].", examples=[120.0])
    force_N: Force | None = Field(None, description="Force on a translating follower [N].", examples=[50.0])
    moment_Nm: Force | None = Field(None, description="Moment on an oscillating follower about its pivot [N·m].")


class CamLoadsIn(StrictModel):
    """The follower's inertia, spring and process loads; a spring left without stiffness or preload is designed:
    the least spring (largest spring force least) keeping contact with the margin."""

    mass_kg: float | None = Field(None, ge=0.0, le=MAX_MASS_KG, description="Translating follower's mass [kg].",
                                  examples=[2.0])
    inertia_kgm2: float | None = Field(None, ge=0.0, le=MAX_INERTIA_KGM2,
                                       description="Oscillating follower's inertia about its pivot [kg·m²].")
    spring_stiffness_N_m: float | None = Field(None, ge=0.0, le=1e12, description="Spring rate [N/m].")
    spring_preload_N: float | None = Field(None, ge=0.0, le=MAX_FORCE_N,
                                           description="Spring force at the lowest position [N].")
    spring_stiffness_Nm_rad: float | None = Field(None, ge=0.0, le=1e12,
                                                  description="Torsion spring rate [N·m/rad].")
    spring_preload_Nm: float | None = Field(None, ge=0.0, le=MAX_FORCE_N,
                                            description="Torsion spring moment at the lowest position [N·m].")
    process: list[CamProcessLoadIn] = Field(default_factory=list, max_length=8, description="Process loads.")
    contact_margin: float = Field(0.2, ge=0.0, le=10.0, description="The spring must exceed the separating force "
                                  "by this fraction at every angle.")
    rolling_resistance_m: float = Field(0.0, ge=0.0, le=0.1, description="Roller followers: the coefficient of "
                                        "rolling friction k [m] of the roller on the cam (a couple k·N against its "
                                        "rolling); smaller than the roller radius.", examples=[0.0005])
    max_initial_compression_m: float | None = Field(None, gt=0.0, le=MAX_LENGTH_M, description="A designed "
                                                    "spring's largest initial compression F0/k [m]; default the "
                                                    "follower's total lift.")
    spring_wire: SpringWire = Field("music_wire", description="The designed spring's wire (translating "
                                    "followers): its strength, shear modulus and density.")
    spring_index: float = Field(8.0, ge=4.0, le=12.0, description="The designed spring's index D/d [-].")


class LawOptionsIn(StrictModel):
    """How the segments with the `optimised` law are found (a convex program in the spline's coefficients)."""

    objective: LawObjective = Field("peak_acceleration", description="peak_acceleration, peak_jerk or "
                                     "residual_vibration (needs natural_frequency_hz).")
    knot_intervals: int = Field(16, ge=4, le=64, description="Knot intervals of the quintic B-spline.")
    natural_frequency_hz: float | None = Field(None, gt=0.0, le=1e5,
                                               description="The follower system's natural frequency [Hz].")
    max_acceleration_coefficient: float = Field(2.0 * math.pi, gt=4.0, le=100.0, description="With "
                                                "residual_vibration: cap on the peak acceleration, in h/beta² "
                                                "(2 pi: no worse than cycloidal).")


SpringWire = Literal["music_wire", "oil_tempered", "hard_drawn", "chrome_vanadium", "chrome_silicon",
                     "stainless_302"]


class _CamFields(StrictModel):
    max_pressure_angle_rise_deg: float = Field(30.0, gt=0.0, lt=90.0,
                                               description="Largest pressure angle in the rises [deg].")
    max_pressure_angle_return_deg: float = Field(45.0, gt=0.0, lt=90.0,
                                                 description="Largest pressure angle in the returns [deg].")
    segments: list[CamSegmentIn] = Field(min_length=1, max_length=MAX_SEGMENTS,
                                      description="The follower's program, in order from cam angle 0.")
    follower: CamFollowerIn = Field(default_factory=CamFollowerIn, description="The follower.")
    speed_rpm: float = Field(gt=0.0, le=1e5, description="Cam speed [rev/min].", examples=[300.0])
    samples: int = Field(720, ge=72, le=1_000_000, description="Cam angles per turn (the service's max_samples "
                         "bounds it).")
    loads: CamLoadsIn | None = Field(None, description="Inertia, spring and process loads for the forces.")
    law_options: LawOptionsIn = Field(default_factory=LawOptionsIn, description="Optimised laws' options.")
    drawing_angle_deg: float = Field(0.0, ge=0.0, le=360.0, description="Cam angle the figure draws [deg].")
    chord_tolerance_m: float = Field(1e-5, ge=1e-7, le=1e-2, description="Largest distance of the DXF's "
                                     "polyline from the profile [m].")

    @property
    def omega_rad_s(self) -> float:
        """Cam speed [rad/s]."""
        return self.speed_rpm * math.pi / 30.0


_EXAMPLE_SEGMENTS: list[JsonValue] = [
    {"kind": "rise", "angle_deg": 120, "lift_m": 0.02, "law": "cycloidal"},
    {"kind": "dwell", "angle_deg": 60},
    {"kind": "return", "angle_deg": 120, "lift_m": 0.02, "law": "polynomial_345"},
    {"kind": "dwell", "angle_deg": 60},
]


class CamAnalysisIn(_CamFields):
    """A disc cam of a given base circle to analyse over one turn."""

    base_radius_m: Length = Field(description="Base circle radius: the profile's least distance from the cam "
                                  "centre [m].", examples=[0.04])
    min_curvature_radius_m: float = Field(0.002, gt=0.0, le=MAX_LENGTH_M, description="Least radius of "
                                          "curvature of the convex profile [m] the answer is held to (a roller's "
                                          "profile also to the roller's radius).")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"segments": _EXAMPLE_SEGMENTS, "follower": {"contact": "roller", "roller_radius_m": 0.01,
                                                     "offset_m": 0.005},
         "base_radius_m": 0.04, "speed_rpm": 300,
         "loads": {"mass_kg": 2.0, "process": [{"from_deg": 0, "to_deg": 120, "force_N": 50}]}},
        {"segments": [{"kind": "rise", "angle_deg": 100, "lift_deg": 20, "law": "modified_sine"},
                      {"kind": "dwell", "angle_deg": 80},
                      {"kind": "return", "angle_deg": 100, "lift_deg": 20, "law": "optimised"},
                      {"kind": "dwell", "angle_deg": 80}],
         "follower": {"motion": "oscillating", "contact": "roller", "roller_radius_m": 0.008,
                      "pivot_distance_m": 0.1, "arm_length_m": 0.07},
         "base_radius_m": 0.035, "speed_rpm": 200, "law_options": {"objective": "peak_jerk"}},
    ]})


class CamSynthesisIn(_CamFields):
    """The least disc cam (base circle, and offset when its range is given) for pressure-angle and curvature
    limits."""

    min_curvature_radius_m: float = Field(0.0, ge=0.0, le=MAX_LENGTH_M, description="Least radius of curvature "
                                          "of the convex profile [m] (a roller's profile also keeps clear of "
                                          "undercut; a flat face needs a positive value).")
    base_radius_bounds_m: list[Annotated[float, Field(gt=0.0, le=MAX_LENGTH_M)]] = Field(
        min_length=2, max_length=2, description="Range searched for the base radius [m]: [min, max].",
        examples=[[0.005, 0.2]])
    offset_bounds_m: list[Coordinate] | None = Field(
        None, min_length=2, max_length=2, description="Range of a free offset [m]: [min, max]; without it the "
                                                      "follower's offset_m is kept.")
    hub_radius_m: float = Field(0.0, ge=0.0, le=MAX_LENGTH_M, description="Radius of the shaft or hub the "
                                "cam is made on [m]: no base circle below it is searched; 0: not given (the answer "
                                "then warns hub_radius_missing).")

    model_config = ConfigDict(json_schema_extra={"examples": [
        {"segments": _EXAMPLE_SEGMENTS, "follower": {"contact": "roller", "roller_radius_m": 0.01},
         "speed_rpm": 300, "max_pressure_angle_rise_deg": 30, "max_pressure_angle_return_deg": 45,
         "base_radius_bounds_m": [0.005, 0.2]},
        {"segments": _EXAMPLE_SEGMENTS, "follower": {"contact": "roller", "roller_radius_m": 0.01},
         "speed_rpm": 300, "base_radius_bounds_m": [0.005, 0.2], "offset_bounds_m": [-0.02, 0.02],
         "min_curvature_radius_m": 0.003},
    ]})

# ---------------------------------------------------------------- answers


class TranslatingMotionOut(BaseModel):
    """A translating follower's displacement and its derivatives over the turn, per radian and at speed."""

    follower_motion: Literal["translating"] = Field("translating", description="The follower's kind: the "
                                                    "names of the fields below carry its unit, m.")
    s_m: list[float] = Field(description="Displacement from the lowest position [m].")
    v_m_per_rad: list[float] = Field(description="ds/dtheta [m/rad].")
    a_m_per_rad2: list[float] = Field(description="d2s/dtheta2 [m/rad²].")
    jerk_m_per_rad3: list[float] = Field(description="d3s/dtheta3 [m/rad³].")
    v_m_s: list[float] = Field(description="Velocity at the cam speed [m/s].")
    a_m_s2: list[float] = Field(description="Acceleration at the cam speed [m/s²].")
    jerk_m_s3: list[float] = Field(description="Jerk at the cam speed [m/s³].")


class OscillatingMotionOut(BaseModel):
    """An oscillating follower's swing and its derivatives over the turn, per radian and at speed."""

    follower_motion: Literal["oscillating"] = Field("oscillating", description="The follower's kind: the "
                                                    "names of the fields below carry its unit, rad.")
    psi_rad: list[float] = Field(description="Arm swing from its lowest position [rad].")
    v_rad_per_rad: list[float] = Field(description="dpsi/dtheta [rad/rad].")
    a_rad_per_rad2: list[float] = Field(description="d2psi/dtheta2 [rad/rad²].")
    jerk_rad_per_rad3: list[float] = Field(description="d3psi/dtheta3 [rad/rad³].")
    omega_rad_s: list[float] = Field(description="Arm angular velocity at the cam speed [rad/s].")
    alpha_rad_s2: list[float] = Field(description="Arm angular acceleration [rad/s²].")
    jerk_rad_s3: list[float] = Field(description="Arm angular jerk [rad/s³].")


MotionOut = Annotated[Union[TranslatingMotionOut, OscillatingMotionOut], Field(discriminator="follower_motion")]


class CamProfileOut(BaseModel):
    """The cam in its own frame (centre at the origin, at cam angle 0), with pressure angle and curvature."""

    base_radius_m: float = Field(description="Base circle radius [m].")
    prime_radius_m: float = Field(description="Prime circle radius: base plus roller [m].")
    offset_m: float = Field(description="The translating follower's offset [m].")
    pitch_m: list[list[float]] = Field(description="Pitch curve (roller centre, knife edge, or a flat face's "
                                       "reference point) per cam angle, cam frame [m].")
    profile_m: list[list[float]] = Field(description="Profile (contact point) per cam angle, cam frame [m].")
    pressure_angle_deg: list[float] = Field(description="Pressure angle per cam angle [deg]: from the contact "
                                            "point's motion to the common normal, counter-clockwise.")
    curvature_1_m: list[float] = Field(description="Profile curvature per cam angle [1/m], positive convex.")
    max_pressure_angle_rise_deg: float = Field(description="Largest |pressure angle| in the rises [deg].")
    max_pressure_angle_return_deg: float = Field(description="Largest |pressure angle| in the returns [deg].")
    min_curvature_radius_m: float = Field(description="Least radius of curvature of the convex profile [m].")
    min_curvature_radius_at_deg: float = Field(description="Cam angle where it occurs [deg].")
    face_width_m: float = Field(description="Least width of a flat face: the contact's travel along it [m]; 0 "
                                "for other contacts.")
    face_extent_m: list[float] = Field(description="Flat face: the contact's nearest and farthest position along "
                                       "the face from its reference point [m].")


class CamForcesOut(BaseModel):
    """The pair's forces over the turn at the cam speed."""

    spring_designed: bool = Field(description="The spring (stiffness, preload or both) was designed: least "
                                  "largest spring force keeping contact with the margin (a linear program).")
    spring_stiffness_N_m: float | None = Field(description="Translating follower: spring rate [N/m].")
    spring_preload_N: float | None = Field(description="Translating follower: spring force at s = 0 [N].")
    spring_stiffness_Nm_rad: float | None = Field(description="Oscillating follower: torsion rate [N·m/rad].")
    spring_preload_Nm: float | None = Field(description="Oscillating follower: torsion moment at psi = 0 [N·m].")
    least_contact_margin: float | None = Field(description="Least spring force over separating force, less 1, "
                                               "where inertia and process would lift the follower off; null "
                                               "when nothing would.")
    contact_force_N: list[float] = Field(description="Contact force along the common normal per cam angle [N].")
    min_contact_force_N: float = Field(description="Least contact force [N]; contact holds while it is > 0.")
    max_contact_force_N: float = Field(description="Largest contact force [N].")
    driving_torque_Nm: list[float] = Field(description="Camshaft driving torque from the contact geometry, "
                                           "N (C x n), per cam angle [N·m]; with rolling resistance also the "
                                           "tangential force's moment and the rolling couple.")
    driving_torque_virtual_power_Nm: list[float] = Field(description="The same by virtual power, T = Q dq/dtheta, "
                                                         "plus the rolling loss, per cam angle [N·m].")
    rolling_loss_torque_Nm: list[float] = Field(default_factory=list, description="The rolling resistance's "
                                                "share of the driving torque, k N |v_t| / r (the couple times the "
                                                "roller's rotation relative to the cam), per cam angle [N·m]; "
                                                "zeros without rolling resistance.")
    peak_driving_torque_Nm: float = Field(description="Largest |driving torque| [N·m].")
    mean_driving_torque_Nm: float = Field(description="Mean driving torque: the work per turn over 2 pi [N·m].")
    rms_driving_torque_Nm: float = Field(description="RMS driving torque [N·m].")
    reduced_inertia_kgm2: list[float] = Field(description="The camshaft as a machine's crank: the follower's "
                                              "inertia reduced to it, m (dq/dtheta)², per cam angle [kg·m²] "
                                              "(the cam's own inertia not included).")
    load_torque_Nm: list[float] = Field(description="Spring and process loads reduced to the camshaft, "
                                        "(k q + F0 + F_p) dq/dtheta, per cam angle [N·m], positive resisting: the "
                                        "driving torque less the inertia's (omega²/2) dJ/dtheta. With "
                                        "reduced_inertia_kgm2 the tables /v1/flywheel takes.")


class LawCheckOut(BaseModel):
    """A rise or return: the sampled peaks against the law's closed form, and the closed form against the
    textbook's coefficient."""

    segment: int = Field(description="Index of the segment.")
    kind: str = Field(description="rise or return.")
    law: str = Field(description="Its motion law.")
    velocity_coefficient: float = Field(description="C_v of the closed form: peak ds/dtheta = C_v h/beta.")
    acceleration_coefficient: float = Field(description="C_a: peak d2s/dtheta2 = C_a h/beta².")
    jerk_coefficient: float = Field(description="C_j: peak d3s/dtheta3 = C_j h/beta³.")
    textbook_acceleration_coefficient: float | None = Field(description="C_a as the textbooks print it; null for "
                                                            "an optimised law.")
    sampled_peak_acceleration_ratio: float = Field(description="Peak acceleration on the answer's samples over "
                                                   "C_a h/beta² (at most 1; near 1 when a sample falls near the "
                                                   "peak).")


class CamChecksOut(BaseModel):
    """Independent figures every cam answer carries."""

    table_pressure_angle_error_deg: float = Field(description="Largest difference between the pressure angle "
                                                  "recomputed from the profile's point table (finite "
                                                  "differences) and the analytic one [deg].")
    table_curvature_error: float = Field(description="Largest difference of the curvature recomputed from the "
                                         "point table, over the largest |curvature| [-].")
    table_samples_compared: int = Field(description="Samples compared (those whose stencil stays in one segment).")
    derivative_error: float = Field(description="Largest difference between the laws' closed-form v, a, jerk and "
                                    "finite differences of s, v, a, over each one's peak [-].")
    torque_virtual_power_error: float | None = Field(description="max |N (C x n) - Q dq/dtheta| over the peak "
                                                     "torque [-]: T omega = F v; null without loads.")
    reduced_model_error: float | None = Field(description="max |T - (load + (omega²/2) dJ/dtheta)| over the peak "
                                              "torque, dJ/dtheta by differences of the reduced-inertia table [-]; "
                                              "null without loads.")
    laws: list[LawCheckOut] = Field(description="Per rise and return.")


class OptimisedLawOut(BaseModel):
    """A law the service optimised (a quintic B-spline in u = theta/beta), with its check figures."""

    objective: str = Field(description="peak_acceleration, peak_jerk or residual_vibration.")
    solver_status: str = Field(description="The convex program's status (Clarabel).")
    objective_value: float = Field(description="The program's optimum (peak coefficient, or residual/lift).")
    velocity_coefficient: float = Field(description="C_v recomputed on a grid 10x finer than the program's.")
    acceleration_coefficient: float = Field(description="C_a recomputed likewise.")
    jerk_coefficient: float = Field(description="C_j recomputed likewise.")
    lower_bound: float | None = Field(description="No admissible rise can do better: 4 for the peak acceleration, "
                                      "32 for the peak jerk; null for residual vibration.")
    residual_vibration: float = Field(description="Residual vibration amplitude over the lift at frequency_ratio "
                                      "[-]; 0 when no natural frequency was given.")
    frequency_ratio: float = Field(description="omega_n times the segment's duration [-].")
    end_condition_error: float = Field(description="Largest error of f, f', f'' at both ends [-].")
    knot_intervals: int = Field(description="Knot intervals of the spline.")
    coefficients: list[float] = Field(description="B-spline coefficients of f(u), degree 5, clamped uniform knots.")


class CoilSpringOut(BaseModel):
    """The designed spring as a helical compression spring of round wire (squared and ground ends)."""

    wire: str = Field(description="The wire material.")
    wire_diameter_m: float = Field(description="Wire diameter d [m] (continuous: round up to a stock size).")
    mean_coil_diameter_m: float = Field(description="Mean coil diameter D [m].")
    spring_index: float = Field(description="D/d [-].")
    active_coils: float = Field(description="Active coils [-]; two more in the solid length.")
    free_length_m: float = Field(description="Free length [m].")
    installed_length_m: float = Field(description="Length at the follower's lowest position [m].")
    solid_length_m: float = Field(description="Solid length [m].")
    initial_compression_m: float = Field(description="Preload over rate [m].")
    max_force_N: float = Field(description="Force at full lift [N].")
    max_shear_stress_MPa: float = Field(description="Largest shear stress, Bergsträsser factor [MPa].")
    allowable_shear_stress_MPa: float = Field(description="The wire's allowable static shear stress [MPa].")
    fatigue_factor: float = Field(description="Goodman factor of safety, Zimmerli's unpeened data [-].")
    surge_frequency_Hz: float = Field(description="First surge frequency between flat plates [Hz].")
    surge_order: float = Field(description="Surge frequency over the cam's frequency [-] (at least 13).")


class CamAnalysisOut(BaseModel):
    """A disc cam over one turn: motion, profile, forces, and the checks."""

    cam_angle_deg: list[float] = Field(description="Cam angles of every per-angle list [deg].")
    speed_rpm: float = Field(description="Cam speed [rev/min].")
    motion: MotionOut = Field(description="The follower's motion; its field names carry the follower's unit.")
    profile: CamProfileOut = Field(description="Pitch curve, profile, pressure angle and curvature.")
    forces: CamForcesOut | None = Field(description="Contact force, spring, driving torque; null without loads.")
    optimised_laws: list[OptimisedLawOut] = Field(description="The laws the service optimised, in segment order.")
    checks: CamChecksOut = Field(description="Independent check figures.")
    spring: CoilSpringOut | None = Field(None, description="A designed spring of a translating follower as a "
                                         "coil; null otherwise.")
    warnings: list[WarningOut] = Field(default_factory=list, description="Where the model stops: follower_jump, "
                                       "pressure_angle_high, profile_radius_small, jerk_infinite, spring_surge, "
                                       "spring_fatigue, spring_buckling, hub_radius_missing.")
    validity: list[ValidityCheckOut] = Field(default_factory=list, description="Each condition the model needs "
                                             "against its limit.")


class CamConstraintOut(BaseModel):
    """A limit of the least-cam search at the answer."""

    name: str = Field(description="The limit's request field.")
    limit: float = Field(description="Its value as requested (deg or m).")
    value: float = Field(description="The answer's value (deg or m).")
    active: bool = Field(description="The limit that stops a smaller cam.")


class LeastCamCertificateOut(BaseModel):
    """Why no smaller cam meets the limits."""

    statement: str = Field(description="The method and the certificate in words.")
    grid_points: int = Field(description="Base radii checked over the whole range.")
    evaluations: int = Field(description="Cams evaluated in all.")
    bracket_width_m: float = Field(description="Width of the final bisection bracket [m].")
    monotone: bool = Field(description="Every radius above the answer met the limits on the grid.")
    just_below_fails: str = Field(description="The limit that fails 1e-6 below the answer.")
    offsets_scanned: int = Field(description="Offsets scanned when the offset was free; 0 otherwise.")


class CamSynthesisOut(BaseModel):
    """The least cam: base radius (and offset), the active constraint, the certificate, and the cam analysed."""

    base_radius_m: float = Field(description="Least base circle radius [m].")
    offset_m: float = Field(description="The follower's offset at the answer [m] (the best when free).")
    active_constraint: str = Field(description="The limit that stops a smaller cam (a request field name, or "
                                   "base_radius_min_m when the range's lower end is feasible).")
    constraints: list[CamConstraintOut] = Field(description="Every limit at the answer.")
    certificate: LeastCamCertificateOut = Field(description="How the answer was found and checked.")
    cam: CamAnalysisOut = Field(description="The least cam analysed, with its checks.")


class MotionLawOut(BaseModel):
    """A standard motion law's peak coefficients: peak = C h/beta^k per radian of cam angle."""

    name: str = Field(description="The law's name as segments take it.")
    velocity_coefficient: float = Field(description="C_v.")
    acceleration_coefficient: float = Field(description="C_a, from the closed form.")
    jerk_coefficient: float = Field(description="C_j.")
    textbook_acceleration_coefficient: float = Field(description="C_a as the textbooks print it.")
