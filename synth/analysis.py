"""One call from a linkage to its full kinematic and kinetostatic picture over a cycle."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from .counter_rotors import CounterRotor, rotor_inertia, rotor_loads
from .dynamics import ReducedModel, reduced_model
from .errors import InvalidInput, TooLarge
from .friction import FrictionAnalysis, PairFriction, friction_kinetostatics
from .kinematics import FourBar, MAX_SAMPLES, Motion, PointState, cycle_angles, motion, transmission_angle
from .kinematics.motion import magnitude
from .kinetostatics import (Kinetostatics, LinkArrays, external_loads, link_arrays, solve_direct,
                            virtual_power_torque)
from .model import FloatArray, Linkage


@dataclass(frozen=True, slots=True)
class Summary:
    """RMS (over the samples) and peak absolute values [N, N·m] of the frame loads and the driving torque."""

    rms_shaking_force: float
    max_shaking_force: float
    rms_shaking_moment: float
    max_shaking_moment: float
    rms_driving_torque: float
    max_driving_torque: float
    max_bearing_force: float


def _rms(values: FloatArray) -> float:
    return float(np.sqrt(np.mean(values**2)))


@dataclass(frozen=True, slots=True)
class Analysis:
    """Kinematics, kinetostatics, reduced model and check figures of one linkage over the requested angles.

    ``motion`` carries the centres of mass as points ``S_<link>``. ``virtual_power_torque`` is the driving
    torque recomputed from the power balance, independently of the reaction solve. ``counter_rotors`` are in the
    driving torque, the shaking moment and the reduced model (their gear forces are not in the joint reactions).
    ``friction`` the kinetostatics with friction in the pairs (None without); its losses are in the reduced
    model's ``friction_torque``.
    """

    linkage: Linkage
    motion: Motion
    kinetostatics: Kinetostatics
    virtual_power_torque: FloatArray
    reduced: ReducedModel
    counter_rotors: tuple[CounterRotor, ...] = ()
    friction: FrictionAnalysis | None = None
    #: The mechanism's own motion (without centres of mass or trace points): what a re-analysis of the same
    #: mechanism with other masses passes as ``base_motion``.
    mechanism_motion: Motion | None = field(default=None, repr=False, compare=False)
    # the summary once computed: balancing, the chain and their checks each ask for it (replace() starts anew)
    _summary: list[Summary] = field(default_factory=list, init=False, repr=False, compare=False)

    @property
    def torque_check(self) -> float:
        """Largest |kinetostatic - virtual-power| driving torque difference [N·m]."""
        return float(np.max(np.abs(self.kinetostatics.driving_torque - self.virtual_power_torque)))

    @property
    def transmission_angle(self) -> FloatArray | None:
        """Four-bar transmission angle [rad] at every sample; None for other families."""
        if not isinstance(self.linkage.mechanism, FourBar):
            return None
        return transmission_angle(self.motion.link_angle["coupler"], self.motion.link_angle["rocker"])

    def bearing_forces(self) -> dict[str, FloatArray]:
        """Magnitude of every revolute joint's reaction [N], (N,) each."""
        topo = self.linkage.mechanism.topology
        return {
            j.name: magnitude(self.kinetostatics.reactions[j.name])
            for j in topo.joints
            if j.kind == "revolute"
        }

    def summary(self) -> Summary:
        """RMS and peak shaking force, shaking moment, driving torque, and peak bearing force."""
        if not self._summary:
            self._summary.append(self._summarise())
        return self._summary[0]

    def _summarise(self) -> Summary:
        k = self.kinetostatics
        force = magnitude(k.shaking_force)
        bearings = self.bearing_forces()
        return Summary(
            rms_shaking_force=_rms(force),
            max_shaking_force=float(force.max()),
            rms_shaking_moment=_rms(k.shaking_moment),
            max_shaking_moment=float(np.abs(k.shaking_moment).max()),
            rms_driving_torque=_rms(k.driving_torque),
            max_driving_torque=float(np.abs(k.driving_torque).max()),
            max_bearing_force=float(max(b.max() for b in bearings.values())),
        )


