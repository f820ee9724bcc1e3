"""Schemas of POST /v1/analysis."""

from __future__ import annotations

from typing import Literal, get_args

from pydantic import BaseModel, ConfigDict, Field

from .common import (
    FOURBAR_EXAMPLE,
    SIX_BAR_PRESS_EXAMPLE,
    MAX_INERTIA_KGM2,
    CounterweightIn,
    FrictionIn,
    LinkageRequest,
    StrictModel,
    SummaryOut,
    Vec2,
    WarningOut,
)


class TracePointIn(StrictModel):
    """A named point fixed in a link (a coupler point, a tool tip) whose motion is reported."""

    name: str = Field(min_length=1, max_length=40, description="Name of the point in the answer's `points`.",
                      examples=["coupler_point"])
    link: str = Field(description="Link the point is fixed in, by name.", examples=["coupler"])
    position_m: Vec2 = Field(description="Position in the link frame [m].", examples=[[0.175, 0.08]])


class CounterRotorIn(StrictModel):
    """A counter-rotating inertia geared to a link at -ratio times its speed (a full-balance answer's)."""

    link: str = Field(description="Link the rotor is geared to, by name.", examples=["crank"])
    inertia_kgm2: float = Field(ge=0, le=MAX_INERTIA_KGM2, description="Rotor inertia about its axis [kg·m²].",
                                examples=[0.03])
    ratio: float = Field(1.0, gt=0, le=1e3, description="Rotor speed over the link's speed, counter-rotating [-].")


class BalancingAnswerIn(BaseModel):
    """A balancing answer sent back as it is: its counterweights, coupler inertia and counter-rotors are used,
    everything else in it (summaries, checks, placements) is ignored."""

    model_config = ConfigDict(extra="ignore", allow_inf_nan=False)

    counterweights: list[CounterweightIn] = Field(default_factory=list, max_length=20,
                                                  description="The answer's counterweights.")
    coupler_inertia_kgm2: float | None = Field(None, ge=0, le=MAX_INERTIA_KGM2, description="The coupler's inertia "
                                               "about its centre that full balancing asks for [kg·m²].")
    counter_rotors: list[CounterRotorIn] | None = Field(None, max_length=10,
                                                        description="The answer's counter-rotors (full balancing).")


class AnalysisIn(LinkageRequest):
    """A linkage, its speed, loads and optional counterweights, to analyse over one crank revolution."""

    instant_centres: bool = Field(False, description="Add every link's instant centre relative to the frame over "
                                  "the cycle and the coupler's centrodes (`centres`).")
    relative_centres: bool = Field(False, description="With `instant_centres`: every pair of links' relative "
                                   "centre too.")
    path_curvature: bool = Field(False, description="Add the curvature of every point's path (`curvature`).")

    def geometry_request(self) -> tuple[bool, bool, bool]:
        """The optional kinematic geometry asked for: centres, relative centres, curvature."""
        return self.instant_centres or self.relative_centres, self.relative_centres, self.path_curvature

    trace_points: list[TracePointIn] = Field(
        default_factory=list, max_length=20, description="Extra points to report, e.g. coupler points."
    )
    counter_rotors: list[CounterRotorIn] = Field(
        default_factory=list, max_length=10,
        description="Counter-rotating inertias (a full balance's): in the shaking moment, driving torque and J_red.")
    coupler_inertia_kgm2: float | None = Field(
        None, ge=0, le=MAX_INERTIA_KGM2,
        description="Replaces the coupler's inertia about its centre of mass (a full balance's pendulum coupler).")
    balancing: BalancingAnswerIn | None = Field(
        None, description="A /v1/balancing answer as it is: its counterweights, coupler inertia and counter-rotors "
        "are added to this linkage.")
    friction: FrictionIn | None = Field(
        None, description="Friction per pair: the answer's `friction` block then holds the reactions and the "
        "driving torque with friction, each pair's friction and power loss, and the efficiency.")

    def trace(self) -> dict[str, tuple[str, tuple[float, float]]]:
        """Trace points as the engine takes them: name -> (link, position in the link frame)."""
        return {p.name: (p.link, (p.position_m[0], p.position_m[1])) for p in self.trace_points}

    model_config = ConfigDict(
        json_schema_extra={
            "examples": [
                {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 360},
                {
                    "mechanism": {
                        "type": "slotted_lever",
                        "crank_length_m": 0.1,
                        "ground_length_m": 0.3,
                        "rocker_length_m": 0.6,
                        "ram_height_m": 0.7,
                        "links": {
                            "crank": {"mass_kg": 5.0},
                            "rocker": {"mass_kg": 10.0, "com_m": [0.25, 0.0], "inertia_kgm2": 0.3},
                            "ram": {"mass_kg": 12.0},
                        },
                    },
                    "speed_rpm": 38.197,
                    "gravity": {"g_m_s2": 9.81},
                    "loads": [{"type": "window", "force_N": 1200, "start_deg": -60, "end_deg": 60, "point_m": [0, -0.1]}],
                },
                {"mechanism": SIX_BAR_PRESS_EXAMPLE, "speed_rpm": 60, "samples": 360,
                 "loads": [{"type": "window", "force_N": 2000, "start_deg": 200, "end_deg": 300}]},
            ]
        }
    )


