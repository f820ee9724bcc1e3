"""The drive with an elastic link: motor rotor and machine as two masses joined by a torsional spring.

Everything is reduced to the crank shaft (seed 000:472-518; the printed equation of motion at 518 is garbled,
the intended one is used): the rotor J_1 = i²·J_rotor (+ what else turns with the motor shaft), the machine
J_2(phi) = J_red(phi) + the constant inertia on its side, the elastic element of stiffness c (the shafts' G·I_p/L
and the couplings' catalogue stiffness, each reduced to the crank by its speed ratio squared, in series) and a
damper b = 2·zeta·sqrt(c·J_1·J_2m/(J_1 + J_2m)):

    J_1·theta_1'' = M_d(theta_1') - M_e,
    J_2(theta_2)·theta_2'' + J_2'(theta_2)·theta_2'²/2 = M_e + M_load(theta_2),
    M_e = c·(theta_1 - theta_2) + b·(theta_1' - theta_2')

with M_d the motor's torque reduced to the crank (i·eta·T(i·w)). The free-free natural frequency is
w = sqrt(c·(J_1 + J_2)/(J_1·J_2)) (J_2 its mean, and its range over the cycle). The steady cycle is found by
a few revolutions integrated with ``solve_ivp`` from the rigid machine's steady motion, then, if the state where
the crank passes its first sample does not yet repeat, Newton shooting on that state (a revolution a step);
the torque in the elastic element over it is compared with the torque the rigid model passes between rotor and
machine, M_d - J_1·alpha (the dynamic factor). The work integrals ride along as
states, so every run reports its energy balance.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicHermiteSpline

from ..analysis import analyse
from ..counter_rotors import CounterRotor
from ..errors import InvalidInput, SolverFailed
from ..flywheel import Motor
from ..friction import PairFriction
from ..model import FloatArray, Linkage
from .simulate import MachineCycle, MachineMotion, simulate_machine
from .startup import simulate_startup

#: Shear modulus of steel [Pa], the default of a shaft element.
STEEL_SHEAR_MODULUS = 81e9
#: A load harmonic within this relative distance of the natural frequency is warned about [-].
NEAR_RESONANCE = 0.15
#: ... when its amplitude is at least this fraction of the largest harmonic's [-].
HARMONIC_SHARE = 0.02
#: Most Newton steps of the shooting for the steady cycle.
MAX_NEWTON = 12
#: Plain revolutions before the Newton steps.
PLAIN_REVOLUTIONS = 6
#: Integrator of the runs: the tables are only piecewise smooth (a kink at every sample), where a low order
#: steps on at a fraction of the high orders' cost.
METHOD = "RK45"
#: The state at the same crank angle counts as repeating within this fraction of the mean speed [-].
PERIODIC_TOLERANCE = 1e-7
#: Newton's residual may stall above :data:`PERIODIC_TOLERANCE` at the integration's own noise (a lightly damped
#: link near a load harmonic amplifies it); below this fraction of the mean speed, a step that no longer halves
#: the residual ends the shooting [-].
NOISE_TOLERANCE = 1e-4
#: Most points of a start-up's time series in an answer.
START_POINTS = 3000


@dataclass(frozen=True, slots=True)
class ElasticElement:
    """One element of the elastic link: a ``shaft`` (``diameter`` [m], ``length`` [m], ``shear_modulus`` [Pa]) or
    a ``coupling`` (catalogue ``stiffness`` [N·m/rad]); ``speed_ratio`` its shaft's speed over the crank's [-]."""

    kind: Literal["shaft", "coupling"]
    speed_ratio: float = 1.0
    diameter: float = 0.0
    length: float = 0.0
    shear_modulus: float = STEEL_SHEAR_MODULUS
    stiffness: float = 0.0

    def own_stiffness(self) -> float:
        """Torsional stiffness on its own shaft [N·m/rad]: G·pi·d⁴/(32·L) for a shaft."""
        if self.kind == "shaft":
            return self.shear_modulus * math.pi * self.diameter**4 / (32 * self.length)
        return self.stiffness

    def reduced_stiffness(self) -> float:
        """Stiffness reduced to the crank [N·m/rad]: the same strain energy at the crank's twist, c·i²."""
        return self.own_stiffness() * self.speed_ratio**2


