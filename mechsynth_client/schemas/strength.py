"""Schemas of POST /v1/strength: a linkage's bars sized for strength, fed back into the analysis to a fixed point."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field, model_validator
from pydantic.config import JsonDict

from .common import FOURBAR_EXAMPLE, SIX_BAR_PRESS_EXAMPLE, LinkageRequest, StrictModel, SummaryOut

MaterialName = Literal["S235JR", "S355J2", "C45E+N", "C45E+QT", "42CrMo4+QT", "EN AW-6082-T6"]
_LIMITS = ("yield_strength_MPa", "ultimate_strength_MPa", "fatigue_limit_MPa", "elastic_modulus_GPa", "density_kg_m3")


class MaterialIn(StrictModel):
    """A shipped grade by ``grade``, or your material with every one of its limits (never one guessed)."""

    grade: MaterialName | None = Field(None, description="A shipped grade (indicative minimum figures of its "
                                       "product standard; GET /docs strength page).")
    name: str = Field("user", min_length=1, max_length=80, description="Your material's name.")
    yield_strength_MPa: float | None = Field(None, gt=0, le=1e4, description="Yield strength Re or Rp0.2 [MPa].")
    ultimate_strength_MPa: float | None = Field(None, gt=0, le=1e4, description="Ultimate strength Rm [MPa].")
    fatigue_limit_MPa: float | None = Field(None, gt=0, le=1e4, description="Fatigue limit of the polished "
                                            "rotating-beam specimen S'e [MPa].")
    elastic_modulus_GPa: float | None = Field(None, gt=0, le=1e4, description="Young's modulus [GPa].")
    density_kg_m3: float | None = Field(None, gt=0, le=1e5, description="Density [kg/m³].")

    @model_validator(mode="after")
    def _grade_or_every_limit(self) -> MaterialIn:
        given = [name for name in _LIMITS if getattr(self, name) is not None]
        if self.grade is not None and given:
            raise ValueError(f"give a grade or your material's limits, not both (got grade and {given})")
        if self.grade is None and len(given) != len(_LIMITS):
            missing = [name for name in _LIMITS if getattr(self, name) is None]
            raise ValueError(f"a material of your own carries every limit: missing {missing}")
        return self


class SectionIn(StrictModel):
    """The shape of a link's section; the least size of its series that meets every check is chosen, or the
    given ``size_mm`` (or IPE ``profile``) is checked as it is."""

    kind: Literal["round", "tube", "rectangle", "ipe"] = Field("rectangle", description="Round bar, round tube, "
                                                              "flat bar (height in the plane of motion) or IPE.")
    ratio: float = Field(3.0, gt=0, le=20, description="Flat bar: height over width; tube: wall over outer "
                         "diameter (below 0.5).")
    min_size_mm: float = Field(3.0, gt=0, le=1000, description="Smallest diameter or width of the series [mm].")
    max_size_mm: float = Field(250.0, gt=0, le=1000, description="Largest diameter or width of the series [mm].")
    size_mm: float | None = Field(None, gt=0, le=1000, description="A given diameter or width [mm]: checked, "
                                  "not sized.")
    profile: Literal["IPE 80", "IPE 100", "IPE 120", "IPE 140", "IPE 160"] | None = Field(
        None, description="A given IPE section (EN 10365): checked, not sized.")


class LinkStrengthIn(StrictModel):
    """One link's material and section, where they differ from the request's defaults."""

    link: str = Field(min_length=1, max_length=40, description="The link, by name.", examples=["coupler"])
    material: MaterialIn | None = Field(None, description="This link's material; default the request's.")
    section: SectionIn | None = Field(None, description="This link's section; default the request's.")


class StrengthLimitsIn(StrictModel):
    """Required factors of safety and the fatigue conditions of every link."""

    static_safety: float = Field(1.5, ge=1, le=100, description="Against yield (von Mises) [-].")
    fatigue_safety: float = Field(1.5, ge=1, le=100, description="On the modified Goodman line [-].")
    buckling_safety: float = Field(2.5, ge=1, le=100, description="On the Euler/Johnson critical load [-].")
    surface: Literal["ground", "machined", "hot_rolled", "forged"] = Field(
        "machined", description="Surface finish for Marin's factor ka (Shigley Table 6-2).")
    reliability: float = Field(0.9, ge=0.5, lt=1, description="Reliability for Marin's factor ke, one of "
                               "Shigley Table 6-5's: 0.5, 0.9, 0.95, 0.99, 0.999 or 0.9999.")
    notch_factor: float = Field(1.0, ge=1, le=10, description="Fatigue stress-concentration factor Kf on every "
                                "fatigue stress [-].")
    in_plane_ends: Literal["pinned-pinned", "fixed-fixed", "fixed-pinned", "fixed-free"] = Field(
        "pinned-pinned", description="Column ends in the plane of motion (revolute joints let them turn).")
    out_of_plane_ends: Literal["pinned-pinned", "fixed-fixed", "fixed-pinned", "fixed-free"] = Field(
        "fixed-fixed", description="Column ends out of the plane (pins in long bores hold them square).")


class StrengthFields(StrictModel):
    """What the links are made of and what they must bear: shared by POST /v1/strength and a machine's
    ``strength`` block."""

    material: MaterialIn = Field(default_factory=lambda: MaterialIn(grade="S355J2"),
                                 description="Every link's material unless the link says otherwise.")
    section: SectionIn = Field(default_factory=SectionIn, description="Every link's section shape and series.")
    links: list[LinkStrengthIn] | None = Field(
        None, max_length=40, description="Links with their own material or section; every bar of the linkage is "
        "sized (a block, such as a slider, is not a bar), these as they say, the others by the defaults.")
    limits: StrengthLimitsIn = Field(default_factory=StrengthLimitsIn, description="Required factors of safety.")


_FOURBAR_STRENGTH: JsonDict = {"mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "samples": 180,
                               "gravity": {"g_m_s2": 9.81},
                               "loads": [{"type": "window", "torque_Nm": 60, "start_deg": 0, "end_deg": 180}],
                               "material": {"grade": "S355J2"}, "section": {"kind": "rectangle", "ratio": 3}}
_PRESS_STRENGTH: JsonDict = {"mechanism": SIX_BAR_PRESS_EXAMPLE, "speed_rpm": 60, "samples": 180,
                             "gravity": {"g_m_s2": 9.81},
                             "loads": [{"type": "window", "force_N": 4000, "start_deg": 0, "end_deg": 180}],
                             "section": {"kind": "rectangle", "ratio": 3, "min_size_mm": 6},
                             "links": [{"link": "crank", "section": {"kind": "round", "min_size_mm": 10}},
                                       {"link": "rod", "material": {"grade": "C45E+QT"},
                                        "section": {"kind": "tube", "ratio": 0.15}}]}


class StrengthSizingIn(LinkageRequest, StrengthFields):
    """A linkage at its speed with its loads, and how its bars are made."""

    model_config = {**LinkageRequest.model_config,
                    "json_schema_extra": {"examples": [_FOURBAR_STRENGTH, _PRESS_STRENGTH]}}


class LinkCheckOut(BaseModel):
    """One check of a link: its least factor of safety over the cycle and along the link, against the required."""

    name: Literal["static", "fatigue", "buckling_in_plane", "buckling_out_of_plane"] = Field(
        description="static: von Mises vs yield; fatigue: modified Goodman with Marin factors; buckling: "
        "Euler/Johnson in and out of the plane of motion.")
    safety: float | None = Field(description="Least factor of safety [-]; null where the link never sees the "
                                 "load (a bar never in compression cannot buckle).")
    required: float = Field(description="The required factor of safety [-].")
    passed: bool = Field(description="safety >= required.")
    crank_angle_deg: float = Field(description="Crank angle where the factor is least [deg].")
    x_m: float = Field(description="Section where it is least, along the link from its first joint [m].")
    method: str = Field(description="The model and its source.")


class LinkSectionOut(BaseModel):
    """A link's section and mass as built, with every check."""

    link: str = Field(description="The link, by name.")
    material: str = Field(description="The material's name.")
    section: str = Field(description="The section, e.g. `flat 24x8 mm` (height x width) or `IPE 80`.")
    kind: str = Field(description="round, tube, rectangle or ipe.")
    dimensions_mm: dict[str, float] = Field(description="The section's dimensions [mm].")
    area_mm2: float = Field(description="Cross-section area [mm²].")
    second_moment_mm4: float = Field(description="About the in-plane bending axis [mm⁴].")
    modulus_mm3: float = Field(description="Elastic section modulus for in-plane bending [mm³].")
    length_m: float = Field(description="The bar between its outer load points [m].")
    start_m: float = Field(description="Where the bar starts along the link's x-axis [m] (behind the first "
                           "joint for a counterweight arm).")
    mass_kg: float = Field(description="rho A L [kg].")
    com_m: list[float] = Field(description="Centre of mass in the link frame [m].")
    inertia_kgm2: float = Field(description="About the centre of mass, m (L² + h²)/12 [kg·m²].")
    sized: bool = Field(description="False when the section was given and only checked.")
    passed: bool = Field(description="Every check met.")
    checks: list[LinkCheckOut] = Field(description="Static, fatigue and buckling in and out of the plane.")
    points_m: dict[str, float] = Field(description="Each load point's place along the link [m].")
    max_axial_N: float = Field(description="Largest |axial force| over the cycle and along the link [N].")
    max_moment_Nm: float = Field(description="Largest |bending moment| [N·m].")