Grashof = Literal["crank-rocker", "double-crank", "double-rocker", "rocker-crank", "change-point", "triple-rocker"]
GRASHOF_CLASSES: tuple[Grashof, ...] = get_args(Grashof)


class PointOut(BaseModel):
    """A point's position [m], velocity [m/s] and acceleration [m/s²] at every sample, as [x, y] pairs."""

    position_m: list[list[float]] = Field(description="Position [x, y] in the fixed frame (origin at the crank "
                                          "pivot O) at each crank angle of `crank_angle_deg` [m].")
    velocity_m_s: list[list[float]] = Field(description="Absolute velocity [vx, vy] at each crank angle [m/s].")
    acceleration_m_s2: list[list[float]] = Field(description="Absolute acceleration [ax, ay] at each crank angle "
                                                 "[m/s²].")


class LinkMotionOut(BaseModel):
    """A link's angle [deg], angular velocity [rad/s] and angular acceleration [rad/s²] at every sample."""

    angle_deg: list[float] = Field(description="Angle of the link frame's x-axis (first joint toward the second) "
                                   "from the fixed x-axis, counter-clockwise positive, at each crank angle [deg]; a "
                                   "block on a fixed guide keeps the guide's angle.")
    angular_velocity_rad_s: list[float] = Field(description="Angular velocity at each crank angle [rad/s], "
                                                "counter-clockwise positive.")
    angular_acceleration_rad_s2: list[float] = Field(description="Angular acceleration at each crank angle "
                                                     "[rad/s²], counter-clockwise positive.")


class ChecksOut(BaseModel):
    """Independent check figures carried with the result."""

    virtual_power_torque_max_diff_Nm: float = Field(
        description="Largest difference over the samples between the kinetostatic and the virtual-power driving "
        "torque [N·m]."
    )
    loop_closure_m: float | None = Field(
        None, description="General linkages: the largest distance over every pair and sample between where its two "
        "links put it (each revolute's point from each link's position and angle, each slider point from its axis) "
        "[m]; zero to rounding when every loop closes (passive links and groups placed numerically included). "
        "Null for the named families.")


class PairFrictionOut(BaseModel):
    """One pair's friction at every sample."""

    kind: Literal["revolute", "prismatic"] = Field(description="The pair's kind: a revolute pair's friction is a "
                                                   "moment, a slide's a force.")
    friction_moment_Nm: list[float] | None = Field(None, description="Revolute pair: the friction moment on the "
                                                   "pair's second link at each sample, counter-clockwise positive "
                                                   "[N·m]; null for a slide.")
    friction_force_N: list[float] | None = Field(None, description="Slide: the friction force on the pair's second "
                                                 "link along the slide axis at each sample [N]; null for a revolute "
                                                 "pair.")
    power_loss_W: list[float] = Field(description="Power the pair's friction dissipates at each sample [W] (>= 0).")
    mean_power_loss_W: float = Field(description="Power loss averaged over the samples [W].")


