"""General linkages of dyads: the named families as linkages, six-bars against an independent loop-closure
solution, the structure refused where it is not a chain of dyads, and bad descriptions named."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import fsolve

import synth
from helpers import spectral_derivative
from synth import JointSpec, LinkSpec, PlanarLinkage

SPEED = 10.0  # [rad/s]
G = synth.Gravity()


def rev(name: str, a: str, b: str, point: str | None = None) -> JointSpec:
    return JointSpec(name, "revolute", (a, b), point)


def press(rod: float = 0.5) -> PlanarLinkage:
    """Six-bar press: crank-rocker O-A-B-Q, rod C-D from the rocker's arm to a ram on a vertical guide (x = 0.45)."""
    return PlanarLinkage(
        (("O", (0.0, 0.0)), ("Q", (0.3, 0.0)), ("G", (0.45, 0.0))),
        (LinkSpec("crank", ("O", "A"), 0.1), LinkSpec("coupler", ("A", "B"), 0.35),
         LinkSpec("rocker", ("Q", "B"), 0.25, (("C", (0.4, 0.0)),)), LinkSpec("rod", ("C", "D"), rod),
         LinkSpec("ram", ("D",))),
        (rev("O", "frame", "crank"), rev("A", "crank", "coupler"), rev("B", "coupler", "rocker"),
         rev("Q", "frame", "rocker"), rev("C", "rocker", "rod"), rev("D", "rod", "ram"),
         JointSpec("guide", "prismatic", ("frame", "ram"), through="G", axis_angle=math.pi / 2)),
        "crank", "ram")


def watt() -> PlanarLinkage:
    """Watt six-bar (two four-bars in series): the ternary rocker Q-B-C drives the output rocker R-D."""
    return PlanarLinkage(
        (("O", (0.0, 0.0)), ("Q", (0.3, 0.0)), ("R", (0.55, 0.35))),
        (LinkSpec("crank", ("O", "A"), 0.1), LinkSpec("coupler", ("A", "B"), 0.35),
         LinkSpec("rocker", ("Q", "B"), 0.25, (("C", (0.15, 0.12)),)), LinkSpec("link", ("C", "D"), 0.35),
         LinkSpec("output", ("R", "D"), 0.3)),
        (rev("O", "frame", "crank"), rev("A", "crank", "coupler"), rev("B", "coupler", "rocker"),
         rev("Q", "frame", "rocker"), rev("C", "rocker", "link"), rev("D", "link", "output"),
         rev("R", "frame", "output")),
        "crank", "output")


def stephenson() -> PlanarLinkage:
    """Stephenson six-bar: a dyad hung from the coupler point C of a four-bar (ternary links not adjacent)."""
    return PlanarLinkage(
        (("O", (0.0, 0.0)), ("Q", (0.3, 0.0)), ("R", (0.1, 0.45))),
        (LinkSpec("crank", ("O", "A"), 0.1), LinkSpec("coupler", ("A", "B"), 0.35, (("C", (0.2, 0.15)),)),
         LinkSpec("rocker", ("Q", "B"), 0.25), LinkSpec("link", ("C", "D"), 0.3), LinkSpec("output", ("R", "D"), 0.25)),
        (rev("O", "frame", "crank"), rev("A", "crank", "coupler"), rev("B", "coupler", "rocker"),
         rev("Q", "frame", "rocker"), rev("C", "coupler", "link"), rev("D", "link", "output"),
         rev("R", "frame", "output")),
        "crank", "output")


def with_masses(mech: PlanarLinkage, load: float = 0.0) -> synth.Linkage:
    """Every link with mass off its axis, gravity on, and a process load on the output over part of the turn."""
    props = {k.name: synth.MassProps(1.0 + i, (0.4 * k.length, 0.01 * (i + 1)), 0.01 * (i + 1))
             for i, k in enumerate(mech.links)}
    loads = (synth.ProcessLoad("window", load, math.radians(200), math.radians(300)),) if load else ()
    return synth.Linkage(mech, props, gravity=G, loads=loads)


# --- the independent computation: generalised coordinates, loop closure by fsolve, derivatives by FFT ---

