"""Builders shared by the tests: the lecture-10 shaper from its seed inputs, random linkages, spectral derivatives."""

from __future__ import annotations

from typing import Any

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

import synth


def shaper_from_case(inputs: dict[str, Any], *, with_load: bool = True, gravity: bool = True,
                     masses: tuple[str, ...] = ("crank", "rocker", "ram")) -> synth.Linkage:
    """The lecture-10 shaper [000:219-353] from a seed case's inputs.

    The ram guide height is not among the kinematic cases' inputs; it only moves the ram's line of action and
    comes from the kinetostatic case (h = 0.7 m above O1, cutting force b = 0.1 m below the ram's centre of mass).
    """
    mech = synth.SlottedLever(inputs["l_OA_m"], inputs["l_O1O_m"], inputs["l_O1B_m"], inputs.get("h_m", 0.7))
    props = {
        "crank": synth.MassProps(inputs.get("m1_kg", 0.0)),
        "rocker": synth.MassProps(inputs.get("m3_kg", 0.0), (inputs["l_O1S3_m"], 0.0), inputs.get("J3_kgm2", 0.0)),
        "ram": synth.MassProps(inputs.get("m5_kg", 0.0)),
    }
    loads = ()
    if with_load:
        # The cutting stroke window covers the lecture's position; the force opposes the ram's motion.
        loads = (synth.ProcessLoad("window", inputs["P_cut_N"], -1.0, 1.0, point=(0.0, -inputs["b_m"])),)
    return synth.Linkage(
        mech,
        links={k: v for k, v in props.items() if k in masses},
        gravity=synth.Gravity(inputs.get("g_m_s2", 9.81)) if gravity else None,
        loads=loads,
    )


def lecture_angle() -> np.ndarray:
    """The lecture's position: crank OA perpendicular to O1O with A at its lateral extreme (crank angle 0)."""
    return np.array([0.0])


def spectral_derivative(values: np.ndarray, order: int = 1) -> np.ndarray:
    """d^k/dphi^k of samples of a smooth 2*pi-periodic function on a uniform grid (axis 0)."""
    n = values.shape[0]
    k = np.fft.fftfreq(n, d=1.0 / n)
    if n % 2 == 0:
        k[n // 2] = 0.0
    factor = (1j * k) ** order
    shape = (n,) + (1,) * (values.ndim - 1)
    return np.real(np.fft.ifft(np.fft.fft(values, axis=0) * factor.reshape(shape), axis=0))


lengths = st.floats(0.2, 1.0)
masses = st.floats(0.1, 5.0)
offsets = st.floats(-0.3, 0.3)


@st.composite
def mass_props(draw: st.DrawFn, length: float) -> synth.MassProps:
    """Random mass properties of a link of ``length`` [m], centre of mass anywhere near the link."""
    m = draw(masses)
    x = draw(st.floats(-0.5, 1.5)) * length
    y = draw(st.floats(-0.3, 0.3)) * length
    j = m * length**2 * draw(st.floats(0.01, 0.2))
    return synth.MassProps(m, (x, y), j)


@st.composite
def crank_fourbars(draw: st.DrawFn) -> synth.Linkage:
    """Random four-bars whose crank turns fully (Grashof crank-rocker or double-crank) with a margin."""
    ground, coupler, rocker = draw(lengths), draw(lengths), draw(lengths)
    crank = draw(st.floats(0.05, 0.6)) * min(ground, coupler, rocker)
    mech_lengths = sorted([ground, crank, coupler, rocker])
    assume(mech_lengths[0] + mech_lengths[3] < 0.9 * (mech_lengths[1] + mech_lengths[2]))
    fb = synth.FourBar(ground, crank, coupler, rocker, draw(st.sampled_from([1, -1])))
    assume(fb.grashof in ("crank-rocker", "double-crank"))
    links = {
        "crank": draw(mass_props(crank)),
        "coupler": draw(mass_props(coupler)),
        "rocker": draw(mass_props(rocker)),
    }
    return synth.Linkage(fb, links)


@st.composite
def slider_cranks(draw: st.DrawFn) -> synth.Linkage:
    """Random offset slider-cranks that assemble over the whole revolution."""
    crank = draw(st.floats(0.05, 0.3))
    rod = crank * draw(st.floats(2.0, 6.0))
    offset = draw(st.floats(-0.5, 0.5)) * (rod - crank)
    sc = synth.SliderCrank(crank, rod, offset, draw(st.sampled_from([1, -1])))
    links = {"crank": draw(mass_props(crank)), "rod": draw(mass_props(rod)), "slider": draw(mass_props(0.1))}
    return synth.Linkage(sc, links)