class FrictionChecksOut(BaseModel):
    """How the friction solve ended, and its independent check."""

    newton_residual: float = Field(description="Largest equilibrium residual over the samples at the end, relative "
                                   "to the largest known load [-]; the solve stops below 1e-12.")
    newton_iterations: int = Field(description="Newton iterations taken (all samples at once).")
    virtual_power_max_diff_Nm: float = Field(description="Largest |T - T0 - P_loss/w| over the samples [N·m]: the "
                                             "drive supplies exactly what friction dissipates (virtual power).")


class FrictionOut(BaseModel):
    """The kinetostatics with friction in the pairs; the shaking force and moment do not change (friction acts
    between the frame and the linkage, and the motor housing takes back what the frame's pairs lose)."""

    driving_torque_Nm: list[float] = Field(description="Driving torque with friction at each sample [N·m], same "
                                           "sign convention as the frictionless `driving_torque_Nm`.")
    loss_torque_Nm: list[float] = Field(description="Total friction power loss over the crank speed at each "
                                        "sample [N·m]: the driving torque with friction less the one without.")
    joint_reactions_N: dict[str, list[list[float]]] = Field(description="Per joint: the force [Fx, Fy] its first "
                                                            "link exerts on its second with friction [N]; a slide's "
                                                            "is its normal force (the friction force is in "
                                                            "`pairs`).")
    prismatic_couples_Nm: dict[str, list[float]] = Field(description="Per slide: its couple with friction [N·m].")
    pairs: dict[str, PairFrictionOut] = Field(description="Per pair with friction, by joint name.")
    efficiency: list[float | None] = Field(description="Instantaneous mechanical efficiency 1 - P_loss/(T·w) at "
                                           "each sample where the drive puts power in [-]; null where it does not.")
    cycle_efficiency: float | None = Field(description="1 - lost work / driving work over the cycle [-]; null when "
                                           "the drive does no net work or the samples are not one uniform cycle.")
    mean_power_loss_W: float = Field(description="All pairs' power loss averaged over the samples [W].")
    checks: FrictionChecksOut = Field(description="Solve residual and the virtual-power check.")


class CentresOut(BaseModel):
    """Instant centres over the cycle as unit homogeneous coordinates [x·w, y·w, w]: the point is (x, y) where
    w ≠ 0; w = 0 puts it at infinity in the direction (x, y) (a link that translates)."""

    absolute: dict[str, list[list[float]]] = Field(description="Each link's centre relative to the frame.")
    relative: dict[str, list[list[float]]] = Field(description="Each pair of bodies' relative centre, keyed "
                                                   "`a/b` (the frame is `frame`); empty unless asked for.")
    coupler: str | None = Field(None, description="The link whose centrodes are given.")
    fixed_centrode: list[list[float]] | None = Field(None, description="The coupler's centre in the frame.")
    moving_centrode: list[list[float]] | None = Field(None, description="The same points in the coupler's own "
                                                      "frame (origin at its first joint, x-axis along it).")
    kennedy_check: float = Field(description="Check: the largest |det| of three relative centres of any three "
                                 "bodies (Kennedy: collinear, so zero to rounding).")


class CurvatureOut(BaseModel):
    """The curvature of a point's path over the cycle."""

    curvature_1_m: list[float] = Field(description="Signed curvature (v × a)/|v|³ [1/m], counter-clockwise "
                                       "positive; the radius of curvature is its inverse (rho = |v|³/|v × a|). "
                                       "Zero where the point stops.")
    stopped_deg: list[float] = Field(description="Crank angles where the point stops and its path has no "
                                     "curvature [deg].")


