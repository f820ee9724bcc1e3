"""The machine on its foundation: the frame as a rigid body in the plane on elastic isolators.

The frame (the whole machine: bed, housings and the linkage's links, mass ``m`` and inertia ``J`` about its
centre C) moves a little in its plane, q = (x, y, theta) of C; the linkage drives it with its shaking force F(t)
and shaking moment (about the crank pivot O, moved to C: M_C = M_O - (C - O) x F). An isolator at P_i passes on
u_i = A_i q, A_i = [[1, 0, -r_y], [0, 1, r_x]] with r = P_i - C, and resists with K_i u_i + C_i u_i'; what the
foundation feels is that force, + (K_i u_i + C_i u_i'). So M q'' + C q' + K q = G(t), K = sum A_i^T K_i A_i.

The steady cycle is periodic: G(t) is written as its harmonics (the FFT of the analysis' samples at the crank
speed) and each harmonic solved exactly, (K - (k w)^2 M + i k w C) Q_k = G_k (seed 003:762-835 for one degree of
freedom: z_max = (F/m)/sqrt((w0^2 - w^2)^2 + 4 n^2 w^2)). The independent check integrates the same equations in
time with scipy's ``solve_ivp`` and finds their periodic state by shooting: for linear equations the state after
one period is x(T) = Phi x(0) + x_p(T), so x(0) = (I - Phi)^-1 x_p(T) is the state every start settles into,
after as many cycles as it takes (reported as the settling time).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, replace

import numpy as np
import numpy.typing as npt
import scipy.linalg
from scipy.integrate import solve_ivp

from ..analysis import Analysis, analyse
from ..counter_rotors import CounterRotor
from ..errors import Infeasible, InvalidInput
from ..flywheel import Motor
from ..kinetostatics import link_arrays
from ..model import FloatArray, Linkage
from ..warnings import DesignWarning, ValidityCheck, angle_ranges
from .simulate import MachineCycle
from .startup import StartUp, simulate_startup

ComplexArray = npt.NDArray[np.complex128]
#: Standard gravity, for the static deflection under the machine's weight [m/s²].
G = 9.80665
#: Harmonics of the shaking force smaller than this fraction of the largest are left out [-].
HARMONIC_CUT = 1e-7
#: A rigid-body mode counts as free when its stiffness is below this fraction of the largest [-].
FREE_MODE = 1e-10
#: A harmonic carries energy when its shaking force or moment is at least this fraction of the largest [-].
ENERGY_SHARE = 0.01
#: Isolation needs every harmonic with energy at least sqrt(2) times above every natural frequency.
ISOLATION_RATIO = math.sqrt(2.0)
#: A harmonic within this fraction of a natural frequency drives that mode near resonance [-] ...
NEAR_MODE = 0.25
#: ... where its damping ratio should be at least this (amplification 1/(2·zeta) at most 5) [-].
MIN_MODE_DAMPING = 0.1


@dataclass(frozen=True, slots=True)
class Isolator:
    """One isolator: ``position`` (x, y) in the linkage's coordinates [m]; stiffness ``kx``, ``ky`` [N/m];
    damping as coefficients ``cx``, ``cy`` [N·s/m], or as a ``damping_ratio`` [-] of the share of the machine's
    mass it carries (its part of the summed vertical stiffness): c = 2·zeta·sqrt(k·m_share)."""

    position: tuple[float, float]
    kx: float
    ky: float
    cx: float = 0.0
    cy: float = 0.0
    damping_ratio: float | None = None


@dataclass(frozen=True, slots=True)
class Frame:
    """The machine as one rigid body: ``mass`` [kg], ``inertia`` about its centre [kg·m²], ``centre`` (x, y) in the
    linkage's coordinates [m]."""

    mass: float
    inertia: float
    centre: tuple[float, float]


@dataclass(frozen=True, slots=True)
class Forcing:
    """The linkage's pull on the frame over one steady cycle at constant crank ``speed`` [rad/s]: ``phi`` uniform
    crank angles [rad] (N,), ``force`` the shaking force [N] (N, 2), ``moment`` the shaking moment about the crank
    pivot O [N·m] (N,)."""

    phi: FloatArray
    speed: float
    force: FloatArray
    moment: FloatArray

    @property
    def period(self) -> float:
        """One crank revolution [s]."""
        return 2 * math.pi / self.speed


@dataclass(frozen=True, slots=True)
class Mode:
    """One natural mode: ``frequency`` undamped [Hz]; ``shape`` (x [m], y [m], theta [rad]) scaled so that the
    largest of |x|, |y| and |theta|·rho (rho the radius of gyration) is 1; ``damping_ratio`` from the damped
    eigenvalue, -Re(lambda)/|lambda| [-]."""

    frequency: float
    shape: tuple[float, float, float]
    damping_ratio: float


@dataclass(frozen=True, slots=True)
class Harmonic:
    """One harmonic of the steady cycle: ``order`` k (k times the crank speed), ``frequency`` [Hz]; amplitudes of
    the shaking force |F_k| [N] and moment about the centre |M_k| [N·m], of the force and the moment about the
    centre passed to the foundation [N, N·m]; ``force_transmissibility`` and ``moment_transmissibility`` their
    ratios [-] (None where the shaking term is nil)."""

    order: int
    frequency: float
    shaking_force: float
    shaking_moment: float
    transmitted_force: float
    transmitted_moment: float
    force_transmissibility: float | None
    moment_transmissibility: float | None