def link_stiffness(elements: tuple[ElasticElement, ...]) -> float:
    """The elements in series, reduced to the crank: 1/c = sum 1/c_k [N·m/rad]; InvalidInput naming the field."""
    if not elements:
        raise InvalidInput("give the link's stiffness or its elements", field="elements")
    inverse = 0.0
    for k, e in enumerate(elements):
        if not (math.isfinite(e.speed_ratio) and e.speed_ratio > 0):
            raise InvalidInput("the speed ratio must be positive", field=f"elements.{k}.speed_ratio")
        if e.kind == "shaft":
            for name, v in (("diameter_m", e.diameter), ("length_m", e.length), ("shear_modulus_Pa", e.shear_modulus)):
                if not (math.isfinite(v) and v > 0):
                    raise InvalidInput(f"a shaft's {name} must be positive", field=f"elements.{k}.{name}")
        elif not (math.isfinite(e.stiffness) and e.stiffness > 0):
            raise InvalidInput("a coupling's stiffness must be positive", field=f"elements.{k}.stiffness_Nm_rad")
        reduced = e.reduced_stiffness()
        if not (reduced >= sys.float_info.min and math.isfinite(1.0 / reduced)):
            # subnormal or overflowing: 1/c_k would be infinite or lost, and the link's stiffness with it
            culprit = "speed_ratio" if e.speed_ratio < 1 else (
                "stiffness_Nm_rad" if e.kind != "shaft" else "diameter_m")
            raise InvalidInput(f"element {k} reduced to the crank has a stiffness of {reduced:g} N·m/rad, beyond "
                               "what the model computes with", field=f"elements.{k}.{culprit}")
        inverse += 1.0 / reduced
    return 1.0 / inverse


def two_mass_frequency(stiffness: float, j1: float, j2: float) -> float:
    """Free-free natural frequency of two inertias [kg·m²] on a spring [N·m/rad]: sqrt(c·(J1+J2)/(J1·J2))
    [rad/s]."""
    return math.sqrt(stiffness * (j1 + j2) / (j1 * j2))


@dataclass(frozen=True, slots=True)
class LoadHarmonic:
    """A harmonic of the machine's load torque at the mean speed: ``order``, ``frequency`` [Hz], ``amplitude``
    [N·m], ``ratio`` its frequency over the natural frequency [-], ``near`` within :data:`NEAR_RESONANCE` and
    large enough to matter."""

    order: int
    frequency: float
    amplitude: float
    ratio: float
    near: bool


@dataclass(frozen=True, slots=True)
class ElasticRun:
    """A run of the two-mass drive: ``time`` [s], ``phi`` crank angle [rad], ``rotor_speed`` and ``crank_speed``
    [rad/s] (the rotor's reduced to the crank), ``elastic_torque`` in the link [N·m] at each output point; energy
    over the run [J]: ``motor_work``, ``damping_loss``, ``load_work`` (done on the machine by the loads),
    ``energy_change`` (kinetic of both masses plus elastic); ``energy_residual`` motor work + load work -
    damping loss - energy change over the largest of them [-]."""

    time: FloatArray
    phi: FloatArray
    rotor_speed: FloatArray
    crank_speed: FloatArray
    elastic_torque: FloatArray
    motor_work: float
    damping_loss: float
    load_work: float
    energy_change: float
    energy_residual: float


