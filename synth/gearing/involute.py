"""Involute geometry of an external spur or helical pair (ISO 21771): pressure angles, diameters, contact ratios.

The working pressure angle follows from the profile shifts through inv(alpha_wt) = inv(alpha_t) +
2 tan(alpha_n) (x1 + x2)/(z1 + z2); a given centre distance must agree with it to within 0.05 modules (the
rounding of a published shift), so a pair never jams and never carries a shift it does not have.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import InvalidInput

CENTRE_DISTANCE_TOLERANCE = 0.05  # [modules]


def inv(alpha: float) -> float:
    """Involute function tan(alpha) - alpha [rad]."""
    return math.tan(alpha) - alpha


def inv_inverse(value: float) -> float:
    """The angle whose involute is ``value`` [rad], by Newton's method from a cube-root start."""
    alpha = (3.0 * value) ** (1.0 / 3.0) if value > 0 else 0.0
    for _ in range(50):
        step = (inv(alpha) - value) / math.tan(alpha) ** 2 if alpha > 0 else 0.0
        alpha -= step
        if abs(step) < 1e-15:
            break
    return alpha


@dataclass(frozen=True, slots=True)
class BasicRack:
    """Basic rack of the cutting tool in modules: addendum h_aP* (tool dedendum), dedendum h_fP*, root radius
    rho_fP* of the generated tooth [-], and the normal pressure angle [rad]."""

    addendum: float = 1.0
    dedendum: float = 1.25
    root_radius: float = 0.38
    pressure_angle: float = math.radians(20.0)


@dataclass(frozen=True, slots=True)
class PairGeometry:
    """Geometry of an external pair; lengths [m], angles [rad]; index 0 pinion, 1 gear.

    ``alpha_t`` transverse and ``alpha_wt`` working pressure angles; ``beta_b`` base helix angle; ``d`` reference,
    ``db`` base, ``da`` tip, ``df`` root and ``dw`` working pitch diameters; ``a`` centre distance and
    ``a_shift`` the one the profile shifts give; ``eps_alpha`` transverse and ``eps_beta`` overlap contact
    ratios; ``zn`` virtual tooth numbers; ``rho_red`` reduced radius of curvature at the pitch point.
    """

    z: tuple[int, int]
    normal_module: float
    face_width: float
    helix_angle: float
    x: tuple[float, float]
    rack: BasicRack
    alpha_t: float
    alpha_wt: float
    beta_b: float
    a: float
    a_shift: float
    d: tuple[float, float]
    db: tuple[float, float]
    da: tuple[float, float]
    df: tuple[float, float]
    dw: tuple[float, float]
    eps_alpha: float
    eps_beta: float
    zn: tuple[float, float]
    rho_red: float

    @property
    def ratio(self) -> float:
        """Gear ratio u = z2/z1 [-]."""
        return self.z[1] / self.z[0]

    @property
    def eps_gamma(self) -> float:
        """Total contact ratio [-]."""
        return self.eps_alpha + self.eps_beta

    @property
    def transverse_module(self) -> float:
        """m_t = m_n / cos(beta) [m]."""
        return self.normal_module / math.cos(self.helix_angle)


def min_profile_shift(z: int, helix_angle: float, rack: BasicRack) -> float:
    """Least profile shift cutting ``z`` teeth without undercut, h_aP* - z sin²(alpha_t)/(2 cos beta) [-]."""
    alpha_t = math.atan(math.tan(rack.pressure_angle) / math.cos(helix_angle))
    return rack.addendum - z * math.sin(alpha_t) ** 2 / (2 * math.cos(helix_angle))


