"""The parallel key of a hub on a shaft (gear, flywheel, counterweight, coupling), by DIN 6885-1.

Inputs: the hub's name, the shaft diameter [m], the torque the key carries over the cycle, shape (N,) [N·m], the
allowed bearing pressure of the weaker of hub and shaft [Pa] (or the hub material's yield strength and a safety
factor), the hub's length [m] and the key's form. Output: :func:`size_key` gives a :class:`KeyResult`: the
key's section b x h and keyway depths from DIN 6885-1's table by the shaft diameter, the standard length, the
bearing pressure over the cycle at that length, shape (N,) [Pa], and its check.

Method: the key's cross-section comes from the shaft diameter alone (DIN 6885-1); its length from the mean
bearing pressure on the hub's flank (Roloff/Matek, *Maschinenelemente*, ch. 12, parallel keys):
p = 2 T / (d (h - t1) l_tr n phi) <= p_allow, with h - t1 the key's height standing in the hub, l_tr the bearing
length (l - b for form A's round ends, l for form B's square ones), n keys and phi = 1 for one key, 0.75 for two.
The key's shear is reported beside it, tau = 2 T / (d b l_tr); DIN 6885's sections are proportioned so that the
pressure governs. The pressure check is the peak over the cycle of |T|.

Where it stops: no load-distribution or load-peak factors of DIN 6892 method B/C (method C's mean pressure only),
no fatigue of the keyseat in the shaft (that is the shaft's notch, in :mod:`.shafts`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from ..errors import Infeasible, InvalidInput
from ..model import FloatArray
from .checks import PartCheck

KeyForm = Literal["A", "B"]

# DIN 6885-1 (high form): shaft diameter over..up to [mm] -> b x h, shaft keyway t1, hub keyway t2 [mm].
_DIN_6885_1: tuple[tuple[float, float, float, float, float, float], ...] = (
    (6, 8, 2, 2, 1.2, 1.0), (8, 10, 3, 3, 1.8, 1.4), (10, 12, 4, 4, 2.5, 1.8), (12, 17, 5, 5, 3.0, 2.3),
    (17, 22, 6, 6, 3.5, 2.8), (22, 30, 8, 7, 4.0, 3.3), (30, 38, 10, 8, 5.0, 3.3), (38, 44, 12, 8, 5.0, 3.3),
    (44, 50, 14, 9, 5.5, 3.8), (50, 58, 16, 10, 6.0, 4.3), (58, 65, 18, 11, 7.0, 4.4), (65, 75, 20, 12, 7.5, 4.9),
    (75, 85, 22, 14, 9.0, 5.4), (85, 95, 25, 14, 9.0, 5.4), (95, 110, 28, 16, 10.0, 6.4),
    (110, 130, 32, 18, 11.0, 7.4), (130, 150, 36, 20, 12.0, 8.4), (150, 170, 40, 22, 13.0, 9.4),
    (170, 200, 45, 25, 15.0, 10.4), (200, 230, 50, 28, 17.0, 11.4),
)
#: DIN 6885-1 standard key lengths [m].
STANDARD_KEY_LENGTHS = tuple(x / 1000.0 for x in (
    6, 8, 10, 12, 14, 16, 18, 20, 22, 25, 28, 32, 36, 40, 45, 50, 56, 63, 70, 80, 90, 100, 110, 125, 140, 160,
    180, 200, 220, 250, 280, 315, 355, 400))


@dataclass(frozen=True, slots=True)
class KeySection:
    """DIN 6885-1 key for a shaft diameter: width ``b``, height ``h``, shaft keyway depth ``t1``, hub keyway depth
    ``t2`` [m]."""

    b: float
    h: float
    t1: float
    t2: float


def din6885_section(shaft_diameter: float, where: str = "key") -> KeySection:
    """The DIN 6885-1 key section for a shaft of ``shaft_diameter`` [m] (over 6 up to 230 mm)."""
    d = shaft_diameter * 1e3
    for lo, hi, b, h, t1, t2 in _DIN_6885_1:
        if lo < d <= hi + 1e-9:
            return KeySection(b / 1e3, h / 1e3, t1 / 1e3, t2 / 1e3)
    raise InvalidInput(f"{where}: DIN 6885-1 covers shafts over 6 up to 230 mm, got {d:g} mm",
                       field=f"{where}.shaft_diameter")


@dataclass(frozen=True, slots=True)
class KeyResult:
    """A hub's key: ``section`` (DIN 6885-1), ``form``, ``count`` keys, ``length`` the standard length [m],
    ``bearing_length`` l_tr [m], ``length_required`` the least bearing length the pressure allows [m];
    ``pressure`` and ``shear`` over the cycle, shape (N,) [Pa]; ``checks`` the peak pressure against its limit and
    the key fitting in the hub."""

    hub: str
    shaft_diameter: float
    section: KeySection
    form: KeyForm
    count: int
    length: float
    bearing_length: float
    length_required: float
    pressure: FloatArray
    shear: FloatArray
    checks: tuple[PartCheck, ...]


def key_pressure(torque: ArrayLike, shaft_diameter: float, hub_height: float, bearing_length: float,
                 count: int = 1) -> FloatArray:
    """Mean bearing pressure on the hub's flank, p = 2 |T| / (d (h - t1) l_tr n phi) [Pa], shape of ``torque``;
    ``hub_height`` the key's height standing in the hub h - t1 [m]."""
    phi = 1.0 if count == 1 else 0.75
    out: FloatArray = 2.0 * np.abs(np.asarray(torque, dtype=float)) / (
        shaft_diameter * hub_height * bearing_length * count * phi)
    return out