@dataclass(frozen=True, slots=True)
class ElasticDrive:
    """The elastic drive's answer.

    ``stiffness`` of the link reduced to the crank [N·m/rad], ``damping`` [N·m·s/rad]; ``rotor_inertia`` J_1 and
    ``machine_inertia`` J_2 mean, min and max [kg·m²]; ``natural_frequency`` free-free at the mean J_2 and its
    range over the cycle [Hz]; ``eigen_frequency`` the same from the eigenvalues of the linearised two-mass
    matrix (the check of the closed form) [Hz]; ``steady`` the steady cycle at the samples ``phi`` (its energy
    balance over the cycle); ``rigid_torque`` what the rigid model passes between rotor and machine at ``phi``
    [N·m]; ``dynamic_factor`` peak |elastic torque| over peak |rigid torque| [-]; ``harmonics`` of the load
    torque; ``revolutions`` integrated to reach the steady cycle; ``start`` the run-up from rest with the
    elastic link (None when not asked), ``start_peak_torque`` its largest |elastic torque| and
    ``rigid_start_peak_torque`` the rigid run-up's largest motor torque reduced to the crank [N·m];
    ``mean_speed`` of the steady cycle [rad/s].
    """

    stiffness: float
    damping: float
    rotor_inertia: float
    machine_inertia: tuple[float, float, float]
    natural_frequency: float
    natural_frequency_range: tuple[float, float]
    mean_speed: float
    eigen_frequency: float
    phi: FloatArray
    steady: ElasticRun
    rigid_torque: FloatArray
    dynamic_factor: float
    harmonics: tuple[LoadHarmonic, ...]
    revolutions: int
    start: ElasticRun | None
    start_peak_torque: float | None
    rigid_start_peak_torque: float | None


class _Model:
    """The right-hand side of the two-mass drive with its work integrals."""

    def __init__(self, cycle: MachineCycle, machine_constant: float, motor: Motor, j1: float, c: float,
                 b: float) -> None:
        phi0 = float(cycle.phi[0])
        nodes = np.append(cycle.phi, phi0 + 2 * math.pi) - phi0
        self.j = CubicHermiteSpline(nodes, np.append(cycle.inertia, cycle.inertia[0]) + machine_constant,
                                    np.append(cycle.inertia_slope, cycle.inertia_slope[0]))
        self.dj = self.j.derivative()
        self.nodes, self.load = nodes, np.append(cycle.load_torque, cycle.load_torque[0])
        self.phi0, self.motor, self.j1, self.c, self.b = phi0, motor, j1, c, b
        self.i_eta = motor.gear_ratio * motor.efficiency
        # plain lists and floats for the scalar right-hand side
        self.n, self.two_pi, self.step = cycle.phi.size, 2 * math.pi, 2 * math.pi / cycle.phi.size
        self.jt = (np.append(cycle.inertia, cycle.inertia[0]) + machine_constant).tolist()
        self.dt = np.append(cycle.inertia_slope, cycle.inertia_slope[0]).tolist()
        self.lt = self.load.tolist()
        self.gear, self.n_s = motor.gear_ratio, motor.synchronous_speed
        self.slope = motor.rated_torque / (motor.synchronous_speed - motor.rated_speed)
        self.n_b = motor.breakdown_speed
        self.low: tuple[float, float] | None = None
        if motor.starting_torque is not None and motor.breakdown_torque is not None and self.n_b > 0:
            self.low = (motor.starting_torque, (motor.breakdown_torque - motor.starting_torque) / self.n_b)

    def drive(self, w1: FloatArray | float) -> FloatArray:
        """Motor torque reduced to the crank at the rotor's reduced speed [N·m]."""
        return self.i_eta * self.motor.start_torque_at(self.motor.gear_ratio * np.asarray(w1, dtype=float))

    def inertia(self, theta2: FloatArray | float) -> FloatArray:
        """J_2 at crank angle theta_2 [kg·m²]."""
        return np.asarray(self.j((np.asarray(theta2) - self.phi0) % (2 * math.pi)), dtype=float)

    def rhs(self, t: float, y: FloatArray) -> FloatArray:
        """d/dt of (theta_1 - theta_2, w_1, theta_2, w_2, motor work, damping loss, load work), in scalar
        arithmetic (a solver calls it tens of thousands of times); the twist is a state of its own, so it is not
        the small difference of two large angles."""
        twist, w1, th2, w2 = float(y[0]), float(y[1]), float(y[2]), float(y[3])
        s = ((th2 - self.phi0) % self.two_pi) / self.step
        k = int(s)
        f = s - k
        k %= self.n
        jt, dt, lt = self.jt, self.dt, self.lt
        h = self.step
        j2 = ((2 * f**3 - 3 * f**2 + 1) * jt[k] + (f**3 - 2 * f**2 + f) * h * dt[k] + (-2 * f**3 + 3 * f**2) * jt[k + 1]
              + (f**3 - f**2) * h * dt[k + 1])
        dj2 = ((6 * f**2 - 6 * f) * (jt[k] - jt[k + 1]) / h + (3 * f**2 - 4 * f + 1) * dt[k]
               + (3 * f**2 - 2 * f) * dt[k + 1])
        load = lt[k] + f * (lt[k + 1] - lt[k])
        speed = self.gear * w1
        if self.low is not None and speed < self.n_b:
            torque = self.low[0] + self.low[1] * speed
        else:
            torque = self.slope * (self.n_s - speed)
        m_d = self.i_eta * torque
        twist_rate = w1 - w2
        m_e = self.c * twist + self.b * twist_rate
        return np.array([twist_rate, (m_d - m_e) / self.j1, w2, (m_e + load - 0.5 * dj2 * w2 * w2) / j2, m_d * w1,
                         self.b * twist_rate**2, load * w2])

    def energy(self, y: FloatArray) -> FloatArray:
        """Kinetic energy of both masses plus the spring's [J] at states (7, M)."""
        return np.asarray(0.5 * self.j1 * y[1] ** 2 + 0.5 * self.inertia(y[2]) * y[3] ** 2
                          + 0.5 * self.c * y[0] ** 2, dtype=float)

    def run(self, y: FloatArray, t: FloatArray) -> ElasticRun:
        """An :class:`ElasticRun` of states (7, M) at times ``t``."""
        torque = self.c * y[0] + self.b * (y[1] - y[3])
        e = self.energy(y)
        motor, damping, load = (float(y[k, -1] - y[k, 0]) for k in (4, 5, 6))
        change = float(e[-1] - e[0])
        scale = max(abs(motor), abs(damping), abs(load), abs(change), 1e-300)
        return ElasticRun(t - t[0], y[2], y[1], y[3], torque, motor, damping, load, change,
                          (motor + load - damping - change) / scale)