@dataclass(frozen=True, slots=True)
class IsolationCheck:
    """The harmonic answer against a time integration of the same equations (``solve_ivp``, periodic state by
    shooting): largest differences in the centre's displacement [m], the rotation [rad] and the force to the
    foundation [N], and those over the harmonic answer's peaks [-]; ``series_residual`` the harmonics kept against
    the analysis' samples, largest difference over the largest shaking force or moment [-]."""

    displacement_diff: float
    rotation_diff: float
    force_diff: float
    relative_diff: float
    series_residual: float
    method: str


@dataclass(frozen=True, slots=True)
class Isolation:
    """The frame's steady motion on its isolators over one cycle, and what the foundation feels.

    ``time`` from the first sample [s] and ``phi`` [rad] (N,); ``displacement`` of the centre [m] (N, 2),
    ``rotation`` [rad] (N,); ``isolator_force`` on the foundation [N] (I, N, 2), ``force`` all together [N]
    (N, 2), ``moment`` their moment about O [N·m] (N,); ``shaking_force`` and ``shaking_moment`` (about O) what a
    rigidly bolted frame would pass on [N, N·m]; ``peak_*`` the largest magnitudes over the cycle;
    ``peak_isolator_displacement`` the largest movement of any isolator point [m]; ``static_deflection`` of
    each isolator under the machine's weight (y down) [m] (I, 2) and ``static_load`` on it [N] (I, 2),
    compression positive;
    ``settle_time`` for a start's transient to fall to 1 % (slowest mode's decay) [s]; ``run_up`` the frame
    while the machine runs up (None: not asked for); ``warnings`` and ``checks`` where the model stops
    (:func:`isolation_validity`).
    """

    frame: Frame
    isolators: tuple[Isolator, ...]
    time: FloatArray
    phi: FloatArray
    displacement: FloatArray
    rotation: FloatArray
    isolator_force: FloatArray
    force: FloatArray
    moment: FloatArray
    shaking_force: FloatArray
    shaking_moment: FloatArray
    modes: tuple[Mode, ...]
    harmonics: tuple[Harmonic, ...]
    peak_displacement: float
    peak_rotation: float
    peak_isolator_displacement: float
    peak_force: float
    peak_moment: float
    peak_shaking_force: float
    peak_isolator_force: FloatArray
    static_deflection: FloatArray
    static_load: FloatArray
    settle_time: float
    check: IsolationCheck
    run_up: RunUpPassage | None = None
    warnings: tuple[DesignWarning, ...] = ()
    checks: tuple[ValidityCheck, ...] = ()


@dataclass(frozen=True, slots=True)
class FrameModel:
    """The frame's matrices: ``mass`` M, ``stiffness`` K, ``damping`` C (3, 3) in (x, y, theta); ``maps`` A_i
    (I, 2, 3); the isolators' stiffness and damping (I, 2)."""

    mass: FloatArray
    stiffness: FloatArray
    damping: FloatArray
    maps: FloatArray
    k: FloatArray
    c: FloatArray


def _finite(value: float, name: str, *, positive: bool = False) -> None:
    if not math.isfinite(value) or value < 0 or (positive and value == 0):
        raise InvalidInput(f"{name} must be finite and {'positive' if positive else 'not negative'}", field=name)


def frame_model(frame: Frame, isolators: tuple[Isolator, ...] | list[Isolator]) -> FrameModel:
    """Mass, stiffness and damping matrices of the frame on its isolators; InvalidInput naming the field for no
    isolator, a negative or non-finite value, or a layout that leaves a rigid-body mode free."""
    _finite(frame.mass, "frame.mass_kg", positive=True)
    _finite(frame.inertia, "frame.inertia_kgm2", positive=True)
    if not isolators:
        raise InvalidInput("the frame needs at least one isolator (and enough of them to hold x, y and rotation)",
                           field="isolators")
    cx0, cy0 = frame.centre
    if not (math.isfinite(cx0) and math.isfinite(cy0)):
        raise InvalidInput("the frame's centre must be finite", field="frame.centre_m")
    k = np.zeros((len(isolators), 2))
    c = np.zeros((len(isolators), 2))
    maps = np.zeros((len(isolators), 2, 3))
    for i, iso in enumerate(isolators):
        for name, value in (("kx_N_m", iso.kx), ("ky_N_m", iso.ky), ("cx_Ns_m", iso.cx), ("cy_Ns_m", iso.cy)):
            _finite(value, f"isolators.{i}.{name}")
        if iso.damping_ratio is not None:
            _finite(iso.damping_ratio, f"isolators.{i}.damping_ratio")
        rx, ry = iso.position[0] - cx0, iso.position[1] - cy0
        if not (math.isfinite(rx) and math.isfinite(ry)):
            raise InvalidInput("an isolator's position must be finite", field=f"isolators.{i}.position_m")
        maps[i] = [[1.0, 0.0, -ry], [0.0, 1.0, rx]]
        k[i] = iso.kx, iso.ky
    total_ky = float(k[:, 1].sum())
    for i, iso in enumerate(isolators):
        if iso.damping_ratio is not None:
            if iso.cx or iso.cy:
                raise InvalidInput("give an isolator's damping as coefficients or as a ratio, not both",
                                   field=f"isolators.{i}.damping_ratio")
            share = frame.mass * (k[i, 1] / total_ky if total_ky > 0 else 1.0 / len(isolators))
            c[i] = 2 * iso.damping_ratio * np.sqrt(k[i] * share)
        else:
            c[i] = iso.cx, iso.cy
    stiffest = float(np.max(k, initial=0.0))
    for name, value in (("frame.mass_kg", frame.mass), ("frame.inertia_kgm2", frame.inertia)):
        # a subnormal mass or inertia: stiffness over it overflows and the frame's modes cannot be computed
        if not (value >= sys.float_info.min and math.isfinite(stiffest / value)):
            raise InvalidInput(f"{name} {value:g} is too small to compute the frame's modes with against isolators "
                               f"of up to {stiffest:g} N/m", field=name)
    mass = np.diag([frame.mass, frame.mass, frame.inertia])
    stiffness = np.einsum("iaj,ia,iak->jk", maps, k, maps)
    damping = np.einsum("iaj,ia,iak->jk", maps, c, maps)
    _refuse_free_modes(mass, stiffness, (cx0, cy0))
    return FrameModel(mass, stiffness, damping, maps, k, c)