def key_shear(torque: ArrayLike, shaft_diameter: float, width: float, bearing_length: float,
              count: int = 1) -> FloatArray:
    """Mean shear stress in the key, tau = 2 |T| / (d b l_tr n phi) [Pa], shape of ``torque``."""
    phi = 1.0 if count == 1 else 0.75
    out: FloatArray = 2.0 * np.abs(np.asarray(torque, dtype=float)) / (
        shaft_diameter * width * bearing_length * count * phi)
    return out


def size_key(
    hub: str,
    shaft_diameter: float,
    torque: ArrayLike,
    allowed_pressure: float,
    *,
    hub_length: float,
    form: KeyForm = "A",
    count: int = 1,
    application_factor: float = 1.0,
) -> KeyResult:
    """Key the hub ``hub`` to a shaft of ``shaft_diameter`` [m] for ``torque`` (N,) [N·m] times K_A.

    ``allowed_pressure`` p on the weaker of hub, key and shaft [Pa] (the weaker part's yield strength over a
    safety factor; Shigley's crushing check takes S_y/n); ``hub_length`` [m] bounds the key;
    ``form`` A (round ends) or B (square); ``count`` 1 or 2 keys (two at 180 degrees carry 1.5 times one).
    :class:`Infeasible` (constraint ``key_pressure``) names the hub when no standard key within the hub carries
    the torque.
    """
    if not (math.isfinite(shaft_diameter) and shaft_diameter > 0.0):
        raise InvalidInput(f"{hub}: the shaft diameter must be positive, got {shaft_diameter!r}",
                           field=f"{hub}.shaft_diameter")
    sec = din6885_section(shaft_diameter, hub)
    t = np.asarray(torque, dtype=float)
    if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)):
        raise InvalidInput(f"{hub}: the torque must be finite, shape (N,), got {t.shape}", field=f"{hub}.torque")
    for name, v in (("allowed_pressure", allowed_pressure), ("hub_length", hub_length),
                    ("application_factor", application_factor)):
        if not (math.isfinite(v) and v > 0.0):
            raise InvalidInput(f"{hub}: {name} must be positive (the hub material's limit), got {v!r}",
                               field=f"{hub}.{name}")
    if count not in (1, 2) or form not in ("A", "B"):
        raise InvalidInput(f"{hub}: one or two keys of form A or B, got {count} of form {form!r}",
                           field=f"{hub}.key")
    design = application_factor * t
    peak = float(np.abs(design).max())
    hub_height = sec.h - sec.t1
    need = float(key_pressure(np.array([peak]), shaft_diameter, hub_height, 1.0, count)[0]) / allowed_pressure
    rounding = sec.b if form == "A" else 0.0
    length = next((x for x in STANDARD_KEY_LENGTHS if x - rounding >= need * (1.0 - 1e-12) and x > rounding), None)
    if length is None or length > hub_length * (1.0 + 1e-12):
        raise Infeasible(f"{hub}: a DIN 6885 key {sec.b * 1e3:g} x {sec.h * 1e3:g} needs {(need + rounding) * 1e3:.0f}"
                         f" mm of length for the bearing pressure, the hub is {hub_length * 1e3:.0f} mm long; "
                         "use two keys, a longer hub or a press fit", constraint="key_pressure", hub=hub,
                         length_required_m=need + rounding)
    l_tr = length - rounding
    p = key_pressure(design, shaft_diameter, hub_height, l_tr, count)
    shear = key_shear(design, shaft_diameter, sec.b, l_tr, count)
    checks = (
        PartCheck(hub, "key_pressure", float(p.max()), allowed_pressure, "Pa",
                  f"bearing pressure of the {sec.b * 1e3:g} x {sec.h * 1e3:g} x {length * 1e3:g} key on the "
                  "hub's flank at the cycle's peak torque"),
        PartCheck(hub, "key_length", length, hub_length, "m", "the key's length within the hub"),
    )
    return KeyResult(hub, shaft_diameter, sec, form, count, length, l_tr, need, p, shear, checks)