def elastic_drive(cycle: MachineCycle, motor: Motor, stiffness: float, *, machine_inertia: float = 0.0,
                  motor_side_inertia: float = 0.0, damping_ratio: float = 0.05, start: bool = True,
                  start_cycle: MachineCycle | None = None) -> ElasticDrive:
    """The machine driven through an elastic link (see the module's notes).

    Parameters
    ----------
    cycle
        The linkage reduced to its crank, uniform samples over one revolution [kg·m², N·m].
    motor
        The motor through its train (ratio, efficiency, rotor inertia on the motor shaft).
    stiffness
        The link's torsional stiffness reduced to the crank [N·m/rad] (see :func:`link_stiffness`).
    machine_inertia
        Constant inertia on the machine's side (flywheel, gears) reduced to the crank [kg·m²].
    motor_side_inertia
        Constant inertia on the motor shaft besides the rotor, on that shaft [kg·m²].
    damping_ratio
        The link's damping as a ratio of the critical damping of the two-mass mode [-].
    start
        Also simulate the run-up from rest with the elastic link.
    start_cycle
        The machine the run-up drives, when it is not ``cycle`` (a machine that runs up idling and takes its
        process load once it runs).
    """
    for name, v in (("stiffness_Nm_rad", stiffness),):
        if not (math.isfinite(v) and v > 0):
            raise InvalidInput("the link's stiffness must be positive", field=name)
    for name, v in (("machine_inertia_kgm2", machine_inertia), ("motor_side_inertia_kgm2", motor_side_inertia),
                    ("damping_ratio", damping_ratio)):
        if not (math.isfinite(v) and v >= 0):
            raise InvalidInput(f"{name} must not be negative", field=name)
    n = cycle.phi.size
    if n < 3 or not np.allclose(np.diff(cycle.phi), 2 * math.pi / n, rtol=1e-9, atol=1e-12):
        raise InvalidInput("the elastic drive takes uniformly spaced crank angles over one revolution",
                           field="samples")
    i = motor.gear_ratio
    j1 = i * i * (motor.rotor_inertia + motor_side_inertia)
    if j1 <= 0:
        raise InvalidInput("the motor's side has no inertia: give the rotor inertia (or a catalogue motor)",
                           field="motor.rotor_inertia_kgm2")
    j2_all = cycle.inertia + machine_inertia
    if not np.all(j2_all > 0):
        raise InvalidInput("the machine has no inertia at some crank angles", field="machine_inertia_kgm2")
    j2 = float(np.mean(j2_all))
    if not (math.isfinite(stiffness / j1) and stiffness / j1 >= sys.float_info.min):
        raise InvalidInput(f"the motor's side (inertia {j1:g} kg·m² at the crank) and the link's stiffness "
                           f"({stiffness:g} N·m/rad) give no natural frequency the model computes with",
                           field="motor.rotor_inertia_kgm2" if j1 < 1e-100 else "stiffness_Nm_rad")
    if not (math.isfinite(stiffness / j2) and stiffness / j2 >= sys.float_info.min
            and math.isfinite(float(np.max(cycle.load_torque, initial=0.0)) / stiffness)):
        raise InvalidInput(f"the link's stiffness {stiffness:g} N·m/rad is beyond what the model computes with "
                           f"against the machine's inertia ({j2:g} kg·m²)", field="stiffness_Nm_rad")
    wn = two_mass_frequency(stiffness, j1, j2)
    b = 2 * damping_ratio * math.sqrt(stiffness * j1 * j2 / (j1 + j2))
    # the same frequency from the two-mass matrix's eigenvalues: one zero (rigid rotation), one w²
    lam = np.linalg.eigvals(np.array([[stiffness / j1, -stiffness / j1], [-stiffness / j2, stiffness / j2]]))
    eigen = math.sqrt(float(np.max(lam.real)))
    model = _Model(cycle, machine_inertia, motor, j1, stiffness, b)

    rigid = simulate_machine(cycle, j1 + machine_inertia, motor)
    mean = rigid.mean_speed
    period = 2 * math.pi / mean
    phi0 = float(cycle.phi[0])
    w_start = float(np.interp(phi0, rigid.phi, rigid.omega, period=2 * math.pi))
    m_start = float(model.drive(w_start))
    a_start = float(np.interp(phi0, rigid.phi, rigid.alpha, period=2 * math.pi))
    twist = (m_start - j1 * a_start) / stiffness
    y = np.array([phi0 + twist, w_start, phi0, w_start, 0.0, 0.0, 0.0])
    max_step = min(2 * math.pi / wn / 8, period / 64)
    twist_scale = abs(twist) + float(np.max(np.abs(cycle.load_torque))) / stiffness + 1e-12
    scale = np.array([twist_scale, mean, mean])
    work = 2 * math.pi * (float(np.max(np.abs(cycle.load_torque))) + stiffness * twist_scale)
    atol = 1e-9 * np.array([twist_scale, mean, 2 * math.pi, mean, work, work, work])

    def revolution(z: FloatArray, dense: bool = False) -> Any:
        """One revolution from theta_2 = phi0 with (twist, w1, w2) = z."""
        y0 = np.array([z[0], z[1], phi0, z[2], 0.0, 0.0, 0.0])

        def around(t: float, y: FloatArray) -> float:
            return float(y[2] - phi0 - 2 * math.pi)

        around.terminal = True  # type: ignore[attr-defined]
        around.direction = 1  # type: ignore[attr-defined]
        sol = solve_ivp(model.rhs, (0.0, 20 * period), y0, method=METHOD, rtol=1e-8, atol=atol,
                        dense_output=dense, max_step=max_step, events=around)
        if not sol.success or sol.status != 1:
            raise SolverFailed("no_periodic_motion", "the elastic drive stalled within a revolution")
        return sol

    def step_map(z: FloatArray) -> FloatArray:
        end = revolution(z).y_events[0][0]
        return np.array([end[0], end[1], end[3]])

    z = np.array([twist, w_start, w_start])
    revs = 0
    settled = False
    # a few plain revolutions first: from the rigid motion a quick drive settles in these already, and each
    # costs one run where a Newton step costs four
    for _ in range(PLAIN_REVOLUTIONS):
        z_next = step_map(z)
        revs += 1
        settled = bool(np.all(np.abs(z_next - z) <= PERIODIC_TOLERANCE * scale))
        z = z_next
        if settled:
            break
    # then Newton shooting on the state where the crank passes phi0, Jacobian by differences (a revolution each)
    newton = 0
    last = math.inf
    while not settled:
        if newton == MAX_NEWTON:
            raise SolverFailed("no_periodic_motion", f"the elastic drive's shooting did not converge in "
                               f"{MAX_NEWTON} steps")
        z_next = step_map(z)
        revs += 1
        r = z_next - z
        size = float(np.max(np.abs(r) / scale))
        if size <= PERIODIC_TOLERANCE or (size <= NOISE_TOLERANCE and size > 0.5 * last):
            break
        last = size
        jac = np.empty((3, 3))
        for k in range(3):
            dz = np.zeros(3)
            dz[k] = 1e-4 * scale[k]
            jac[:, k] = (step_map(z + dz) - z_next) / dz[k]
            revs += 1
        z = z + np.linalg.solve(jac - np.eye(3), -r)
        newton += 1
    sol = revolution(z, dense=True)
    t_end = float(sol.t_events[0][0])
    starting = None
    if start:
        starting = cycle if start_cycle is None else start_cycle
    return _finish(model, sol, (0.0, sol.y[:, 0]), (t_end, sol.y_events[0][0]), cycle, rigid, stiffness, b, j1,
                   j2_all, wn, eigen, revs + 1, motor, machine_inertia, starting)