def _poses(mech: PlanarLinkage, q: np.ndarray, phi: float) -> dict[str, tuple[float, float, float]]:
    """(x, y, angle) of every link's frame: the crank's from phi, the others' from q (three per link)."""
    others = [k.name for k in mech.links if k.name != mech.crank_link]
    poses = {"frame": (0.0, 0.0, 0.0), mech.crank_link: (0.0, 0.0, phi)}
    poses.update({name: (q[3 * i], q[3 * i + 1], q[3 * i + 2]) for i, name in enumerate(others)})
    return poses


def _local(mech: PlanarLinkage) -> dict[str, dict[str, tuple[float, float]]]:
    out = {k.name: k.local() for k in mech.links}
    out["frame"] = dict(mech.frame_points)
    return out


def _at(pose: tuple[float, float, float], xy: tuple[float, float]) -> np.ndarray:
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    return np.array([x + c * xy[0] - s * xy[1], y + s * xy[0] + c * xy[1]])


def _residuals(mech: PlanarLinkage, q: np.ndarray, phi: float) -> np.ndarray:
    """Every pair's closure: a revolute's point the same on both links; a prismatic pair's links turned alike and
    the sliding point on the axis. The crank's own pivot holds by construction."""
    poses, local = _poses(mech, q, phi), _local(mech)
    out: list[float] = []
    for j in mech.joints:
        a, b = j.links
        if j.kind == "revolute":
            if {a, b} == {"frame", mech.crank_link}:
                continue
            p = j.point or j.name
            out += list(_at(poses[a], local[a][p]) - _at(poses[b], local[b][p]))
            continue
        axis = j.axis_link or a
        other = b if axis == a else a
        through = j.through or next(iter(local[axis]))
        point = j.point or next(iter(local[other]))
        psi = poses[axis][2] + j.axis_angle
        out.append(poses[other][2] + j.slider_angle - psi)
        d = _at(poses[other], local[other][point]) - _at(poses[axis], local[axis][through])
        out.append(math.cos(psi) * d[1] - math.sin(psi) * d[0])
    return np.array(out)