def _refuse_free_modes(mass: FloatArray, stiffness: FloatArray, centre: tuple[float, float]) -> None:
    lam, vec = scipy.linalg.eigh(stiffness, mass)
    top = float(np.max(np.abs(lam)))
    if top <= 0 or lam[0] <= FREE_MODE * top:
        v = vec[:, 0] / np.max(np.abs(vec[:, 0]))
        rho = math.sqrt(mass[2, 2] / mass[0, 0])
        if abs(v[2]) * rho > 1e-6 * max(abs(v[0]), abs(v[1])):
            # a small rigid motion (x, y, theta) of the centre turns the frame about C + (-y, x)/theta
            what = (f"it turns about the point ({centre[0] - v[1] / v[2]:.4g}, {centre[1] + v[0] / v[2]:.4g}) m "
                    "of the linkage's coordinates")
        else:
            what = f"it slides along the direction ({v[0]:.3g}, {v[1]:.3g})"
        raise InvalidInput(
            f"the isolators leave a rigid-body motion of the frame free ({what}); add isolators or stiffness "
            "against it, or spread them apart",
            field="isolators")


def modes(model: FrameModel) -> tuple[Mode, ...]:
    """The three natural modes, lowest first, with their damping ratios from the damped eigenproblem."""
    lam, vec = scipy.linalg.eigh(model.stiffness, model.mass)
    rho = math.sqrt(model.mass[2, 2] / model.mass[0, 0])
    damped = scipy.linalg.eigvals(_state_matrix(model))
    out = []
    for j in range(3):
        w = math.sqrt(max(float(lam[j]), 0.0))
        v = vec[:, j].copy()
        scale = max(abs(v[0]), abs(v[1]), abs(v[2]) * rho)
        v /= scale * (1 if v[np.argmax(np.abs(v * [1, 1, rho]))] > 0 else -1)
        # the damped eigenvalue closest to this mode's undamped frequency
        near = damped[np.argmin(np.abs(np.abs(damped) - w))]
        zeta = float(-near.real / abs(near)) if abs(near) > 0 else 1.0
        out.append(Mode(w / (2 * math.pi), (float(v[0]), float(v[1]), float(v[2])), zeta))
    return tuple(out)


def _state_matrix(model: FrameModel) -> FloatArray:
    minv = np.linalg.inv(model.mass)
    return np.block([[np.zeros((3, 3)), np.eye(3)], [-minv @ model.stiffness, -minv @ model.damping]])


@dataclass(frozen=True, slots=True)
class Series:
    """The generalised force on the frame as harmonics: G(t) = Re(sum_k G_k exp(i k w t)), orders (K,) with 0
    the mean, coefficients (K, 3) in (Fx [N], Fy [N], M_C [N·m]); ``residual`` the kept series against the
    samples, over the largest force or moment [-]."""

    orders: FloatArray
    coefficients: FloatArray
    speed: float
    residual: float

    def at(self, t: FloatArray) -> FloatArray:
        """G at times ``t`` [s] -> (len(t), 3)."""
        phase = np.exp(1j * np.outer(np.atleast_1d(t), self.orders * self.speed))
        return np.asarray((phase @ self.coefficients).real, dtype=float)


def generalised_force(frame: Frame, forcing: Forcing) -> FloatArray:
    """(Fx, Fy, M_C) on the frame at every sample: the shaking moment moved from O to the frame's centre."""
    cx, cy = frame.centre
    f = np.asarray(forcing.force, dtype=float)
    m_c = np.asarray(forcing.moment, dtype=float) - (cx * f[:, 1] - cy * f[:, 0])
    return np.column_stack([f, m_c])


def _check_forcing(forcing: Forcing) -> None:
    phi = np.asarray(forcing.phi, dtype=float)
    n = phi.size
    if n < 3:
        raise InvalidInput("the cycle needs at least 3 samples", field="samples")
    if not np.allclose(np.diff(phi), 2 * math.pi / n, rtol=1e-9, atol=1e-12):
        raise InvalidInput("the foundation's harmonics take uniformly spaced crank angles over one revolution",
                           field="crank_angle_deg")
    if not (math.isfinite(forcing.speed) and forcing.speed > 0):
        raise InvalidInput("the crank speed must be positive", field="speed_rpm")
    if forcing.force.shape != (n, 2) or forcing.moment.shape != (n,):
        raise InvalidInput("shaking force (N, 2) and moment (N,) must match the crank angles", field="samples")