def _finish(model: _Model, sol: Any, a: tuple[float, FloatArray], b_: tuple[float, FloatArray],
            cycle: MachineCycle, rigid: MachineMotion, stiffness: float, damping: float, j1: float, j2_all: FloatArray,
            wn: float, eigen: float, revs: int, motor: Motor, machine_inertia: float,
            start: MachineCycle | None) -> ElasticDrive:
    ta, tb = a[0], b_[0]
    grid = np.linspace(ta, tb, 40 * cycle.phi.size + 1)
    ys = sol.sol(grid)
    angle = ys[2] - a[1][2] + cycle.phi[0]
    t_at = np.interp(cycle.phi, angle, grid)
    y_at = sol.sol(np.append(t_at, tb))
    steady = model.run(y_at, np.append(t_at, tb))
    steady = ElasticRun(steady.time[:-1], cycle.phi, steady.rotor_speed[:-1], steady.crank_speed[:-1],
                        steady.elastic_torque[:-1], steady.motor_work, steady.damping_loss, steady.load_work,
                        steady.energy_change, steady.energy_residual)
    rm = rigid
    r_alpha = np.interp(cycle.phi, rm.phi, rm.alpha, period=2 * math.pi)
    r_omega = np.interp(cycle.phi, rm.phi, rm.omega, period=2 * math.pi)
    rigid_torque = model.drive(r_omega) - j1 * r_alpha
    factor = float(np.max(np.abs(steady.elastic_torque)) / max(float(np.max(np.abs(rigid_torque))), 1e-300))
    mean_speed = 2 * math.pi / (tb - ta)
    spectrum = np.abs(np.fft.rfft(cycle.load_torque)) * 2 / cycle.phi.size
    top = float(spectrum[1:].max()) if spectrum.size > 1 else 0.0
    harmonics = []
    for k in range(1, min(spectrum.size, (cycle.phi.size - 1) // 2 + 1)):
        if spectrum[k] < 1e-9 * max(top, 1e-300):
            continue
        ratio = k * mean_speed / wn
        near = abs(ratio - 1) <= NEAR_RESONANCE and spectrum[k] >= HARMONIC_SHARE * top
        harmonics.append(LoadHarmonic(k, k * mean_speed / (2 * math.pi), float(spectrum[k]), ratio, bool(near)))
    j2m = float(np.mean(j2_all))
    freqs = (two_mass_frequency(stiffness, j1, float(j2_all.max())) / (2 * math.pi),
             two_mass_frequency(stiffness, j1, float(j2_all.min())) / (2 * math.pi))
    run, peak, rigid_peak = None, None, None
    if start is not None:
        start_model = model if start is cycle else _Model(start, machine_inertia, motor, j1, stiffness, damping)
        run, peak, rigid_peak = _start(start_model, start, motor, j1, machine_inertia, wn)
    return ElasticDrive(stiffness, damping, j1, (j2m, float(j2_all.min()), float(j2_all.max())),
                        wn / (2 * math.pi), freqs, mean_speed, eigen / (2 * math.pi), cycle.phi, steady, rigid_torque,
                        factor,
                        tuple(harmonics), revs, run, peak, rigid_peak)


def _start(model: _Model, cycle: MachineCycle, motor: Motor, j1: float, machine_inertia: float,
           wn: float) -> tuple[ElasticRun, float, float]:
    """The run-up from rest with the elastic link, as long as the rigid run-up takes and a little more."""
    rigid = simulate_startup(cycle, j1 + machine_inertia, motor)
    if rigid.run is None:
        raise InvalidInput("the motor cannot start the machine, so there is no run-up to simulate",
                           field="start")
    end = rigid.steady_time if rigid.steady_time is not None else float(rigid.run.time[-1])
    mean = rigid.steady.mean_speed
    horizon = 1.2 * end + 3 * 2 * math.pi / mean
    phi0 = float(rigid.run.phi[0])
    y0 = np.array([0.0, 0.0, phi0, 0.0, 0.0, 0.0, 0.0])
    sol = solve_ivp(model.rhs, (0.0, horizon), y0, method=METHOD, rtol=1e-8, atol=1e-9,
                    max_step=min(2 * math.pi / wn / 8, 2 * math.pi / mean / 64))
    if not sol.success:
        raise SolverFailed("integration_failed", f"the elastic run-up's integration failed: {sol.message}")
    full = model.run(sol.y, sol.t)
    step = max(1, sol.t.size // START_POINTS)
    keep = np.append(np.arange(0, sol.t.size, step), sol.t.size - 1) if (sol.t.size - 1) % step else np.arange(
        0, sol.t.size, step)
    run = ElasticRun(full.time[keep], full.phi[keep], full.rotor_speed[keep], full.crank_speed[keep],
                     full.elastic_torque[keep], full.motor_work, full.damping_loss, full.load_work,
                     full.energy_change, full.energy_residual)
    rigid_peak = rigid.peak_motor_torque * motor.gear_ratio * motor.efficiency
    return run, float(np.max(np.abs(full.elastic_torque))), float(rigid_peak)


def elastic_drive_for_linkage(linkage: Linkage, speed: float, motor: Motor, *, stiffness: float | None = None,
                              elements: tuple[ElasticElement, ...] = (), samples: int = 360,
                              max_samples: int = 100_000, counter_rotors: tuple[CounterRotor, ...] = (),
                              friction: tuple[PairFriction, ...] = (), machine_inertia: float = 0.0,
                              motor_side_inertia: float = 0.0, damping_ratio: float = 0.05,
                              start: bool = True) -> ElasticDrive:
    """Analyse ``linkage`` at crank ``speed`` [rad/s], reduce it to its crank (its friction losses taken off the
    load) and drive it through the elastic link of ``stiffness`` [N·m/rad at the crank] or of ``elements``."""
    if (stiffness is None) == (not elements):
        raise InvalidInput("give the link's stiffness or its elements, one of the two", field="stiffness_Nm_rad")
    c = stiffness if stiffness is not None else link_stiffness(elements)
    an = analyse(linkage, speed, samples=samples, max_samples=max_samples, counter_rotors=counter_rotors,
                 friction=friction)
    red = an.reduced
    cycle = MachineCycle(red.phi, red.inertia, red.inertia_slope, red.resisting_torque)
    return elastic_drive(cycle, motor, c, machine_inertia=machine_inertia, motor_side_inertia=motor_side_inertia,
                         damping_ratio=damping_ratio, start=start)