class SizingIterationOut(BaseModel):
    """One pass of the fixed point: the masses its analysis used and the sections it chose."""

    masses_kg: dict[str, float] = Field(description="Per link, the mass its analysis used [kg].")
    sections: dict[str, str] = Field(description="Per link, the section this pass chose.")
    largest_change_kg: float = Field(description="Largest difference between a chosen section's mass and the "
                                     "mass the analysis used [kg]; zero at the fixed point.")


class StrengthSizingOut(BaseModel):
    """The sized links, the fixed point's passes and the linkage as built."""

    links: list[LinkSectionOut] = Field(description="Every bar of the linkage as built.")
    mass_kg: float = Field(description="All sized bars [kg].")
    passed: bool = Field(description="Every check of every link met.")
    iterations: list[SizingIterationOut] = Field(description="The passes, first from the masses given.")
    analyses: int = Field(description="Analyses run (one per pass).")
    mass_residual_kg: float = Field(description="Largest |mass in the final analysis - its section's mass| [kg]: "
                                    "the fixed point's check.")
    closure_N: float = Field(description="Largest force any bar's beam equilibrium leaves over [N]: zero to "
                             "round-off when the beams carry exactly the kinetostatics' loads.")
    summary: SummaryOut = Field(description="The analysis of the linkage as built.")
    notes: list[str] = Field(default_factory=list, description="Where the model is stretched (e.g. a plate taken "
                             "as a bar with brackets).")