def series(frame: Frame, forcing: Forcing, cut: float = HARMONIC_CUT) -> Series:
    """The harmonics of the generalised force whose size is at least ``cut`` of the largest (the mean always),
    below the Nyquist order (whose phase the samples cannot tell)."""
    _check_forcing(forcing)
    g = generalised_force(frame, forcing)
    n = g.shape[0]
    spectrum = np.fft.rfft(g, axis=0) / n
    spectrum[1:] *= 2
    top_order = (n - 1) // 2
    spectrum = spectrum[: top_order + 1]
    size = np.abs(spectrum)
    scale = np.maximum(size.max(axis=0), 1e-300)
    keep = np.any(size >= cut * scale, axis=1)
    keep[0] = True
    orders = np.flatnonzero(keep).astype(float)
    coefficients = spectrum[keep]
    t = np.arange(n) * forcing.period / n
    rebuilt = np.asarray((np.exp(1j * np.outer(t, orders * forcing.speed)) @ coefficients).real)
    peak = np.max(np.abs(g), axis=0)
    residual = float(np.max(np.abs(rebuilt - g).max(axis=0) / np.maximum(peak, 1e-300)))
    return Series(orders, coefficients, forcing.speed, residual)


def harmonic_response(model: FrameModel, s: Series) -> tuple[ComplexArray, ComplexArray]:
    """Q_k of the displacement (K, 3) and of the foundation's generalised force (K, 3) for every kept harmonic:
    (K - (k w)^2 M + i k w C) Q_k = G_k, the mean by K Q_0 = G_0."""
    w = s.orders * s.speed
    z = (model.stiffness[None] - (w**2)[:, None, None] * model.mass[None]
         + 1j * w[:, None, None] * model.damping[None])
    # an undamped frame driven exactly at a natural frequency has no steady cycle
    cond = np.linalg.cond(z)
    if not np.all(np.isfinite(cond)) or np.any(cond > 1e13):
        bad = int(s.orders[int(np.argmax(np.where(np.isfinite(cond), cond, np.inf)))])
        raise InvalidInput(f"harmonic {bad} of the shaking force drives the frame at a natural frequency with "
                           "no damping: it has no steady cycle; give the isolators damping or change their "
                           "stiffness", field="isolators")
    q = np.linalg.solve(z, s.coefficients[..., None])[..., 0]
    passed = q @ model.stiffness.T + 1j * w[:, None] * (q @ model.damping.T)
    return np.asarray(q, dtype=complex), np.asarray(passed, dtype=complex)