def pair_geometry(z1: int, z2: int, normal_module: float, face_width: float, helix_angle: float = 0.0,
                  x1: float = 0.0, x2: float = 0.0, centre_distance: float | None = None,
                  rack: BasicRack | None = None, max_face_width_ratio: float = 1.5) -> PairGeometry:
    """Geometry of an external pair from its teeth, normal module [m], face width [m], helix angle [rad] and
    profile shifts [-]; the centre distance [m] defaults to the one the shifts give.

    Raises InvalidInput naming the field: teeth below the undercut limit without enough profile shift, a face
    width beyond ``max_face_width_ratio`` pinion diameters, a centre distance the shifts do not give, a
    transverse contact ratio below 1.
    """
    rack = rack or BasicRack()
    for name, v in (("pinion_teeth", z1), ("gear_teeth", z2)):
        if v < 5:
            raise InvalidInput(f"{name} must be at least 5, got {v}", field=name)
    for name, f in (("normal_module_mm", normal_module), ("face_width_mm", face_width)):
        if not (math.isfinite(f) and f > 0):
            raise InvalidInput(f"{name} must be positive", field=name)
    if not 0 <= helix_angle < math.radians(45):
        raise InvalidInput("the helix angle must lie in [0, 45) deg", field="helix_angle_deg")
    for name, z, shift in (("pinion_profile_shift", z1, x1), ("gear_profile_shift", z2, x2)):
        x_min = min_profile_shift(z, helix_angle, rack)
        if shift < x_min - 1e-9:
            teeth = "pinion_teeth" if name.startswith("pinion") else "gear_teeth"
            raise InvalidInput(
                f"{z} teeth with profile shift {shift:g} are undercut ({teeth}): the shift must be at least "
                f"{x_min:.3f}, or the teeth at least "
                f"{math.ceil(2 * math.cos(helix_angle) * (rack.addendum - shift) / math.sin(math.atan(math.tan(rack.pressure_angle) / math.cos(helix_angle))) ** 2)}",
                field=name)
    an, beta, mn = rack.pressure_angle, helix_angle, normal_module
    alpha_t = math.atan(math.tan(an) / math.cos(beta))
    beta_b = math.atan(math.tan(beta) * math.cos(alpha_t))
    d = np.array([z1, z2]) * mn / math.cos(beta)
    db = d * math.cos(alpha_t)
    _check_face_width(face_width, max_face_width_ratio, float(d[0]))
    a0 = (d[0] + d[1]) / 2
    alpha_w_shift = inv_inverse(inv(alpha_t) + 2 * math.tan(an) * (x1 + x2) / (z1 + z2))
    a_shift = a0 * math.cos(alpha_t) / math.cos(alpha_w_shift)
    a = a_shift if centre_distance is None else centre_distance
    if abs(a - a_shift) > CENTRE_DISTANCE_TOLERANCE * mn:
        cos_w = a0 * math.cos(alpha_t) / a
        need = (inv(math.acos(cos_w)) - inv(alpha_t)) * (z1 + z2) / (2 * math.tan(an)) if abs(cos_w) < 1 else math.nan
        raise InvalidInput(
            f"centre distance {a * 1e3:.4g} mm does not fit the profile shifts (they give {a_shift * 1e3:.4g} mm); "
            f"it needs a shift sum x1 + x2 = {need:.4f}", field="centre_distance_mm")
    alpha_wt = math.acos(a0 * math.cos(alpha_t) / a)
    x = np.array([x1, x2])
    da = d + 2 * mn * (rack.addendum + x)
    df = d - 2 * mn * (rack.dedendum - x)
    dw = db / math.cos(alpha_wt)
    pbt = math.pi * mn * math.cos(alpha_t) / math.cos(beta)
    approach = np.sqrt(da**2 - db**2) / 2
    eps_alpha = float((approach.sum() - a * math.sin(alpha_wt)) / pbt)
    if eps_alpha < 1.0:
        raise InvalidInput(f"transverse contact ratio {eps_alpha:.3f} is below 1: the teeth do not mesh "
                           "continuously", field="pinion_profile_shift")
    # Transverse tooth thickness at the tip circle: a pointed (or nearly pointed) tooth cannot be rated.
    alpha_at = np.arccos(db / da)
    s_at = da * ((math.pi + 4 * x * math.tan(an)) / (2 * np.array([z1, z2])) + inv(alpha_t)
                 - (np.tan(alpha_at) - alpha_at))
    for i, name in enumerate(("pinion_profile_shift", "gear_profile_shift")):
        if s_at[i] * math.cos(beta) < 0.1 * mn:
            raise InvalidInput(f"the {name.split('_')[0]}'s teeth are pointed: tip thickness "
                               f"{s_at[i] * math.cos(beta) / mn:.3f} modules (at least 0.1); reduce the profile "
                               "shift", field=name)
    eps_beta = _overlap_ratio(face_width, beta, mn)
    zn = np.array([z1, z2]) / (math.cos(beta_b) ** 2 * math.cos(beta))
    rho = db / 2 * math.tan(alpha_wt)
    rho_red = float(rho[0] * rho[1] / (rho[0] + rho[1]))
    return PairGeometry(
        (z1, z2), mn, face_width, beta, (x1, x2), rack, alpha_t, alpha_wt, beta_b, float(a), float(a_shift),
        (float(d[0]), float(d[1])), (float(db[0]), float(db[1])), (float(da[0]), float(da[1])),
        (float(df[0]), float(df[1])), (float(dw[0]), float(dw[1])), eps_alpha, float(eps_beta),
        (float(zn[0]), float(zn[1])), rho_red)


def _check_face_width(face_width: float, max_face_width_ratio: float, d1: float) -> None:
    if face_width > max_face_width_ratio * d1:
        raise InvalidInput(
            f"face width {face_width * 1e3:.4g} mm exceeds {max_face_width_ratio:g} pinion reference diameters "
            f"({max_face_width_ratio * d1 * 1e3:.4g} mm): the load would not spread across it",
            field="face_width_mm")


def _overlap_ratio(face_width: float, helix_angle: float, normal_module: float) -> float:
    return float(face_width * math.sin(helix_angle) / (math.pi * normal_module))


def with_face_width(g: PairGeometry, face_width: float, max_face_width_ratio: float = 1.5) -> PairGeometry:
    """The same pair with another face width [m]: the face width and the overlap ratio are all it changes.
    Raises InvalidInput as :func:`pair_geometry` does for a width that is not positive or too wide."""
    if not (math.isfinite(face_width) and face_width > 0):
        raise InvalidInput("face_width_mm must be positive", field="face_width_mm")
    _check_face_width(face_width, max_face_width_ratio, g.d[0])
    return dataclasses.replace(g, face_width=face_width,
                               eps_beta=_overlap_ratio(face_width, g.helix_angle, g.normal_module))