def analyse(
    linkage: Linkage,
    speed: float,
    *,
    samples: int = 360,
    phi: FloatArray | None = None,
    crank_acceleration: float = 0.0,
    max_samples: int = MAX_SAMPLES,
    points: Mapping[str, tuple[str, tuple[float, float]]] | None = None,
    counter_rotors: Sequence[CounterRotor] = (),
    friction: Sequence[PairFriction] = (),
    base_motion: Motion | None = None,
) -> Analysis:
    """Analyse ``linkage`` at crank speed ``speed`` [rad/s] over a uniform grid of ``samples`` or at ``phi`` [rad].

    ``points`` adds named points fixed in links (name -> (link, position in the link frame [m])), such as
    coupler points, to the motion. ``counter_rotors`` (a full-balance answer's) add their moment on the frame,
    their share of the driving torque and their reduced inertia. ``friction`` per pair adds the kinetostatics with
    friction and its losses in the reduced model. ``base_motion`` is :func:`synth.kinematics.motion` of this
    mechanism at these angles, speed and acceleration when the caller has it already (the same mechanism analysed
    again with other masses: balancing's before and after). Raises InvalidInput, TooLarge (more samples than
    ``max_samples``) or NotAssemblable (with the ranges).
    """
    if phi is None:
        angles = cycle_angles(samples, 2 * math.pi, max_samples)
    else:
        angles = np.asarray(phi, dtype=float).reshape(-1)
        if angles.size > max_samples:
            raise TooLarge("crank angles", max_samples, angles.size, field="crank_angle_deg")
    if base_motion is None:
        base = motion(linkage.mechanism, angles, speed, crank_acceleration)
    elif (base_motion.samples != angles.size or base_motion.omega_crank != speed
          or base_motion.alpha_crank != crank_acceleration or not np.array_equal(base_motion.phi, angles)):
        raise ValueError("base_motion is not this mechanism's motion at these angles, speed and acceleration")
    else:
        base = base_motion
    links = linkage.mechanism.topology.links
    extra = dict(points or {})
    for name, (link, _) in extra.items():
        if link not in links:
            raise InvalidInput(f"point {name!r} is on unknown link {link!r}; links are {list(links)}", field="trace_points")
        if name in base.point_pos:
            raise InvalidInput(f"point name {name!r} is already a joint of the mechanism", field="trace_points")
    for i, rotor in enumerate(counter_rotors):
        rotor.validate(links, f"counter_rotors[{i}]")
    arrays = link_arrays(base, linkage)
    coms = {f"S_{link}": PointState(arrays.com_pos[i], arrays.com_vel[i], arrays.com_acc[i])
            for i, link in enumerate(links)}
    mot = base.with_points(extra, coms, states_checked=True)   # the stacked arrays are (L, N, 2) by construction
    loads = external_loads(mot, linkage)
    kin = solve_direct(mot, linkage, arrays, loads)
    vp = virtual_power_torque(mot, linkage, arrays, loads)
    red = reduced_model(mot, linkage, arrays, loads)
    if counter_rotors:
        moment, torque = rotor_loads(mot, counter_rotors)
        kin = replace(kin, driving_torque=kin.driving_torque + torque, shaking_moment=kin.shaking_moment + moment)
        # the virtual-power check sees the rotors through their kinetic energy, d/dt(k²J w_i²/2) / w
        j_rot, slope_rot = rotor_inertia(mot, counter_rotors)
        w = mot.omega_crank
        vp = vp + (j_rot * mot.alpha_crank + 0.5 * slope_rot * w**2)
        red = replace(red, inertia=red.inertia + j_rot, inertia_slope=red.inertia_slope + slope_rot,
                      kinetic_energy=red.kinetic_energy + 0.5 * j_rot * w**2)
    fric = None
    if friction:
        fric = friction_kinetostatics(mot, linkage, kin, friction)
        red = replace(red, friction_torque=fric.loss_torque)
    result = Analysis(
        linkage=linkage,
        motion=mot,
        kinetostatics=kin,
        virtual_power_torque=vp,
        reduced=red,
        counter_rotors=tuple(counter_rotors),
        friction=fric,
        mechanism_motion=base,
    )
    k, r = result.kinetostatics, result.reduced
    checked = (k.unknowns, k.shaking_force, k.shaking_moment, result.virtual_power_torque, r.inertia, r.load_torque)
    # A sum is finite only when every term is (a huge but finite set of terms that overflows its sum is as far
    # outside any physical range); one sum of the arrays' sums, each by the ufunc itself (ndarray.sum is three
    # Python calls).
    if not math.isfinite(sum(float(np.add.reduce(a, axis=None)) for a in checked)):
        raise InvalidInput("the analysis overflows floating point: a length, mass, inertia, load or speed is far "
                           "outside any physical range")
    return result