class AnalysisOut(BaseModel):
    """Kinematics and kinetostatics over the cycle; reactions are forces of a joint's first link on its second."""

    crank_angle_deg: list[float] = Field(description="Crank angle of each sample [deg], counter-clockwise from "
                                         "the frame's x-axis (O->Q for a four-bar); every other array has one "
                                         "entry per sample, in this order.")
    driving_torque_Nm: list[float] = Field(description="Torque the drive applies to the crank at each sample "
                                           "[N·m], counter-clockwise positive, the crank's direction of rotation: "
                                           "positive while the drive puts power in.")
    virtual_power_torque_Nm: list[float] = Field(description="The driving torque recomputed at each sample from "
                                                 "virtual power (the powers of all loads and inertia forces sum to "
                                                 "zero), independently of the reaction solve; same sign [N·m].")
    shaking_force_N: list[list[float]] = Field(description="Force [Fx, Fy] the linkage exerts on the frame at each "
                                               "sample, -sum(m·a_S) over the links [N]; gravity and process loads "
                                               "are reacted by the frame and not part of it.")
    shaking_moment_Nm: list[float] = Field(description="Moment the linkage exerts on the frame about the crank "
                                           "pivot O at each sample, counter-clockwise positive [N·m]; includes the "
                                           "reaction of the driving torque on the motor housing, not gravity or "
                                           "process loads.")
    reduced_inertia_kgm2: list[float] = Field(description="Reduced (equivalent) inertia J_red of the whole linkage "
                                              "on the crank at each sample, sum(m·|v_S/w|² + J_S·(w_i/w)²) "
                                              "[kg·m²], the crank's own inertia and any counter-rotors included.")
    reduced_inertia_slope_kgm2_per_rad: list[float] = Field(description="dJ_red/dphi at each sample [kg·m²/rad].")
    reduced_load_torque_Nm: list[float] = Field(description="Reduced torque of the process loads, link torques and "
                                                "gravity on the crank at each sample (their power over the crank "
                                                "speed) [N·m]; positive drives the crank, negative resists.")
    kinetic_energy_J: list[float] = Field(description="Kinetic energy of the linkage at each sample at the request's "
                                          "crank speed, J_red·w²/2 [J].")
    joint_reactions_N: dict[str, list[list[float]]] = Field(description="Per joint by name (O, A, B, Q, guide, "
                                                            "...): the force [Fx, Fy] its first link exerts on its "
                                                            "second (the frame first for frame joints) at each "
                                                            "sample [N]; a prismatic joint's is normal to its "
                                                            "slide.")
    prismatic_couples_Nm: dict[str, list[float]] = Field(description="Per prismatic joint by name: the couple its "
                                                         "first link exerts on its second at each sample, "
                                                         "counter-clockwise positive [N·m].")
    links: dict[str, LinkMotionOut] = Field(description="Per link by name: its angle, angular velocity and "
                                            "angular acceleration at each sample.")
    points: dict[str, PointOut] = Field(description="Per point by name: every joint, every link's centre of mass "
                                        "(`S_<link>`) and each trace point, with position, velocity and "
                                        "acceleration at each sample.")
    transmission_angle_deg: list[float] | None = Field(None, description="Four-bar: angle between coupler and "
                                                       "rocker at each sample, in [0, 180] [deg] (90 transmits "
                                                       "best); null for other mechanisms.")
    grashof: Grashof | None = Field(None, description="Grashof class of a four-bar; null for other mechanisms.")
    summary: SummaryOut = Field(description="RMS and peak shaking force, shaking moment and driving torque over "
                                "the samples, and the largest bearing force.")
    checks: ChecksOut = Field(description="Independent check figures of this answer.")
    friction: FrictionOut | None = Field(None, description="With friction in the pairs (when the request gives "
                                         "any): reactions, driving torque, losses and efficiency; null without.")
    warnings: list[WarningOut] = Field(default_factory=list, description="Likely mistakes in the request.")
    assumptions: list[str] = Field(default_factory=list, description="What the answer assumes beyond rigid links "
                                   "and ideal pairs: how statically indeterminate reactions are split (redundant "
                                   "pairs), how a group of class III or above is placed.")
    centres: CentresOut | None = Field(None, description="With `instant_centres`: instant centres and centrodes.")
    curvature: dict[str, CurvatureOut] | None = Field(None, description="With `path_curvature`: per point by "
                                                      "name, the curvature of its path.")

    def to_lists(self) -> AnalysisOut:
        """The same answer validated as a plain pydantic model (numpy arrays turned into lists)."""
        return AnalysisOut.model_validate(_lists(self))


def _lists(value: object) -> object:
    if isinstance(value, BaseModel):
        return {name: _lists(getattr(value, name)) for name in type(value).model_fields}
    if isinstance(value, dict):
        return {key: _lists(item) for key, item in value.items()}
    if hasattr(value, "tolist"):     # the engine's arrays, as the service builds the answer
        return value.tolist()
    return value
