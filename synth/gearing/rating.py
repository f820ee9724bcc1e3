"""Load capacity of an external spur or helical pair by ISO 6336 method B: pitting (part 2) and tooth root (part 3).

Contact stress sigma_H = Z_B,D Z_H Z_E Z_eps Z_beta sqrt(F_t/(d1 b) (u + 1)/u) sqrt(K_A K_V K_Hbeta K_Halpha)
against sigma_HG = sigma_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X; root stress sigma_F = F_t/(b m_n) Y_F Y_S Y_beta Y_B Y_DT
K_A K_V K_Fbeta K_Falpha (ISO 6336-3:2006 and :2019 method B, eq. (3)) against sigma_FG = sigma_Flim Y_ST Y_NT
Y_deltarelT Y_RrelT Y_X. The safety factors are S_H = sigma_HG/sigma_H and S_F = sigma_FG/sigma_F per gear.

Factors: K_V by method B (resonance ratio, ISO 6336-1 §6.5) with the single and mesh stiffness of §9;
K_Halpha, K_Falpha by method B (§8.3); K_Hbeta by method C (§7.6: mesh misalignment from the pinion's bending
and torsion, pinion centred between its bearings, plus the helix slope deviation of the accuracy grade) unless
the request gives it from a shaft analysis; K_Fbeta = K_Hbeta^N_F. Line loads below 100 N/mm count as 100 N/mm
in these factors, as ISO 6336-1 prescribes. Z_beta = 1/sqrt(cos beta) (ISO 6336-2:2019).
Y_F, Y_S by method B with the load at the outer point of single pair contact (ISO 6336-3:2006 §6.2, §7.2: h_Fe,
alpha_Fen at that point's diameter d_en); the load sharing this point accounts for is why method B has no contact
ratio factor Y_eps (that belonged to the load at the tip, the old method C of DIN 3990). Y_beta of §8, the rim
thickness factor Y_B (§7.7: 1 for a solid wheel or s_R/h >= 1.2, else 1.6 ln(2.242 h/s_R)) and the deep tooth
factor Y_DT (§7.8: 1 for eps_alpha_n <= 2.05 or an accuracy grade above 4; below, 2.366 - 0.666 eps_alpha_n up to
2.5 and 0.7 beyond). Deviations come from ISO 1328-1:2013 for the accuracy grade.

The formulas are stated in ISO's units (mm, N, µm, N/mm²); inputs and results are SI. The load-dependent factors
are evaluated elementwise, so one call rates a whole load spectrum.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InvalidInput
from ..model import FloatArray
from ..warnings import DesignWarning, ValidityCheck
from .involute import BasicRack, PairGeometry, pair_geometry, with_face_width
from .materials import (
    MPA,
    GearMaterial,
    SLIP_LAYER_MM,
    elasticity_factor,
    gear_material,
    life_factor_contact,
    life_factor_root,
    relative_roughness_factor,
    root_size_factor,
    running_in,
    running_in_helix,
    running_in_tip_relief,
)

MM = 1e-3
UM = 1e-6
Y_ST = 2.0
_CHI_T = 1.2  # relative stress gradient of the standard test gear [1/mm]
MIN_LINE_LOAD = 100.0  # [N/mm]: lighter line loads count as this in K_V, K_Hbeta and K_Halpha (ISO 6336-1)


@dataclass(frozen=True, slots=True)
class GearPairSpec:
    """What a rating needs besides the load.

    ``normal_module``, ``face_width``, ``centre_distance`` (None: from the profile shifts) [m]; ``helix_angle``
    [rad]; ``profile_shift`` pinion and gear [-]; ``accuracy_grade`` ISO 1328-1 [-]; ``materials`` grade names of
    pinion and gear; ``oil_viscosity_40`` kinematic viscosity at 40 °C [m²/s]; ``flank_roughness_Ra`` [m];
    ``root_roughness_Rz`` [m]; ``tip_relief`` C_a [m], None for the running-in value; ``face_load_factor``
    K_Hbeta from a shaft analysis, None for method C; ``max_face_width_ratio`` b/d1 limit [-];
    ``rim_thickness`` s_R under the root of pinion and gear [m], None for a solid wheel.
    """

    pinion_teeth: int
    gear_teeth: int
    normal_module: float
    face_width: float
    helix_angle: float = 0.0
    profile_shift: tuple[float, float] = (0.0, 0.0)
    centre_distance: float | None = None
    accuracy_grade: int = 6
    materials: tuple[str, str] = ("case_hardened_MQ", "case_hardened_MQ")
    oil_viscosity_40: float = 220e-6
    flank_roughness_Ra: float = 0.8e-6
    root_roughness_Rz: float = 10e-6
    tip_relief: float | None = None
    face_load_factor: float | None = None
    rack: BasicRack = field(default_factory=BasicRack)
    max_face_width_ratio: float = 1.5
    rim_thickness: tuple[float | None, float | None] = (None, None)


@dataclass(frozen=True, slots=True)
class Duty:
    """Service conditions: ``application_factor`` K_A [-], ``life`` required [h], minimum safety factors
    ``min_safety_contact`` S_Hmin and ``min_safety_root`` S_Fmin [-], ``pitting_permitted`` (the S-N line that
    allows limited pitting for steels)."""

    application_factor: float = 1.0
    life: float = 20000.0
    min_safety_contact: float = 1.0
    min_safety_root: float = 1.4
    pitting_permitted: bool = False


@dataclass(frozen=True, slots=True)
class RatingFactor:
    """One factor of the rating: ISO ``symbol``, ``name`` in words, value for ``pinion`` and ``gear`` (equal for
    a factor of the pair), ``unit`` ('' for dimensionless)."""

    symbol: str
    name: str
    pinion: float
    gear: float
    unit: str = ""


@dataclass(frozen=True, slots=True)
class RatingResult:
    """A rating at one load.

    ``pinion_torque`` [N·m]; ``pinion_speed`` [rad/s]; ``tangential_force`` F_t [N]; ``pitch_line_velocity``
    [m/s]; ``load_cycles`` per gear over the life; stresses per gear [Pa]: ``contact_stress`` sigma_H,
    ``contact_limit`` sigma_HG, ``permissible_contact`` sigma_HP = sigma_HG / S_Hmin, ``root_stress``
    sigma_F, ``root_limit`` sigma_FG, ``permissible_root``; safety factors ``safety_contact`` S_H and
    ``safety_root`` S_F per gear [-]; ``factors`` every factor by symbol; ``checks`` independent figures.
    """

    geometry: PairGeometry
    materials: tuple[GearMaterial, GearMaterial]
    duty: Duty
    pinion_torque: float
    pinion_speed: float
    tangential_force: float
    pitch_line_velocity: float
    load_cycles: tuple[float, float]
    nominal_contact_stress: float
    contact_stress: tuple[float, float]
    contact_limit: tuple[float, float]
    permissible_contact: tuple[float, float]
    nominal_root_stress: tuple[float, float]
    root_stress: tuple[float, float]
    root_limit: tuple[float, float]
    permissible_root: tuple[float, float]
    safety_contact: tuple[float, float]
    safety_root: tuple[float, float]
    factors: tuple[RatingFactor, ...]
    checks: RatingChecks
    warnings: tuple[DesignWarning, ...] = ()
    validity: tuple[ValidityCheck, ...] = ()

    def factor(self, symbol: str) -> RatingFactor:
        """The factor named ``symbol`` (``K_V``, ``Z_H``, ``Y_F``...)."""
        return next(f for f in self.factors if f.symbol == symbol)


@dataclass(frozen=True, slots=True)
class RatingChecks:
    """Independent figures: ``hertz_contact_stress`` the pitch-point Hertz stress of two cylinders of the
    flanks' radii under the normal line load F_t/(b cos alpha_wt cos beta_b), times Z_eps Z_beta and the K
    factors [Pa] (equals sigma_H/Z_B for every pair); ``power_balance`` F_t v / (T_1 w_1) [-] (equals 1)."""

    hertz_contact_stress: float
    power_balance: float


def _tolerances(grade: int, d_mm: FloatArray, mn_mm: float, b_mm: float) -> dict[str, FloatArray]:
    """ISO 1328-1:2013 tolerances [µm] per gear: single pitch f_p, profile form f_falpha, helix slope f_Hbeta."""
    scale = 2.0 ** ((grade - 5) / 2)
    return {"f_pt": _rounded((0.001 * d_mm + 0.4 * mn_mm + 5) * scale),
            "f_falpha": _rounded((0.55 * mn_mm + 5) * scale * np.ones_like(d_mm)),
            "f_Hbeta": _helix_slope_tolerance(grade, d_mm, b_mm)}


def _helix_slope_tolerance(grade: int, d_mm: FloatArray, b_mm: float) -> FloatArray:
    """f_Hbeta of ISO 1328-1:2013 [µm] per gear, the one tolerance the face width enters."""
    return _rounded((0.05 * np.sqrt(d_mm) + 0.35 * math.sqrt(b_mm) + 4) * 2.0 ** ((grade - 5) / 2))


def _rounded(v: FloatArray) -> FloatArray:
    # ISO 1328-1 rounds tolerances to 0.1 µm below 10 µm and to whole micrometres above.
    return np.asarray(np.where(v < 10, np.round(v, 1), np.round(v)), dtype=float)


def _single_stiffness(g: PairGeometry) -> tuple[float, float, float]:
    """c'_th, c' [N/(mm·µm)] and the mesh stiffness c_gamma_alpha (ISO 6336-1 §9, solid wheels, C_M = 0.8)."""
    zn1, zn2 = g.zn
    x1, x2 = g.x
    q = (0.04723 + 0.15551 / zn1 + 0.25791 / zn2 - 0.00635 * x1 - 0.11654 * x1 / zn1 - 0.00193 * x2
         - 0.24188 * x2 / zn2 + 0.00529 * x1**2 + 0.00182 * x2**2)
    c_th = 1.0 / q
    c_b = (1 + 0.5 * (1.2 - g.rack.dedendum)) * (1 - 0.02 * (20 - math.degrees(g.rack.pressure_angle)))
    c1 = c_th * 0.8 * 1.0 * c_b * math.cos(g.helix_angle)
    return c_th, c1, c1 * (0.75 * g.eps_alpha + 0.25)


def _resonance_ratio(g: PairGeometry, mats: tuple[GearMaterial, GearMaterial], n1_rpm: float, c_ga: float
                     ) -> float:
    """The resonance ratio N = n1/nE1 (ISO 6336-1 §6.5.3) [-]."""
    dm = (np.array(g.da) + np.array(g.df)) / 2 / MM
    db = np.array(g.db) / MM
    rho = np.array([m.density for m in mats]) * 1e-9  # [kg/mm³]
    m_star = math.pi / 8 * rho * dm**4 / db**2      # mass per face width reduced to the line of action [kg/mm]
    m_red = float(m_star[0] * m_star[1] / (m_star[0] + m_star[1]))
    n_e1 = 30000.0 / (math.pi * g.z[0]) * math.sqrt(c_ga / m_red)
    return n1_rpm / n_e1


def _running_in(mats: tuple[GearMaterial, GearMaterial], deviation_um: float) -> float:
    """The pair's running-in allowance y_alpha of a pitch or profile deviation [µm]: the wheels' mean."""
    return float(np.mean([running_in(m.group, m.sigma_Hlim, deviation_um) for m in mats]))


def _dynamic_factor(g: PairGeometry, line_load: FloatArray, n_ratio: float, c1: float, fpb: float, y_p: float,
                    ff: float, y_f: float, tip_relief_um: float) -> FloatArray:
    """K_V by method B (ISO 6336-1 §6.5) at the resonance ratio ``n_ratio``; ``line_load`` K_A F_t / b [N/mm],
    ``fpb``, ``ff`` the pitch and profile deviations and ``y_p``, ``y_f`` their running-in allowances [µm]."""
    eg = g.eps_gamma
    if eg <= 2:
        cv2, cv3, cv4, cv6 = 0.34, 0.23, 0.90, 0.47
    else:
        cv2, cv3 = 0.57 / (eg - 0.3), 0.096 / (eg - 1.56)
        cv4, cv6 = (0.57 - 0.05 * eg) / (eg - 1.44), 0.12 / (eg - 1.74)
    cv1, cv5 = 0.32, 0.47
    cv7 = 0.75 if eg <= 1.5 else (0.125 * math.sin(math.pi * (eg - 2)) + 0.875 if eg <= 2.5 else 1.0)
    # ISO 6336-1 takes line loads below 100 N/mm as 100 N/mm in the deviation terms.
    floor = np.maximum(line_load, MIN_LINE_LOAD)
    bp = c1 * (fpb - y_p) / floor
    bf = c1 * (ff - y_f) / floor
    bk = np.abs(1 - c1 * tip_relief_um / floor)
    # N_S lies in [0.5, 0.85]: outside that band of N one range holds at every load, and only its K_V is needed
    if n_ratio <= 0.5:
        return np.asarray(n_ratio * (cv1 * bp + cv2 * bf + cv3 * bk) + 1, dtype=float)
    main = cv1 * bp + cv2 * bf + cv4 * bk + 1
    if 0.85 < n_ratio <= 1.15:
        return np.asarray(main, dtype=float)
    sup = cv5 * bp + cv6 * bf + cv7
    mid = sup + (main - sup) * (1.5 - n_ratio) / 0.35
    if n_ratio > 0.85:
        return np.asarray(mid if n_ratio < 1.5 else sup, dtype=float)
    n_s = np.where(line_load < 100, 0.5 + 0.35 * np.sqrt(line_load / 100), 0.85)
    sub = n_ratio * (cv1 * bp + cv2 * bf + cv3 * bk) + 1
    kv = np.where(n_ratio <= n_s, sub, np.where(n_ratio <= 1.15, main, np.where(n_ratio < 1.5, mid, sup)))
    return np.asarray(kv, dtype=float)


def subcritical_limit(line_load: float) -> float:
    """N_S, the upper end of the subcritical range (ISO 6336-1 §6.5.4): 0.85, or 0.5 + 0.35·sqrt(K_A F_t/b/100)
    below 100 N/mm of line load ``line_load`` [N/mm]."""
    return 0.5 + 0.35 * math.sqrt(line_load / 100) if line_load < 100 else 0.85


#: Subcritical resonances: where N is near 1/2 or 1/3 the mesh frequency's second or third harmonic meets the
#: pair's natural frequency (ISO 6336-1 §6.5.4); within this fraction of those ratios a warning is given.
SUBCRITICAL_BAND = 0.1


def resonance_validity(n_ratio: float, line_load: float) -> tuple[list[DesignWarning], list[ValidityCheck]]:
    """The ranges of the resonance ratio N = n1/nE1 of ISO 6336-1 §6.5.4: the main resonance range
    N_S < N <= 1.15 (to be avoided; method B's K_V does not hold there), the intermediate range 1.15 < N < 1.5
    (K_V interpolated; the standard asks method A), and the subcritical range's resonances near N = 1/2, 1/3;
    the supercritical range N >= 1.5 and the rest of the subcritical one pass."""
    n_s = subcritical_limit(line_load)
    notes: list[DesignWarning] = []
    main = n_s < n_ratio <= 1.15
    checks = [ValidityCheck("main_resonance", n_ratio, n_s, not main,
                            f"resonance ratio N = n1/nE1 outside the main resonance range {n_s:.3g} < N <= 1.15 "
                            "(ISO 6336-1)")]
    if main:
        notes.append(DesignWarning(
            "gear_main_resonance", "pinion_speed_rpm", n_ratio,
            f"the pair runs at N = {n_ratio:.3g} of its mesh resonance, in the main resonance range {n_s:.3g} < N "
            "<= 1.15, which ISO 6336-1 says to avoid: the dynamic factor by method B does not hold there; change "
            "the speed, the teeth or the masses", "1"))
    elif 1.15 < n_ratio < 1.5:
        checks.append(ValidityCheck("intermediate_resonance", n_ratio, 1.5, False,
                                    "resonance ratio N in the intermediate range 1.15 < N < 1.5 (ISO 6336-1)"))
        notes.append(DesignWarning(
            "gear_intermediate_resonance", "pinion_speed_rpm", n_ratio,
            f"the pair runs at N = {n_ratio:.3g}, in the intermediate range 1.15 < N < 1.5 between the main "
            "resonance and the supercritical range: K_V is interpolated, and ISO 6336-1 asks a closer analysis "
            "(method A)", "1"))
    elif n_ratio <= n_s:
        for order in (2, 3):
            if abs(n_ratio * order - 1) <= SUBCRITICAL_BAND:
                checks.append(ValidityCheck("subcritical_resonance", n_ratio, 1 / order, False,
                                            f"resonance ratio N near 1/{order}: the mesh frequency's harmonic "
                                            f"{order} at the pair's natural frequency"))
                notes.append(DesignWarning(
                    "gear_subcritical_resonance", "pinion_speed_rpm", n_ratio,
                    f"the pair runs at N = {n_ratio:.3g}, near 1/{order}: harmonic {order} of the mesh frequency "
                    "excites the pair's natural frequency, a resonance of the subcritical range (ISO 6336-1) that "
                    "K_V by method B does not include for gears of low accuracy", "1"))
    return notes, checks


def _face_load_factor(g: PairGeometry, mats: tuple[GearMaterial, GearMaterial], fm_per_b: FloatArray,
                      c_gb: float, f_hbeta: float) -> FloatArray:
    """K_Hbeta by method C (ISO 6336-1 §7.6): F_betax = 1.33 f_sh + f_ma, f_sh = 0.023 (F_m/b)(b/d1)² for a
    pinion centred between its bearings, f_ma the helix slope deviation, less the running-in allowance."""
    b_d1 = g.face_width / g.d[0]
    fm_per_b = np.maximum(fm_per_b, MIN_LINE_LOAD)
    f_sh = 0.023 * fm_per_b * b_d1**2
    f_bx = 1.33 * f_sh + f_hbeta
    if mats[0] is mats[1]:
        y_b = running_in_helix(mats[0].group, mats[0].sigma_Hlim, f_bx)   # the mean of two equal allowances
    else:
        y_b = np.mean([running_in_helix(m.group, m.sigma_Hlim, f_bx) for m in mats], axis=0)
    f_by = np.maximum(f_bx - y_b, 0.0)
    k = c_gb * f_by / (2 * fm_per_b)
    return np.asarray(np.where(k <= 1, 1 + k, np.sqrt(4 * k)), dtype=float)


def _root_form_factors(g: PairGeometry) -> dict[str, FloatArray]:
    """Y_F, Y_S and the tooth-root figures of method B at the outer point of single pair contact, per gear."""
    # every figure here is the tooth's, not the face width's: a sizing's width search reads them from the cache
    key = (g.normal_module, g.rack, g.helix_angle, g.beta_b, g.eps_alpha, tuple(g.z), tuple(g.zn), tuple(g.x),
           tuple(g.d), tuple(g.da))
    return {k: v.copy() if isinstance(v, np.ndarray) else v for k, v in _root_form_cached(key, g).items()}


_ROOT_FORMS: dict[tuple[object, ...], dict[str, FloatArray]] = {}
_ROOT_FORMS_HELD = 256


def _root_form_cached(key: tuple[object, ...], g: PairGeometry) -> dict[str, FloatArray]:
    held = _ROOT_FORMS.get(key)
    if held is None:
        held = _ROOT_FORMS[key] = _root_form_computed(g)
        if len(_ROOT_FORMS) > _ROOT_FORMS_HELD:
            _ROOT_FORMS.pop(next(iter(_ROOT_FORMS)), None)
    return held


def _root_form_computed(g: PairGeometry) -> dict[str, FloatArray]:
    mn = g.normal_module / MM
    an = g.rack.pressure_angle
    beta = g.helix_angle
    z = np.array(g.z, dtype=float)
    zn = np.array(g.zn)
    x = np.array(g.x)
    d = np.array(g.d) / MM
    da = np.array(g.da) / MM
    hfp, rfp = g.rack.dedendum * mn, g.rack.root_radius * mn
    e = math.pi / 4 * mn - hfp * math.tan(an) - (1 - math.sin(an)) * rfp / math.cos(an)
    big_g = rfp / mn - hfp / mn + x
    big_h = 2 / zn * (math.pi / 2 - e / mn) - math.pi / 3
    theta = np.full(2, math.pi / 6)
    slope = 2 * big_g / zn
    for _ in range(60):
        # once an iterate repeats itself exactly, every later one is the same: stop there
        theta, last = np.minimum(np.maximum(slope * np.tan(theta) - big_h, -1.5), 1.5), theta
        if np.array_equal(theta, last):
            break
    s_fn = mn * (zn * np.sin(math.pi / 3 - theta) + math.sqrt(3) * (big_g / np.cos(theta) - rfp / mn))
    rho_f = rfp + 2 * mn * big_g**2 / (np.cos(theta) * (zn * np.cos(theta) ** 2 - 2 * big_g))
    dn = mn * zn
    dbn = dn * math.cos(an)
    dan = dn + da - d
    eps_an = g.eps_alpha / math.cos(g.beta_b) ** 2
    den = 2 * np.sqrt((np.sqrt((dan / 2) ** 2 - (dbn / 2) ** 2) - math.pi * d * math.cos(beta) * math.cos(an) / z
                       * (eps_an - 1)) ** 2 + (dbn / 2) ** 2)
    alpha_en = np.arccos(dbn / den)
    inv_an = math.tan(an) - an
    gamma_e = (0.5 * math.pi + 2 * np.tan(an) * x) / zn + inv_an - (np.tan(alpha_en) - alpha_en)
    alpha_fen = alpha_en - gamma_e
    h_fe = 0.5 * mn * ((np.cos(gamma_e) - np.sin(gamma_e) * np.tan(alpha_fen)) * den / mn
                       - zn * np.cos(math.pi / 3 - theta) - big_g / np.cos(theta) + rfp / mn)
    y_f = 6 * (h_fe / mn) * np.cos(alpha_fen) / ((s_fn / mn) ** 2 * math.cos(an))
    big_l = s_fn / h_fe
    q_s = s_fn / (2 * rho_f)
    y_s = (1.2 + 0.13 * big_l) * q_s ** (1 / (1.21 + 2.3 / big_l))
    return {"Y_F": y_f, "Y_S": y_s, "q_s": q_s, "s_Fn": s_fn, "rho_F": rho_f, "h_Fe": h_fe, "eps_an": eps_an}


def rim_thickness_factor(rim: float | None, depth: float, field: str = "rim_thickness_mm") -> float:
    """Y_B of an external gear (ISO 6336-3:2006 §7.7) from the rim thickness s_R under the root and the tooth
    depth h [m]: 1 for a solid wheel (None) or s_R/h >= 1.2, 1.6 ln(2.242 h/s_R) down to s_R/h = 0.5; thinner
    rims are outside the standard."""
    if rim is None:
        return 1.0
    if not (math.isfinite(rim) and rim > 0):
        raise InvalidInput(f"the rim thickness must be positive, got {rim}", field=field)
    ratio = rim / depth
    if ratio <= 0.5:
        raise InvalidInput(f"a rim thickness of {ratio:.3g} tooth depths is below the 0.5 ISO 6336-3 rates",
                           field=field)
    return 1.0 if ratio >= 1.2 else 1.6 * math.log(2.242 / ratio)


def deep_tooth_factor(eps_alpha_n: float, accuracy_grade: int) -> float:
    """Y_DT (ISO 6336-3:2006 §7.8) from the virtual contact ratio eps_alpha_n and the ISO 1328 grade: 1 for
    eps_alpha_n <= 2.05 or grades above 4 (coarser), 2.366 - 0.666 eps_alpha_n up to 2.5, 0.7 beyond."""
    if accuracy_grade > 4 or eps_alpha_n <= 2.05:
        return 1.0
    return 2.366 - 0.666 * eps_alpha_n if eps_alpha_n <= 2.5 else 0.7


def _single_pair_factors(g: PairGeometry) -> tuple[float, float]:
    """Z_B and Z_D (ISO 6336-2 §6): the contact stress at the inner points of single pair contact."""
    z1, z2 = g.z
    r1 = math.sqrt((g.da[0] / g.db[0]) ** 2 - 1)
    r2 = math.sqrt((g.da[1] / g.db[1]) ** 2 - 1)
    tw = math.tan(g.alpha_wt)
    p1 = (r1 - 2 * math.pi / z1) * (r2 - (g.eps_alpha - 1) * 2 * math.pi / z2)
    p2 = (r2 - 2 * math.pi / z2) * (r1 - (g.eps_alpha - 1) * 2 * math.pi / z1)
    m1 = tw / math.sqrt(p1) if p1 > 0 else 1.0
    m2 = tw / math.sqrt(p2) if p2 > 0 else 1.0
    eb = min(g.eps_beta, 1.0)
    zb = max(1.0, m1 - eb * (m1 - 1))
    zd = max(1.0, m2 - eb * (m2 - 1))
    return zb, zd


@dataclass(frozen=True, slots=True)
class _LoadFactors:
    ft: FloatArray
    kv: FloatArray
    khb: FloatArray
    kfb: FloatArray
    kha: FloatArray
    kfa: FloatArray
    n_ratio: float


class PairModel:
    """The load-independent part of a rating, built once per pair and duty; :meth:`stresses` evaluates any
    number of pinion torques at once."""

    tol: dict[str, FloatArray]
    fpb: float
    ff: float
    _d_mm: FloatArray
    _depth: tuple[float, float]

    def __init__(self, spec: GearPairSpec, duty: Duty, pinion_speed: float) -> None:
        for name, v in (("application_factor", duty.application_factor), ("life_h", duty.life),
                        ("min_safety_contact", duty.min_safety_contact), ("min_safety_root", duty.min_safety_root),
                        ("pinion_speed_rpm", pinion_speed), ("oil_viscosity_40C_mm2_s", spec.oil_viscosity_40),
                        ("flank_roughness_Ra_um", spec.flank_roughness_Ra),
                        ("root_roughness_Rz_um", spec.root_roughness_Rz)):
            if not (math.isfinite(v) and v > 0):
                raise InvalidInput(f"{name} must be positive, got {v}", field=name)
        if duty.application_factor < 1:
            raise InvalidInput("the application factor K_A is at least 1", field="application_factor")
        if not 1 <= spec.accuracy_grade <= 11:
            raise InvalidInput("the ISO 1328-1 accuracy grade lies in 1..11", field="accuracy_grade")
        if spec.face_load_factor is not None and not 1 <= spec.face_load_factor <= 10:
            raise InvalidInput("K_Hbeta lies in [1, 10]", field="face_load_factor")
        if spec.root_roughness_Rz >= 16e-6:
            raise InvalidInput("method B's Y_RrelT covers a root roughness Rz below 16 µm",
                               field="root_roughness_Rz_um")
        self.spec, self.duty, self.speed = spec, duty, pinion_speed
        self.mats = (gear_material(spec.materials[0], "pinion_material"),
                     gear_material(spec.materials[1], "gear_material"))
        g = pair_geometry(spec.pinion_teeth, spec.gear_teeth, spec.normal_module, spec.face_width,
                          spec.helix_angle, spec.profile_shift[0], spec.profile_shift[1], spec.centre_distance,
                          spec.rack, spec.max_face_width_ratio)
        mn = g.normal_module / MM
        d = np.array(g.d) / MM
        self._face_width_terms(g)
        self.c_th, self.c1, self.c_ga = _single_stiffness(g)
        self.c_gb = 0.85 * self.c_ga
        self.tip_relief_um = (float(np.mean([running_in_tip_relief(m.sigma_Hlim) for m in self.mats]))
                              if spec.tip_relief is None else spec.tip_relief / UM)
        u = g.ratio
        self.n1_rpm = pinion_speed * 30 / math.pi
        self.n_ratio = _resonance_ratio(g, self.mats, self.n1_rpm, self.c_ga)
        self.y_p, self.y_f_dev = _running_in(self.mats, self.fpb), _running_in(self.mats, self.ff)
        self.v = math.pi * d[0] * self.n1_rpm / 60000.0
        self.cycles = np.array([60 * self.n1_rpm * duty.life, 60 * self.n1_rpm / u * duty.life])
        cb, ca = math.cos(g.beta_b), math.cos(g.alpha_t)
        self.z_h = math.sqrt(2 * cb * math.cos(g.alpha_wt) / (ca**2 * math.sin(g.alpha_wt)))
        self.z_e = elasticity_factor(*self.mats)
        self.z_beta = 1 / math.sqrt(math.cos(g.helix_angle))
        lim = np.array([m.sigma_Hlim / MPA for m in self.mats])
        czl = np.where(lim < 850, 0.83, np.where(lim > 1200, 0.91, 0.08 * (lim - 850) / 350 + 0.83))
        nu40 = spec.oil_viscosity_40 * 1e6
        self.z_l = czl + 4 * (1 - czl) / (1.2 + 134 / nu40) ** 2
        czv = czl + 0.02
        self.z_v = czv + 2 * (1 - czv) / np.sqrt(0.8 + 32 / self.v)
        rz = 6 * spec.flank_roughness_Ra / UM   # R_z ≈ 6 R_a for ground or shaved flanks
        rz10 = rz * (10 / (g.rho_red / MM)) ** (1 / 3)
        czr = np.where(lim < 850, 0.15, np.where(lim > 1200, 0.08, 0.32 - 0.0002 * lim))
        self.z_r = (3 / rz10) ** czr
        self.z_w = np.ones(2)
        hard = [m.surface_hardened for m in self.mats]
        for i in (0, 1):
            if hard[1 - i] and not hard[i]:
                hb = self.mats[i].hardness_HB
                self.z_w[i] = 1.2 if hb < 130 else (1.0 if hb > 470 else 1.2 - (hb - 130) / 1700)
        self.z_x = np.ones(2)
        self.z_nt = np.array([life_factor_contact(m, c, duty.pitting_permitted)
                              for m, c in zip(self.mats, self.cycles, strict=True)], dtype=float).reshape(2)
        root = _root_form_factors(g)
        self.root = root
        self.y_f, self.y_s = root["Y_F"], root["Y_S"]
        _check_finite(self)
        depth = (np.array(g.da) - np.array(g.df)) / 2
        self.y_b = np.array([rim_thickness_factor(sr, h, f"{who}_rim_thickness_mm") for sr, h, who in
                             zip(spec.rim_thickness, depth, ("pinion", "gear"), strict=True)])
        self.y_dt = deep_tooth_factor(float(root["eps_an"]), spec.accuracy_grade)
        self.y_nt = np.array([life_factor_root(m, c) for m, c in zip(self.mats, self.cycles, strict=True)],
                             dtype=float).reshape(2)
        chi = (1 + 2 * root["q_s"]) / 5
        rho_p = np.array([SLIP_LAYER_MM[m.group] for m in self.mats])
        self.y_delta = (1 + np.sqrt(rho_p * chi)) / (1 + np.sqrt(rho_p * _CHI_T))
        self.y_r = np.array([relative_roughness_factor(m.group, spec.root_roughness_Rz / UM) for m in self.mats])
        self.y_x = np.array([root_size_factor(m.group, mn) for m in self.mats])
        self.sigma_hg = lim * self.z_nt * self.z_l * self.z_v * self.z_r * self.z_w * self.z_x * MPA
        flim = np.array([m.sigma_Flim / MPA for m in self.mats])
        self.sigma_fg = flim * Y_ST * self.y_nt * self.y_delta * self.y_r * self.y_x * MPA

    def _face_width_terms(self, g: PairGeometry, rewidth: bool = False) -> None:
        """What the face width enters, itself or through the overlap ratio eps_beta: the helix slope tolerance,
        Z_eps, Z_B/Z_D, Y_beta and K_Fbeta's exponent N_F. Nothing else in the model depends on it."""
        self.geometry = g
        if rewidth:                      # the pitch and profile tolerances and the tooth depths stay
            self.tol = {**self.tol, "f_Hbeta": _helix_slope_tolerance(self.spec.accuracy_grade, self._d_mm,
                                                                       g.face_width / MM)}
        else:
            self._d_mm = np.array(g.d) / MM
            self.tol = _tolerances(self.spec.accuracy_grade, self._d_mm, g.normal_module / MM, g.face_width / MM)
            self.fpb = float(np.max(self.tol["f_pt"]))
            self.ff = float(np.max(self.tol["f_falpha"]))
            depth = (np.array(g.da) - np.array(g.df)) / 2
            self._depth = float(np.max(depth)), float(np.min(depth))
        self.f_hbeta = float(np.max(self.tol["f_Hbeta"]))
        ea, eb = g.eps_alpha, g.eps_beta
        if eb >= 1:
            self.z_eps = math.sqrt(1 / ea)
        else:
            self.z_eps = math.sqrt((4 - ea) / 3 * (1 - eb) + eb / ea)
        self.z_b, self.z_d = _single_pair_factors(g)
        beta_deg = min(math.degrees(g.helix_angle), 30.0)
        self.y_beta = max(1 - min(eb, 1.0) * beta_deg / 120, 1 - 0.25 * min(eb, 1.0), 0.75)
        bh = max(min(g.face_width / self._depth[0], g.face_width / self._depth[1]), 3.0)
        self.n_f = bh**2 / (1 + bh + bh**2)

    def at_width(self, face_width: float) -> PairModel:
        """The same pair, duty and speed at another face width [m], the rest of the model shared: a sizing's
        width search rates one pair at many widths. Raises InvalidInput as the geometry does for a width that
        is not positive or exceeds the spec's ratio to the pinion diameter."""
        g = with_face_width(self.geometry, face_width, self.spec.max_face_width_ratio)
        model = copy.copy(self)
        model.spec = dataclasses.replace(self.spec, face_width=face_width)
        model._face_width_terms(g, rewidth=True)
        return model

    def load_factors(self, torque: FloatArray) -> _LoadFactors:
        """Tangential force [N] and the load-dependent K factors at each pinion torque [N·m]."""
        g = self.geometry
        b = g.face_width / MM
        ft = 2000.0 * np.abs(np.asarray(torque, dtype=float)) / (g.d[0] / MM)
        ka = self.duty.application_factor
        line = np.maximum(ka * ft / b, 1e-9)
        kv = _dynamic_factor(g, line, self.n_ratio, self.c1, self.fpb, self.y_p, self.ff, self.y_f_dev,
                             self.tip_relief_um)
        if self.spec.face_load_factor is not None:
            khb = np.full_like(ft, self.spec.face_load_factor)
        else:
            khb = _face_load_factor(g, self.mats, kv * line, self.c_gb, self.f_hbeta)
        kfb = khb**self.n_f
        y_a = self.y_p
        fth_b = np.maximum(line * kv * khb, MIN_LINE_LOAD)
        eg, ea = g.eps_gamma, g.eps_alpha
        core = self.c_ga * (self.fpb - y_a) / fth_b
        if eg <= 2:
            ka_raw = eg / 2 * (0.9 + 0.4 * core)
        else:
            ka_raw = 0.9 + 0.4 * math.sqrt(2 * (eg - 1) / eg) * core
        floored = np.maximum(ka_raw, 1.0)
        kha = np.minimum(floored, eg / (ea * self.z_eps**2))
        y_e = 0.25 + 0.75 / ea
        kfa = np.minimum(floored, eg / (ea * y_e))
        return _LoadFactors(ft, kv, khb, kfb, kha, kfa, self.n_ratio)

    def stresses(self, torque: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, _LoadFactors]:
        """Nominal contact stress (N,), contact stress (N, 2) and root stress (N, 2) [Pa] at each pinion torque."""
        sh0, lanes, lf = self.lane_stresses(torque)
        return sh0, lanes[:2].T, lanes[2:].T, lf

    def lane_stresses(self, torque: FloatArray) -> tuple[FloatArray, FloatArray, _LoadFactors]:
        """Nominal contact stress (N,) and the stresses (4, N) [Pa] of the pinion's and the gear's flank, then
        the pinion's and the gear's root, at each pinion torque: one contiguous row per wheel and mode, the
        layout a Miner sum over the samples runs along."""
        g = self.geometry
        lf = self.load_factors(torque)
        u = g.ratio
        b, d1, mn = g.face_width / MM, g.d[0] / MM, g.normal_module / MM
        ka = self.duty.application_factor
        sh0 = self.z_h * self.z_e * self.z_eps * self.z_beta * np.sqrt(lf.ft / (d1 * b) * (u + 1) / u)
        k_h = sh0 * np.sqrt(ka * lf.kv * lf.khb * lf.kha)
        nominal_root = lf.ft / (b * mn)
        k_f = ka * lf.kv * lf.kfb * lf.kfa
        y = self.y_f * self.y_s * self.y_beta * self.y_b * self.y_dt
        out = np.empty((4, sh0.size))
        for row, z in enumerate((self.z_b, self.z_d)):
            np.multiply(k_h, z, out=out[row])
        for row in (0, 1):
            np.multiply(nominal_root, y[row], out=out[2 + row])
            out[2 + row] *= k_f
        out *= MPA
        return sh0 * MPA, out, lf


def _pair(v: FloatArray | tuple[float, float]) -> tuple[float, float]:
    a = np.asarray(v, dtype=float).reshape(2)
    return float(a[0]), float(a[1])


def rate_pair(spec: GearPairSpec, pinion_torque: float, pinion_speed: float, duty: Duty | None = None
              ) -> RatingResult:
    """ISO 6336 method B rating of a pair at one pinion torque [N·m] and speed [rad/s].

    The load is the nominal torque; K_A of ``duty`` multiplies it in the stresses. Raises InvalidInput naming
    the field for geometry, material or service data that cannot be rated.
    """
    duty = duty or Duty()
    if not (math.isfinite(pinion_torque) and pinion_torque > 0):
        raise InvalidInput(f"pinion_torque_Nm must be positive, got {pinion_torque}", field="pinion_torque_Nm")
    model = PairModel(spec, duty, pinion_speed)
    return _result(model, pinion_torque)


def _check_finite(model: PairModel) -> None:
    """Method B's root section and K factors exist for every rateable pair; say which input left its range."""
    root = np.concatenate([model.y_f, model.y_s, model.root["q_s"]])
    if not np.all(np.isfinite(root)) or np.any(model.root["q_s"] <= 0):
        raise InvalidInput("the tooth root section of method B does not exist for this basic rack and profile "
                           "shift", field="pinion_profile_shift")


def _result(model: PairModel, pinion_torque: float) -> RatingResult:
    g, duty = model.geometry, model.duty
    sh0, sh, sf, lf = model.stresses(np.array([pinion_torque]))
    sh, sf = sh[0], sf[0]
    sigma_hg, sigma_fg = model.sigma_hg, model.sigma_fg
    b, mn = g.face_width / MM, g.normal_module / MM
    sf0 = lf.ft[0] / (b * mn) * model.y_f * model.y_s * model.y_beta * model.y_b * model.y_dt * MPA
    ka = duty.application_factor
    # The independent check: Hertz stress of two cylinders of the flanks' radii at the pitch point.
    rho = np.array(g.db) / 2 * math.tan(g.alpha_wt) / math.cos(g.beta_b)   # normal-section radii
    e1, e2 = (m.elastic_modulus for m in model.mats)
    n1, n2 = (m.poisson for m in model.mats)
    e_star = 1 / ((1 - n1**2) / e1 + (1 - n2**2) / e2)
    line = lf.ft[0] / (g.face_width * math.cos(g.alpha_t))   # normal force per length of contact line
    hertz = math.sqrt(line * e_star / (math.pi * (rho[0] * rho[1] / (rho[0] + rho[1]))))
    hertz *= model.z_eps * model.z_beta * math.sqrt(ka * lf.kv[0] * lf.khb[0] * lf.kha[0])
    power = float(lf.ft[0] * model.v / (pinion_torque * model.speed))
    notes, validity = resonance_validity(lf.n_ratio, float(ka * lf.ft[0] / b))

    def s(sym: str, name: str, v: object, unit: str = "") -> RatingFactor:
        return RatingFactor(sym, name, *_pair(np.broadcast_to(np.asarray(v, dtype=float), (2,))), unit)

    factors = (
        s("K_A", "application factor", ka),
        s("K_V", "dynamic factor (method B)", lf.kv[0]),
        s("N", "resonance ratio n1/nE1", lf.n_ratio),
        s("K_Hbeta", "face load factor, contact" + (" (given)" if model.spec.face_load_factor else
                                                    " (method C)"), lf.khb[0]),
        s("K_Fbeta", "face load factor, root (K_Hbeta^N_F)", lf.kfb[0]),
        s("N_F", "exponent of K_Fbeta", model.n_f),
        s("K_Halpha", "transverse load factor, contact (method B)", lf.kha[0]),
        s("K_Falpha", "transverse load factor, root (method B)", lf.kfa[0]),
        s("Z_H", "zone factor", model.z_h),
        s("Z_E", "elasticity factor", model.z_e, "sqrt(N/mm2)"),
        s("Z_eps", "contact ratio factor", model.z_eps),
        s("Z_beta", "helix angle factor", model.z_beta),
        s("Z_B/Z_D", "single pair tooth contact factors", [model.z_b, model.z_d]),
        s("Z_NT", "life factor, contact", model.z_nt),
        s("Z_L", "lubricant factor", model.z_l),
        s("Z_v", "velocity factor", model.z_v),
        s("Z_R", "roughness factor", model.z_r),
        s("Z_W", "work hardening factor", model.z_w),
        s("Z_X", "size factor, contact", model.z_x),
        s("Y_F", "tooth form factor (method B, load at the outer point of single pair contact)", model.y_f),
        s("Y_S", "stress correction factor (method B, same point)", model.y_s),
        s("Y_beta", "helix angle factor, root", model.y_beta),
        s("Y_B", "rim thickness factor", model.y_b),
        s("Y_DT", "deep tooth factor", model.y_dt),
        s("eps_alpha_n", "virtual transverse contact ratio", model.root["eps_an"]),
        s("Y_ST", "stress correction factor of the test gear", Y_ST),
        s("Y_NT", "life factor, root", model.y_nt),
        s("Y_deltarelT", "relative notch sensitivity factor", model.y_delta),
        s("Y_RrelT", "relative surface factor", model.y_r),
        s("Y_X", "size factor, root", model.y_x),
        s("c'", "single stiffness", model.c1, "N/(mm·µm)"),
        s("c'_th", "theoretical single stiffness", model.c_th, "N/(mm·µm)"),
        s("c_gamma_alpha", "mesh stiffness", model.c_ga, "N/(mm·µm)"),
        s("f_pb", "base pitch deviation (ISO 1328-1 tolerance)", model.fpb, "µm"),
        s("f_falpha", "profile form deviation (ISO 1328-1 tolerance)", model.ff, "µm"),
        s("f_Hbeta", "helix slope deviation (ISO 1328-1 tolerance)", model.f_hbeta, "µm"),
        s("C_a", "tip relief", model.tip_relief_um, "µm"),
        s("z_n", "virtual number of teeth", np.array(g.zn)),
        s("q_s", "notch parameter", model.root["q_s"]),
        s("rho_F", "root fillet radius at the critical section", model.root["rho_F"], "mm"),
        s("s_Fn", "tooth root chord at the critical section", model.root["s_Fn"], "mm"),
        s("h_Fe", "bending moment arm", model.root["h_Fe"], "mm"),
    )
    return RatingResult(
        g, model.mats, duty, pinion_torque, model.speed, float(lf.ft[0]), model.v,
        _pair(model.cycles), float(sh0[0]), _pair(sh), _pair(sigma_hg), _pair(sigma_hg / duty.min_safety_contact),
        _pair(sf0), _pair(sf), _pair(sigma_fg), _pair(sigma_fg / duty.min_safety_root),
        _pair(sigma_hg / sh), _pair(sigma_fg / sf), factors, RatingChecks(hertz, power),
        tuple(notes), tuple(validity))