def _time_state(s: Series, q: ComplexArray, t: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Displacement and velocity (len(t), 3) from harmonic amplitudes."""
    w = s.orders * s.speed
    phase = np.exp(1j * np.outer(t, w))
    return np.asarray((phase @ q).real), np.asarray((phase @ (1j * w[:, None] * q)).real)


def _isolator_forces(model: FrameModel, disp: FloatArray, vel: FloatArray) -> FloatArray:
    """Force each isolator passes to the foundation, (I, N, 2) [N]."""
    u = np.einsum("iaj,nj->ina", model.maps, disp)
    v = np.einsum("iaj,nj->ina", model.maps, vel)
    return np.asarray(model.k[:, None, :] * u + model.c[:, None, :] * v)


def _periodic_by_integration(model: FrameModel, s: Series, t: FloatArray) -> tuple[FloatArray, FloatArray, str]:
    """The periodic state at times ``t`` (within one period from 0) by integrating in time and shooting.

    The run starts at rest in the quasi-static position x_s = (K^-1 G(0), 0); its state after one period is
    y(T) = Phi x_s + p(T) with Phi = exp(A T), so the periodic motion is y(t) + exp(A t) d with
    d = (I - Phi)^-1 (y(T) - x_s)."""
    a = _state_matrix(model)
    minv = np.linalg.inv(model.mass)
    period = 2 * math.pi / s.speed

    w = s.orders * s.speed
    re, im = minv @ s.coefficients.real.T, minv @ s.coefficients.imag.T

    def rhs(time: float, y: FloatArray) -> FloatArray:
        out = a @ y
        out[3:] += re @ np.cos(w * time) - im @ np.sin(w * time)
        return np.asarray(out)

    lam, vec = np.linalg.eig(a)
    oscillations = float(np.max(np.abs(lam))) * period / (2 * math.pi)
    # many natural oscillations per cycle (stiff isolators): an implicit method steps over their decay
    method = "DOP853" if oscillations < 30 else "Radau"
    kwargs = {"jac": a, "rtol": 1e-7} if method == "Radau" else {"rtol": 1e-9}
    start = np.concatenate([np.linalg.solve(model.stiffness, s.at(np.array([0.0]))[0]), np.zeros(3)])
    sol = solve_ivp(rhs, (0.0, period), start, method=method, t_eval=np.append(t, period), atol=1e-16,
                    **kwargs)
    if not sol.success:
        raise InvalidInput(f"the time integration of the frame failed: {sol.message}", field="isolators")
    d = np.linalg.solve(np.eye(6) - scipy.linalg.expm(a * period), sol.y[:, -1] - start)
    coeff = np.linalg.solve(vec, d)
    homogeneous = (vec @ (np.exp(np.outer(lam, t)) * coeff[:, None])).real
    states = sol.y[:, :-1] + homogeneous
    return states[:3].T, states[3:].T, f"solve_ivp {method}, periodic state by shooting over one period"


def isolate(frame: Frame, isolators: tuple[Isolator, ...] | list[Isolator], forcing: Forcing, *,
            check: bool = True) -> Isolation:
    """The frame's steady motion on its isolators under the linkage's shaking force and moment, what each
    isolator and all together pass to the foundation, natural modes and transmissibility per harmonic.

    Parameters
    ----------
    frame
        The machine as a rigid body: mass [kg], inertia about its centre [kg·m²], centre in the linkage's
        coordinates [m].
    isolators
        Positions [m], stiffness [N/m] and damping [N·s/m or -] of the isolators.
    forcing
        Shaking force [N] and moment about O [N·m] at uniform crank angles over one cycle at the crank speed
        [rad/s].
    check
        Integrate in time as the independent check (off only inside a design search).
    """
    isolators = tuple(isolators)
    model = frame_model(frame, isolators)
    s = series(frame, forcing)
    q, passed = harmonic_response(model, s)
    n = forcing.phi.size
    t = np.arange(n) * forcing.period / n
    disp, vel = _time_state(s, q, t)
    iso_force = _isolator_forces(model, disp, vel)
    force = iso_force.sum(axis=0)
    pos = np.array([i.position for i in isolators], dtype=float)
    moment = np.sum(pos[:, None, 0] * iso_force[..., 1] - pos[:, None, 1] * iso_force[..., 0], axis=0)
    g = generalised_force(frame, forcing)
    harmonics = []
    for k, order in enumerate(s.orders):
        if order == 0:
            continue
        fs, ms = float(np.linalg.norm(s.coefficients[k, :2])), float(abs(s.coefficients[k, 2]))
        ft, mt = float(np.linalg.norm(passed[k, :2])), float(abs(passed[k, 2]))
        tiny_f = fs <= 1e-12 * max(float(np.abs(g[:, :2]).max()), 1e-300)
        tiny_m = ms <= 1e-12 * max(float(np.abs(g[:, 2]).max()), 1e-300)
        harmonics.append(Harmonic(int(order), float(order * forcing.speed / (2 * math.pi)), fs, ms, ft, mt,
                                  None if tiny_f else ft / fs, None if tiny_m else mt / ms))
    moved = np.einsum("iaj,nj->ina", model.maps, disp)
    static = np.linalg.solve(model.stiffness, np.array([0.0, -frame.mass * G, 0.0]))
    static_u = model.maps @ static
    decay = -float(np.max(scipy.linalg.eigvals(_state_matrix(model)).real))
    settle = math.log(100) / decay if decay > 0 else math.inf
    if check:
        disp_t, vel_t, method = _periodic_by_integration(model, s, t)
        force_t = _isolator_forces(model, disp_t, vel_t).sum(axis=0)
        dd = float(np.max(np.linalg.norm(disp_t[:, :2] - disp[:, :2], axis=1)))
        dr = float(np.max(np.abs(disp_t[:, 2] - disp[:, 2])))
        df = float(np.max(np.linalg.norm(force_t - force, axis=1)))
        peaks = (float(np.max(np.linalg.norm(disp[:, :2], axis=1))), float(np.max(np.abs(disp[:, 2]))),
                 float(np.max(np.linalg.norm(force, axis=1))))
        rel = max(d / p for d, p in zip((dd, dr, df), peaks) if p > 0) if any(p > 0 for p in peaks) else 0.0
        chk = IsolationCheck(dd, dr, df, rel, s.residual, method)
    else:
        chk = IsolationCheck(math.nan, math.nan, math.nan, math.nan, s.residual, "not run")
    found = modes(model)
    notes, checks = isolation_validity(found, tuple(harmonics), np.asarray(forcing.phi, dtype=float),
                                       -(model.k * static_u), iso_force)
    return Isolation(
        frame, isolators, t, np.asarray(forcing.phi, dtype=float), disp[:, :2], disp[:, 2], iso_force, force,
        moment, np.asarray(forcing.force, dtype=float), np.asarray(forcing.moment, dtype=float), found,
        tuple(harmonics),
        peak_displacement=float(np.max(np.linalg.norm(disp[:, :2], axis=1))),
        peak_rotation=float(np.max(np.abs(disp[:, 2]))),
        peak_isolator_displacement=float(np.max(np.linalg.norm(moved, axis=2))),
        peak_force=float(np.max(np.linalg.norm(force, axis=1))),
        peak_moment=float(np.max(np.abs(moment))),
        peak_shaking_force=float(np.max(np.linalg.norm(forcing.force, axis=1))),
        peak_isolator_force=np.max(np.linalg.norm(iso_force, axis=2), axis=1),
        static_deflection=-static_u,
        static_load=-(model.k * static_u),
        settle_time=settle,
        check=chk,
        warnings=tuple(notes),
        checks=tuple(checks),
    )


def isolation_validity(found: tuple[Mode, ...], harmonics: tuple[Harmonic, ...], phi: FloatArray,
                       static_load: FloatArray, isolator_force: FloatArray) -> tuple[list[DesignWarning],
                                                                                     list[ValidityCheck]]:
    """Where the isolation model stops: a harmonic with energy passed on undiminished (transmissibility at least
    1), below sqrt(2) times the highest natural frequency, or near a mode with little damping; an isolator in
    tension under the weight or during the cycle (it lifts off: the linear model needs it in compression).
    ``static_load`` (I, 2) compression positive [N]; ``isolator_force`` (I, N, 2) the cycle's force on the
    foundation [N]."""
    notes: list[DesignWarning] = []
    checks: list[ValidityCheck] = []
    top_f = max((h.shaking_force for h in harmonics), default=0.0)
    top_m = max((h.shaking_moment for h in harmonics), default=0.0)
    strong = [h for h in harmonics
              if (top_f > 0 and h.shaking_force >= ENERGY_SHARE * top_f)
              or (top_m > 0 and h.shaking_moment >= ENERGY_SHARE * top_m)]
    if strong:
        ratios = [(max(t for t in (h.force_transmissibility, h.moment_transmissibility) if t is not None), h)
                  for h in strong if h.force_transmissibility is not None or h.moment_transmissibility is not None]
        if ratios:
            worst, h = max(ratios, key=lambda x: x[0])
            checks.append(ValidityCheck("transmissibility", worst, 1.0, worst < 1.0,
                                        "largest transmissibility (force or moment passed on over shaking) over "
                                        "the harmonics with energy"))
            if worst >= 1.0:
                notes.append(DesignWarning(
                    "transmissibility_high", "isolators", worst,
                    f"harmonic {h.order} ({h.frequency:.4g} Hz) is passed to the foundation {worst:.3g} times as "
                    "large as the linkage shakes the frame: the isolators amplify it instead of isolating; softer "
                    "isolators or a heavier frame", "1"))
        highest = max(m.frequency for m in found)
        lowest = min(h.frequency for h in strong)
        ratio = lowest / highest if highest > 0 else math.inf
        checks.append(ValidityCheck("frequency_ratio", ratio, ISOLATION_RATIO, ratio >= ISOLATION_RATIO,
                                    "lowest harmonic with energy over the highest natural frequency, against "
                                    "sqrt(2)"))
        if ratio < ISOLATION_RATIO:
            notes.append(DesignWarning(
                "frequency_ratio_low", "isolators", ratio,
                f"the lowest harmonic with energy ({lowest:.4g} Hz) is only {ratio:.3g} times the highest natural "
                f"frequency ({highest:.4g} Hz), below sqrt(2): below it the isolators pass on more than they "
                "take", "1"))
        near = [(abs(h.frequency / m.frequency - 1), m, h) for m in found for h in strong
                if m.frequency > 0 and abs(h.frequency / m.frequency - 1) <= NEAR_MODE]
        if near:
            least = min(m.damping_ratio for _, m, _ in near)
            checks.append(ValidityCheck("resonance_damping", least, MIN_MODE_DAMPING, least >= MIN_MODE_DAMPING,
                                        "least damping ratio of a mode that a harmonic with energy comes within "
                                        "25 % of"))
            for gap, m, h in near:
                if m.damping_ratio < MIN_MODE_DAMPING:
                    notes.append(DesignWarning(
                        "resonance_damping_low", "isolators", m.damping_ratio,
                        f"harmonic {h.order} ({h.frequency:.4g} Hz) lies {gap:.1%} from the natural frequency "
                        f"{m.frequency:.4g} Hz, whose damping ratio is {m.damping_ratio:.3g} (below "
                        f"{MIN_MODE_DAMPING:g}): the frame's motion there is set by the damping alone, which is "
                        "known only roughly; move the mode or damp it", "1"))
    compression = static_load[:, None, 1] - isolator_force[..., 1]
    least = float(compression.min())
    checks.append(ValidityCheck("isolator_compression", least, 0.0, least > 0.0,
                                "least compression of any isolator over the cycle, its share of the weight "
                                "included [N]", "N"))
    for i in range(compression.shape[0]):
        if static_load[i, 1] <= 0:
            notes.append(DesignWarning(
                "isolator_in_tension", f"isolators.{i}", float(static_load[i, 1]),
                f"isolator {i} is pulled ({-static_load[i, 1]:.4g} N of tension) by the machine's weight alone: the "
                "frame's centre lies outside its isolators, and a mount that is not bolted lifts off; move the "
                "isolators under the centre", "N"))
        elif compression[i].min() <= 0:
            lifted = compression[i] <= 0
            notes.append(DesignWarning(
                "isolator_lift_off", f"isolators.{i}", float(compression[i].min()),
                f"isolator {i} goes into tension ({-compression[i].min():.4g} N) at crank angles "
                + ", ".join(f"{math.degrees(a):.4g}–{math.degrees(b):.4g}°" for a, b in angle_ranges(phi, lifted))
                + ": its dynamic movement exceeds its static deflection and the frame lifts off it; the linear "
                "answer no longer holds there", "N", angle_ranges(phi, lifted)))
    return notes, checks


@dataclass(frozen=True, slots=True)
class RunUpPassage:
    """The frame while the machine runs up: ``time`` [s], ``speed`` crank [rad/s] and ``amplitude`` the centre's
    displacement magnitude [m] at each output time; ``peak_amplitude`` the largest [m] at ``peak_time`` [s] and
    crank ``peak_speed`` [rad/s]; ``steady_amplitude`` the steady cycle's peak at the final speed [m];
    ``ratio`` their quotient [-] (None when the steady cycle stands still);
    ``crossed`` the natural frequencies [Hz] some harmonic passed through on the way up."""

    time: FloatArray
    speed: FloatArray
    amplitude: FloatArray
    peak_amplitude: float
    peak_time: float
    peak_speed: float
    steady_amplitude: float
    ratio: float | None
    crossed: tuple[float, ...]


#: Most output points of a run-up passage.
RUN_UP_POINTS = 4000


@dataclass(frozen=True, slots=True)
class Momentum:
    """What the crank's angular acceleration adds to the pull on the frame: the linkage's momentum over the steady
    cycle of its :class:`Forcing` (same crank angles and speed), ``linear`` (N, 2) [N·s] and ``angular`` about the
    crank pivot O (N,) [N·m·s]; ``spin`` the angular momentum of the drive's rotating parts (rotor, train,
    flywheel) per unit crank speed [kg·m²]. At crank speed w and acceleration alpha the linkage pulls with
    F = -dP/dt = (w/w_0)²·F_0 - alpha·P_0/w_0 and turns the frame with M = (w/w_0)²·M_0 - alpha·(H_0/w_0 + spin)."""

    linear: FloatArray
    angular: FloatArray
    spin: float = 0.0


def momentum_of(an: Analysis, spin: float = 0.0) -> Momentum:
    """The momentum of an analysis' links at its constant crank speed (counterweights included; counter-rotors
    left out), with the drive's ``spin`` [kg·m²]."""
    arrays = link_arrays(an.motion, an.linkage)
    mass = np.asarray(arrays.mass, dtype=float)
    vel, pos = arrays.com_vel, arrays.com_pos
    linear = np.einsum("l,lnk->nk", mass, vel)
    cross = pos[..., 0] * vel[..., 1] - pos[..., 1] * vel[..., 0]
    angular = np.einsum("l,ln->n", mass, cross) + np.einsum("l,ln->n", np.asarray(arrays.inertia), arrays.omega)
    return Momentum(np.asarray(linear, dtype=float), np.asarray(angular, dtype=float), float(spin))