def loop_closure(mech: PlanarLinkage, phi: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Poses q at every angle by fsolve, each from the previous angle's (continuation from ``start``)."""
    qs, q = [], start
    for angle in phi:
        # full_output: fsolve's "no further improvement" note at machine precision is judged by the residual below
        q = fsolve(lambda x: _residuals(mech, x, angle), q, xtol=1e-14, full_output=True)[0]
        assert np.abs(_residuals(mech, q, angle)).max() < 1e-13, angle  # closed to rounding [m]
        qs.append(q)
    return np.array(qs)


def _start(mech: PlanarLinkage, mot: synth.Motion) -> np.ndarray:
    """A rough starting pose: the first sample's link frames, each off by a millimetre and a hundredth of a radian."""
    others = [k.name for k in mech.links if k.name != mech.crank_link]
    return np.array([v for name in others for v in (*(mot.point_pos[mech.origins[name]][0] + 1e-3),
                                                      mot.link_angle[name][0] + 1e-2)])


def independent(linkage: synth.Linkage, samples: int) -> tuple[np.ndarray, dict[str, np.ndarray], np.ndarray]:
    """Crank angles, point positions [m] and the driving torque [N·m] by loop closure and virtual power."""
    mech = linkage.mechanism
    assert isinstance(mech, PlanarLinkage)
    phi = synth.cycle_angles(samples)
    first = synth.motion(mech, phi[:1], SPEED)
    q = loop_closure(mech, phi, _start(mech, first))
    local = _local(mech)
    points = {name: np.array([_at(_poses(mech, qi, a)[link], xy) for qi, a in zip(q, phi)])
              for link in [k.name for k in mech.links] for name, xy in local[link].items()}
    angles = {name: np.unwrap(np.array([_poses(mech, qi, a)[name][2] for qi, a in zip(q, phi)]))
              for name in [k.name for k in mech.links]}
    # Virtual power: sum over links of (m·(g - a_S))·v_S - J_S·alpha·omega, plus the load's power, plus T·w = 0.
    power = np.zeros(samples)
    for k in mech.links:
        props = linkage.mass_props(k.name)
        th = angles[k.name]
        origin = points[k.joints[0]]
        s = origin + np.stack([np.cos(th) * props.com[0] - np.sin(th) * props.com[1],
                               np.sin(th) * props.com[0] + np.cos(th) * props.com[1]], axis=-1)
        v, a = SPEED * spectral_derivative(s), SPEED**2 * spectral_derivative(s, 2)
        turns = round((2 * th[-1] - th[-2] - th[0]) / (2 * math.pi))  # whole turns per cycle: 1 crank, 0 rocker
        w = SPEED * (spectral_derivative(th - turns * phi) + turns)
        alpha = SPEED**2 * spectral_derivative(th - turns * phi, 2)
        g = linkage.gravity.vector if linkage.gravity else np.zeros(2)
        power += np.einsum("ij,ij->i", props.mass * (g - a), v) - props.inertia * alpha * w
    for load in linkage.loads:
        out = mech.topology.output
        axis = np.array([math.cos(mech.topology.output_axis_angle), math.sin(mech.topology.output_axis_angle)])
        speed = SPEED * spectral_derivative(points[mech.origins[out]]) @ axis
        magnitude = load.magnitude_at(phi, points[mech.origins[out]] @ axis)
        power += -np.sign(speed) * magnitude * speed
    return phi, points, -power / SPEED


SIX_BARS = {"press": press, "watt": watt, "stephenson": stephenson}


@pytest.mark.parametrize("name", list(SIX_BARS))
def test_six_bars_agree_with_loop_closure_and_virtual_power(name: str) -> None:
    # Independent: poses by fsolve on the generalised-coordinate closure equations, velocities and accelerations
    # by spectral differentiation of those positions over the cycle, the driving torque by virtual power; the
    # engine's come from its closed-form dyads and the Newton-Euler reaction solve.
    linkage = with_masses(SIX_BARS[name](), load=400.0 if name == "press" else 0.0)
    phi, points, torque = independent(linkage, 256)
    an = synth.analyse(linkage, SPEED, samples=256)
    m = an.motion
    for p, pos in points.items():
        assert np.abs(m.point_pos[p] - pos).max() < 1e-9, p  # [m], links of 0.1 to 0.5 m
        vel = SPEED * spectral_derivative(pos)
        assert np.abs(m.point_vel[p] - vel).max() < 1e-9 * max(1.0, np.abs(vel).max()), p
        acc = SPEED**2 * spectral_derivative(pos, 2)
        assert np.abs(m.point_acc[p] - acc).max() < 1e-9 * max(1.0, np.abs(acc).max()), p
    k = an.kinetostatics
    scale = np.abs(torque).max()
    assert np.abs(k.driving_torque - torque).max() < 1e-9 * scale
    assert an.torque_check < 1e-9 * scale  # the engine's own virtual-power figure agrees with its reaction solve


FAMILIES = {
    "fourbar": synth.FourBar(0.3, 0.1, 0.35, 0.25, 1),
    "fourbar_lower": synth.FourBar(0.3, 0.1, 0.35, 0.25, -1),
    "slider_crank": synth.SliderCrank(0.05, 0.2, 0.02, 1),
    "slider_crank_left": synth.SliderCrank(0.05, 0.2, -0.01, -1),
    "shaper": synth.SlottedLever(0.1, 0.3, 0.6, 0.7),
}


@pytest.mark.parametrize("name", list(FAMILIES))
def test_named_families_are_linkages_of_dyads(name: str) -> None:
    # Identity: the family's own closed form and the same mechanism as links, joints and dyads give the same
    # analysis (positions, speeds, reactions, torque, frame loads) to 1e-12 of each quantity's scale.
    mech = FAMILIES[name]
    props = {link: synth.MassProps(1.0 + i, (0.01 * i, 0.002), 0.01) for i, link in enumerate(mech.topology.links)}
    loads = (synth.ProcessLoad("window", 300.0, 0.5, 2.5),)
    a = synth.analyse(synth.Linkage(mech, props, gravity=G, loads=loads), SPEED, crank_acceleration=2.0)
    b = synth.analyse(synth.Linkage(mech.as_linkage(), props, gravity=G, loads=loads), SPEED, crank_acceleration=2.0)

    def same(x: np.ndarray, y: np.ndarray) -> None:
        assert np.abs(x - y).max() <= 1e-12 * max(1.0, np.abs(x).max())

    for p in a.motion.point_pos:
        same(a.motion.point_pos[p], b.motion.point_pos[p])
        same(a.motion.point_vel[p], b.motion.point_vel[p])
        same(a.motion.point_acc[p], b.motion.point_acc[p])
    for link in mech.topology.links:
        same(np.angle(np.exp(1j * (a.motion.link_angle[link] - b.motion.link_angle[link]))), 0.0 * a.motion.phi)
        same(a.motion.link_omega[link], b.motion.link_omega[link])
        same(a.motion.link_alpha[link], b.motion.link_alpha[link])
    for j in a.kinetostatics.reactions:
        same(a.kinetostatics.reactions[j], b.kinetostatics.reactions[j])
    same(a.kinetostatics.driving_torque, b.kinetostatics.driving_torque)
    same(a.kinetostatics.shaking_force, b.kinetostatics.shaking_force)
    same(a.kinetostatics.shaking_moment, b.kinetostatics.shaking_moment)
    same(a.reduced.inertia, b.reduced.inertia)


def test_dyad_kinds_of_the_families_and_a_six_bar() -> None:
    # The structure splits each into the crank and the dyads the textbooks name (seed 001:767-1190).
    assert [d.kind for d in FAMILIES["fourbar"].as_linkage().dyads] == ["RRR"]
    assert [d.kind for d in FAMILIES["slider_crank"].as_linkage().dyads] == ["RRP"]
    assert [d.kind for d in FAMILIES["shaper"].as_linkage().dyads] == ["RPR", "RPP"]
    assert [(d.kind, d.links) for d in press().dyads] == [("RRR", ("coupler", "rocker")), ("RRP", ("rod", "ram"))]


def _scotch_yoke_and_cross_slides() -> PlanarLinkage:
    """Crank, block in a yoke that slides on a horizontal guide (RPP), and a PRP dyad: a block sliding on a
    vertical frame guide, pinned at E to a block riding in a 30-degree slot of the yoke."""
    return PlanarLinkage(
        (("O", (0.0, 0.0)), ("G", (0.0, 0.2)), ("V", (0.3, 0.0))),
        (LinkSpec("crank", ("O", "A"), 0.1), LinkSpec("block", ("A",)),
         LinkSpec("yoke", ("Y", "Y2"), 0.2, (("S", (0.1, -0.2)),)), LinkSpec("rider", ("E",)), LinkSpec("lift", ("E",))),
        (rev("O", "frame", "crank"), rev("A", "crank", "block"),
         JointSpec("slot", "prismatic", ("yoke", "block"), point="A", axis_angle=math.pi / 2, slider_angle=math.pi / 2),
         JointSpec("way", "prismatic", ("frame", "yoke"), point="Y", through="G"),
         JointSpec("slot2", "prismatic", ("yoke", "rider"), point="E", through="S", axis_angle=math.pi / 6,
                   slider_angle=0.0),
         rev("E", "rider", "lift"),
         JointSpec("post", "prismatic", ("frame", "lift"), point="E", through="V", axis_angle=math.pi / 2)),
        "crank", "lift")


def test_rpp_and_prp_dyads_agree_with_loop_closure() -> None:
    # The Scotch yoke moves as x = a·cos(phi) (a closed form by hand); the PRP lift against fsolve as above.
    mech = _scotch_yoke_and_cross_slides()
    assert [d.kind for d in mech.dyads] == ["RPP", "PRP"]
    phi = synth.cycle_angles(128)
    mot = synth.motion(mech, phi, SPEED)
    yoke_x = mot.point_pos["Y"][:, 0]
    assert np.abs(yoke_x - (0.1 * np.cos(phi) + (yoke_x[0] - 0.1))).max() < 1e-12
    q = loop_closure(mech, phi, _start(mech, synth.motion(mech, phi[:1], SPEED)))
    local = _local(mech)
    for name in ("E", "S", "Y2"):
        link = next(k.name for k in mech.links if name in k.local())
        pos = np.array([_at(_poses(mech, qi, a)[link], local[link][name]) for qi, a in zip(q, phi)])
        assert np.abs(mot.point_pos[name] - pos).max() < 1e-9
        assert np.abs(mot.point_acc[name] - SPEED**2 * spectral_derivative(pos, 2)).max() < 1e-9 * SPEED**2


def test_class_three_group_is_named_and_placed_numerically() -> None:
    # A ternary link T held by three binary links to the crank and two frame points: one class-III group.
    mech_args = (
        (("O", (0.0, 0.0)), ("Q1", (0.4, 0.0)), ("Q2", (0.2, 0.5))),
        (LinkSpec("crank", ("O", "A"), 0.1), LinkSpec("l1", ("A", "B"), 0.3), LinkSpec("t", ("B", "C"), 0.2,
                                                                                    (("E", (0.1, 0.15)),)),
         LinkSpec("l2", ("Q1", "C"), 0.3), LinkSpec("l3", ("Q2", "E"), 0.3)),
        (rev("O", "frame", "crank"), rev("A", "crank", "l1"), rev("B", "l1", "t"), rev("C", "t", "l2"),
         rev("Q1", "frame", "l2"), rev("E", "t", "l3"), rev("Q2", "frame", "l3")),
        "crank", "l2",
    )
    mech = PlanarLinkage(*mech_args)  # type: ignore[arg-type]
    (group,) = mech.numeric_groups
    assert set(group.links) == {"l1", "t", "l2", "l3"} and group.group_class == 3 and not mech.dyads


def test_bad_descriptions_name_the_link_joint_or_angles() -> None:
    base = press()
    # a link no joint joins
    with pytest.raises(synth.InvalidInput, match="'loose' is not connected") as err:
        PlanarLinkage(base.frame_points, (*base.links, LinkSpec("loose", ("X", "Y"), 0.1)), base.joints, "crank", "ram")
    assert err.value.field == "mechanism.links.loose"
    # a joint on a link that does not exist
    with pytest.raises(synth.InvalidInput, match="'ghost'") as err:
        PlanarLinkage(base.frame_points, base.links, (*base.joints[:-1], rev("D2", "rod", "ghost", "D")), "crank",
                      "ram")
    assert err.value.field == "mechanism.joints.D2.links"
    # two degrees of freedom: the ram's guide left out and the ram welded nowhere
    with pytest.raises(synth.InvalidInput, match=r"W = 3n - 2p = 3·5 - 2·6 = 3"):
        PlanarLinkage(base.frame_points, base.links, base.joints[:-1], "crank", "ram")
    # a rod too short to reach the guide over part of the turn: the dyad and the crank-angle ranges are named
    with pytest.raises(synth.NotAssemblable, match=r"RRP dyad of links \['rod', 'ram'\]") as na:
        synth.motion(press(rod=0.3), synth.cycle_angles(360), SPEED)
    assert na.value.ranges_deg and all(0.0 <= lo <= hi < 360.0 for lo, hi in na.value.ranges_deg)


def test_six_bar_press_balancing_on_the_linear_map() -> None:
    # Optimal counterweights on the crank and rocker lower the press's shaking force (re-analysed with the plain
    # model); static balance is refused because the ram slides.
    linkage = with_masses(press())
    result = synth.balance_optimal(linkage, SPEED, samples=90)
    assert {c.link for c in result.counterweights} <= {"crank", "rocker"}
    assert result.after.rms_shaking_force < result.before.rms_shaking_force
    with pytest.raises(synth.InvalidInput, match="prismatic pairs"):
        synth.balance_static(linkage, SPEED, samples=90)


def test_watt_six_bar_static_balance_zeroes_the_shaking_force() -> None:
    # An all-turning six-bar can be force-balanced by counterweights (Berkof-Lowen: every link turns about a
    # pivot or is held by two); the re-analysis with the counterweights leaves no shaking force.
    linkage = with_masses(watt())
    spec = synth.CounterweightSpec(("crank", "coupler", "rocker", "link", "output"),
                                   max_radius={k: 1.0 for k in ("crank", "coupler", "rocker", "link", "output")})
    result = synth.balance_static(linkage, SPEED, spec, samples=90)
    assert result.residual_force < 1e-6 * result.before.max_shaking_force



def test_a_bar_with_both_pins_at_one_point_is_named() -> None:
    # The coupler pinned to the rocker at a point P drawn on top of its own pin A: no direction for the bar.
    base = press()
    links = tuple(LinkSpec("coupler", ("A", "B"), 0.35, (("P", (0.0, 0.0)),)) if k.name == "coupler" else
                  LinkSpec("rocker", ("Q", "P"), 0.25, (("C", (0.4, 0.0)),)) if k.name == "rocker" else k
                  for k in base.links)
    joints = tuple(rev("B", "coupler", "rocker", "P") if j.name == "B" else j for j in base.joints)
    mech = PlanarLinkage(base.frame_points, links, joints, "crank", "ram")
    with pytest.raises(synth.InvalidInput, match="'coupler' has its joints 'A' and 'P' at the same point") as err:
        synth.motion(mech, synth.cycle_angles(8), SPEED)
    assert err.value.field == "mechanism.links.coupler.points_m"
