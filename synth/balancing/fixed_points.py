"""Static balance of a four-bar by moving centres of mass to fixed points (seed 003:590-671, digest 8.3-8.4).

With counterweights on all three links (8.3): the crank's centre of mass goes to its pivot O, the coupler's to
its joint B with the rocker, and the rocker, carrying the coupler's whole mass (with its counterweight) at B, has
its centre of mass moved to its pivot Q. The seed's (6.10) leaves the coupler's counterweight out of the mass at
B; the corrected condition is (m2 + m_P2)·l_QB + m3·l_QS3 = m_P3·r3. With counterweights on crank and rocker
only (8.4), the coupler is replaced by point masses at A and B (m_A = m2·l_BS2/l2, m_B = m2·l_AS2/l2) carried
by the crank and the rocker, each of which is then balanced about its pivot.
"""

from __future__ import annotations

import math

from ..errors import InvalidInput
from ..kinematics import FourBar
from ..model import Counterweight, Linkage
from .program import CounterweightSpec


def _on_radius(link: str, need: complex, radius: float) -> Counterweight | None:
    """A point counterweight of first moment ``need`` [kg·m] at ``radius`` [m] from the link frame's origin."""
    if abs(need) <= 1e-15:
        return None
    mass = abs(need) / radius
    return Counterweight(link, mass, (need.real / mass, need.imag / mass))


def _beyond_b(shift: complex, l2: float, radius: float) -> Counterweight | None:
    """The coupler counterweight m at z (from A) with m·(z - l2) = ``shift`` and |z| = ``radius``.

    With t = 1/m: |l2 + t·shift|² = radius², the positive root of a quadratic in t.
    """
    if abs(shift) <= 1e-15:
        return None
    a, b, c = abs(shift) ** 2, 2 * l2 * shift.real, l2**2 - radius**2
    disc = b * b - 4 * a * c
    t = (-b + math.sqrt(disc)) / (2 * a) if disc >= 0 else -1.0
    if not t > 0:
        raise InvalidInput(f"the coupler's counterweight must sit beyond B: radius_m.coupler must exceed the "
                           f"nearest point it can take, here more than {l2:.6g} m", field="radius_m.coupler")
    z = l2 + t * shift
    return Counterweight("coupler", 1.0 / t, (z.real, z.imag))


def fixed_point_counterweights(linkage: Linkage, spec: CounterweightSpec | None = None) -> list[Counterweight]:
    """Counterweights that move each link's centre of mass to a fixed point, closed form; shaking force zero.

    Parameters
    ----------
    linkage : a four-bar with its mass properties.
    spec : links ``crank`` and ``rocker``, optionally ``coupler`` (8.3; else 8.4), and each counterweight's
        radius from its link frame's origin [m] (``radius``, or else ``max_radius``): by default the crank's and
        the rocker's lengths and twice the coupler's (its counterweight sits beyond B). Angles follow from the
        method and cannot be given.
    """
    fb = linkage.mechanism
    if not isinstance(fb, FourBar):
        raise InvalidInput("fixed-point balancing is for four-bars", field="mechanism.type")
    spec = (spec or CounterweightSpec()).resolve(linkage)
    if not {"crank", "rocker"} <= set(spec.links):
        raise InvalidInput("fixed-point balancing puts counterweights on crank and rocker (and the coupler)",
                           field="counterweight_links")
    if spec.angle:
        raise InvalidInput("fixed-point balancing sets each counterweight's angle itself", field="angle_deg")
    default = {"crank": fb.crank, "coupler": 2.0 * fb.coupler, "rocker": fb.rocker}
    radius = {link: float((spec.radius or {}).get(link, (spec.max_radius or {}).get(link, default[link])))
              for link in spec.links}
    h = {link: complex(*linkage.params_of(link)[1:3]) for link in ("crank", "coupler", "rocker")}
    m2 = float(linkage.params_of("coupler")[0])
    out: list[Counterweight | None] = []
    if "coupler" in spec.links:
        # 8.3: crank about O; coupler to B; rocker with the coupler's whole mass at B about Q (6.10 corrected).
        coupler_cw = _beyond_b(m2 * fb.coupler - h["coupler"], fb.coupler, radius["coupler"])
        at_b = m2 + (coupler_cw.mass if coupler_cw else 0.0)
        out += [_on_radius("crank", -h["crank"], radius["crank"]), coupler_cw,
                _on_radius("rocker", -(h["rocker"] + at_b * fb.rocker), radius["rocker"])]
    else:
        # 8.4: the coupler's static replacement, m_A = m2 - h2/l2 at A and m_B = h2/l2 at B (first moments
        # taken as complex numbers, so a centre of mass off AB is split too).
        m_b = h["coupler"] / fb.coupler
        m_a = m2 - m_b
        out += [_on_radius("crank", -(h["crank"] + m_a * fb.crank), radius["crank"]),
                _on_radius("rocker", -(h["rocker"] + m_b * fb.rocker), radius["rocker"])]
    return [c for c in out if c is not None]