def drive_spin(motor: Motor, constant_inertia: float) -> float:
    """Angular momentum per unit crank speed of the rotating drive [kg·m²]: the rotor i·J_r (turning the crank's
    way through the train) and the rest of ``constant_inertia`` (train and flywheel, i²·J_r taken off) counted
    at the crank's speed."""
    i, j_r = motor.gear_ratio, motor.rotor_inertia
    return i * j_r + max(constant_inertia - i * i * j_r, 0.0)


def run_up_passage(frame: Frame, isolators: tuple[Isolator, ...], forcing: Forcing, time: FloatArray,
                   phi: FloatArray, omega: FloatArray, steady_peak: float,
                   momentum: Momentum | None = None) -> RunUpPassage:
    """Integrate the frame from rest while the crank follows ``phi``(``time``) and ``omega`` [rad, rad/s] from a
    start-up simulation. The linkage's pull at crank angle phi, speed w and acceleration alpha is
    G(t) = (w/w_0)²·G_0(phi) - alpha·G_1(phi), G_0 the steady cycle's at w_0 and G_1 from ``momentum`` (the
    linkage's momentum per unit crank speed and the drive's spin, see :class:`Momentum`; None: the
    angular-acceleration terms left out), each as its harmonics Re sum_k G_k exp(i k (phi - phi_0));
    alpha is the slope of ``omega`` over ``time``; ``steady_peak`` the steady cycle's peak displacement of the
    centre [m]."""
    model = frame_model(frame, isolators)
    s = series(frame, forcing)
    w0 = forcing.speed
    phi0 = float(forcing.phi[0])
    minv = np.linalg.inv(model.mass)
    re, im = s.coefficients.real.T, s.coefficients.imag.T
    a = np.block([[np.zeros((3, 3)), np.eye(3)], [-minv @ model.stiffness, -minv @ model.damping]])
    t_arr, p_arr, w_arr = (np.asarray(v, dtype=float) for v in (time, phi, omega))
    if t_arr.size < 2 or not np.all(np.diff(t_arr) > 0):
        raise InvalidInput("the run-up needs increasing times", field="run_up")
    a_arr = np.gradient(w_arr, t_arr)
    if momentum is not None:
        per_speed = Forcing(forcing.phi, w0, momentum.linear / w0, momentum.angular / w0 + momentum.spin)
        s1 = series(frame, per_speed)
        o1, re1, im1 = s1.orders, s1.coefficients.real.T, s1.coefficients.imag.T
    else:
        o1, re1, im1 = np.zeros(1), np.zeros((3, 1)), np.zeros((3, 1))

    def rhs(t: float, y: FloatArray) -> FloatArray:
        p = np.interp(t, t_arr, p_arr) - phi0
        w = np.interp(t, t_arr, w_arr)
        ang = s.orders * p
        g = (w / w0) ** 2 * (re @ np.cos(ang) - im @ np.sin(ang))
        ang1 = o1 * p
        g = g - np.interp(t, t_arr, a_arr) * (re1 @ np.cos(ang1) - im1 @ np.sin(ang1))
        out = a @ y
        out[3:] += minv @ g
        return np.asarray(out)

    t_out = np.linspace(t_arr[0], t_arr[-1], RUN_UP_POINTS)
    top = float(np.max(s.orders)) * float(np.max(w_arr))
    sol = solve_ivp(rhs, (t_arr[0], t_arr[-1]), np.zeros(6), method="DOP853", t_eval=t_out, rtol=1e-7,
                    atol=1e-12, max_step=2 * math.pi / max(top, 1e-9) / 8)
    if not sol.success:
        raise InvalidInput(f"the run-up integration of the frame failed: {sol.message}", field="run_up")
    amp = np.linalg.norm(sol.y[:2], axis=0)
    i = int(np.argmax(amp))
    steady = steady_peak
    w_out = np.interp(t_out, t_arr, w_arr)
    natural = np.sqrt(np.maximum(np.linalg.eigvals(minv @ model.stiffness).real, 0.0))
    crossed = tuple(sorted(float(wn / (2 * math.pi)) for wn in natural
                           if any(o * w_out.min() <= wn <= o * w_out.max() for o in s.orders if o > 0)))
    return RunUpPassage(t_out, w_out, amp, float(amp[i]), float(t_out[i]), float(w_out[i]), steady,
                        float(amp[i] / steady) if steady > 0 else None, crossed)


def isolate_linkage(linkage: Linkage, speed: float, frame: Frame, isolators: tuple[Isolator, ...], *,
                    samples: int = 360, max_samples: int = 100_000,
                    counter_rotors: tuple[CounterRotor, ...] = (),
                    run_up: tuple[Motor, float] | None = None) -> Isolation:
    """Analyse ``linkage`` at constant crank ``speed`` [rad/s] over one revolution and put its frame on
    ``isolators`` (see :func:`isolate`); with ``run_up`` (the motor through its train, and the constant inertia
    of rotor, train and flywheel reduced to the crank [kg·m²]) also the frame while the machine runs up from
    rest, on the speed history of :func:`synth.machine.startup.simulate_startup`."""
    an = analyse(linkage, speed, samples=samples, max_samples=max_samples, counter_rotors=counter_rotors)
    forcing = forcing_of(an)
    result = isolate(frame, isolators, forcing)
    if run_up is None:
        return result
    motor, constant_inertia = run_up
    red = an.reduced
    start = simulate_startup(MachineCycle(red.phi, red.inertia, red.inertia_slope, red.load_torque),
                             constant_inertia, motor)
    return with_run_up(result, forcing, start, momentum_of(an, drive_spin(motor, constant_inertia)))


def with_run_up(result: Isolation, forcing: Forcing, start: StartUp, momentum: Momentum | None = None
                ) -> Isolation:
    """``result`` with the frame's passage while the machine runs up from rest on the speed history ``start``
    of :func:`synth.machine.startup.simulate_startup`; ``forcing`` the steady cycle's at its constant crank
    speed, ``momentum`` what the crank's angular acceleration adds (None: left out)."""
    frame, isolators, speed = result.frame, result.isolators, forcing.speed
    if start.run is None:
        raise Infeasible("the motor cannot start the machine, so there is no run-up to follow",
                         constraint="run_up.motor", margin=start.check.margin)
    run = start.run
    end = run.time.size if start.steady_time is None else int(np.searchsorted(run.time, start.steady_time)) + 1
    step = max(1, end // 20_000)
    t, p, w = run.time[:end:step], run.phi[:end:step], run.omega[:end:step]
    # then on at the last speed for three periods of the slowest mode (or four revolutions): the free vibration
    # a quick passage leaves behind peaks there
    tail = max(3.0 / result.modes[0].frequency, 4 * 2 * math.pi / float(w[-1]))
    extra = np.linspace(0.0, tail, 200)[1:]
    t = np.concatenate([t, t[-1] + extra])
    p = np.concatenate([p, p[-1] + w[-1] * extra])
    w = np.concatenate([w, np.full(extra.size, w[-1])])
    # the reference is the steady cycle at the speed the run-up ends at (the motor's, not the request's)
    scale = (float(w[-1]) / speed) ** 2
    at_end = Forcing(forcing.phi, float(w[-1]), forcing.force * scale, forcing.moment * scale)
    steady = isolate(frame, isolators, at_end, check=False).peak_displacement
    passage = run_up_passage(frame, isolators, forcing, t, p, w, steady, momentum)
    return replace(result, run_up=passage)


def forcing_of(an: Analysis) -> Forcing:
    """The shaking force and moment of an analysis at its constant crank speed."""
    return forcing_from_analysis(an.motion.phi, an.motion.omega_crank, an.kinetostatics.shaking_force,
                                 an.kinetostatics.shaking_moment)


def forcing_from_analysis(phi: FloatArray, speed: float, shaking_force: FloatArray,
                          shaking_moment: FloatArray) -> Forcing:
    """The forcing of an analysis at constant crank speed [rad/s] (its shaking force [N] and moment about O
    [N·m])."""
    return Forcing(np.asarray(phi, dtype=float), float(speed), np.asarray(shaking_force, dtype=float),
                   np.asarray(shaking_moment, dtype=float))
