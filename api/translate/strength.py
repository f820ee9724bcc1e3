"""Translation between the wire models of the parts' strength and the engine."""

from __future__ import annotations

import math
from typing import Any

import synth
from synth import strength
from synth.strength.links import CHECKS
from synth.strength.sections import MM

from api.translate.linkage import linkage_from, summary_out
from mechsynth_client.schemas.strength import (
    LinkCheckOut,
    LinkSectionOut,
    MaterialIn,
    SectionIn,
    SizingIterationOut,
    StrengthFields,
    StrengthLimitsIn,
    StrengthSizingIn,
    StrengthSizingOut,
)

MPA, GPA = 1e6, 1e9


def material_from(m: MaterialIn, where: str) -> strength.Material:
    """Engine material: a shipped grade, or the user's with every limit (validated, named by ``where``)."""
    if m.grade is not None:
        return strength.material(m.grade, where)
    limits = (m.yield_strength_MPa, m.ultimate_strength_MPa, m.fatigue_limit_MPa, m.elastic_modulus_GPa,
              m.density_kg_m3)
    if any(v is None for v in limits):
        raise synth.InvalidInput(f"{where}: a material of your own carries every limit", field=where)
    re, rm, se, e, rho = (float(v) for v in limits if v is not None)
    return strength.Material(m.name, re * MPA, rm * MPA, se * MPA, e * GPA, rho).validate(where)


def spec_from(section: SectionIn, material: strength.Material, where: str) -> strength.LinkSpec:
    """Engine link spec: a family to size, or a given section to check."""
    family = strength.SectionFamily(section.kind, section.ratio, section.min_size_mm * MM, section.max_size_mm * MM)
    if section.max_size_mm < section.min_size_mm:
        raise synth.InvalidInput(f"{where}: max_size_mm is below min_size_mm", field=f"{where}.max_size_mm")
    given: strength.Section | None = None
    if section.kind == "ipe":
        if section.profile is not None:
            given = strength.ipe(section.profile)
    elif section.profile is not None:
        raise synth.InvalidInput(f"{where}: a profile is an IPE's", field=f"{where}.profile")
    elif section.size_mm is not None:
        size = section.size_mm * MM
        given = (strength.round_bar(size) if section.kind == "round"
                 else strength.tube(size, section.ratio * size) if section.kind == "tube"
                 else strength.rectangle(size, section.ratio * size))
    return strength.LinkSpec(material, family, given)


def limits_from(limits: StrengthLimitsIn) -> strength.StrengthLimits:
    """Engine limits."""
    return strength.StrengthLimits(limits.static_safety, limits.fatigue_safety, limits.buckling_safety,
                                   limits.surface, float(limits.reliability), limits.notch_factor,
                                   limits.in_plane_ends, limits.out_of_plane_ends).validate()


def specs_from(fields: StrengthFields, bars: tuple[str, ...], prefix: str = "") -> dict[str, strength.LinkSpec]:
    """Every bar's spec: the request's defaults, or a listed link's own material and section."""
    default_material = material_from(fields.material, f"{prefix}material")
    own: dict[str, tuple[int, Any]] = {}
    for i, entry in enumerate(fields.links or []):
        if entry.link not in bars:
            raise synth.InvalidInput(f"link {entry.link!r} is not a bar of this linkage; the bars are {list(bars)}",
                                     field=f"{prefix}links[{i}].link")
        if entry.link in own:
            raise synth.InvalidInput(f"link {entry.link!r} is listed twice", field=f"{prefix}links[{i}].link")
        own[entry.link] = (i, entry)
    out = {}
    for name in bars:
        material, section, where = default_material, fields.section, f"{prefix}section"
        if name in own:
            i, entry = own[name]
            if entry.material is not None:
                material = material_from(entry.material, f"{prefix}links[{i}].material")
            if entry.section is not None:
                section, where = entry.section, f"{prefix}links[{i}].section"
        out[name] = spec_from(section, material, where)
    return out


def sizing_call(body: StrengthSizingIn) -> tuple[Any, ...]:
    """The engine's arguments for POST /v1/strength: linkage, speed, specs, limits."""
    if body.crank_angle_deg is not None:
        raise synth.InvalidInput("the fatigue check needs the whole cycle: give samples, not crank angles",
                                 field="crank_angle_deg")
    linkage = linkage_from(body)
    bars = tuple(n for n in linkage.mechanism.topology.links if is_bar(linkage, n))
    return linkage, body.omega_rad_s, specs_from(body, bars), limits_from(body.limits)


def is_bar(linkage: synth.Linkage, link: str) -> bool:
    """A link with two or more joints (a block has one point)."""
    points = {j.point for j in linkage.mechanism.topology.joints if link in j.bodies}
    return len(points) >= 2


def _finite(value: float) -> float | None:
    return value if math.isfinite(value) else None


def link_out(s: strength.LinkSizing) -> LinkSectionOut:
    """Wire form of one sized link."""
    sec, f = s.section, s.forces
    return LinkSectionOut(
        link=s.link, material=s.material.name, section=sec.label, kind=sec.kind,
        dimensions_mm={k.removesuffix("_m") + "_mm": v / MM for k, v in sec.dimensions.items()},
        area_mm2=sec.area / MM**2, second_moment_mm4=sec.second_moment / MM**4, modulus_mm3=sec.modulus / MM**3,
        length_m=f.length, start_m=f.start, mass_kg=s.mass, com_m=list(s.mass_props.com),
        inertia_kgm2=s.mass_props.inertia, sized=s.sized, passed=s.passed,
        checks=[LinkCheckOut(name=c.name, safety=_finite(c.safety), required=c.required, passed=c.passed,  # type: ignore[arg-type]
                             crank_angle_deg=math.degrees(c.phi), x_m=c.x, method=c.method)
                for c in s.checks if c.name in CHECKS],
        points_m=f.points, max_axial_N=float(abs(f.axial).max()), max_moment_Nm=float(abs(f.moment).max()))


def sizing_out(r: strength.LinkStrength) -> StrengthSizingOut:
    """Wire form of the sized links."""
    return StrengthSizingOut(
        links=[link_out(s) for s in r.links.values()], mass_kg=r.mass, passed=r.passed,
        iterations=[SizingIterationOut(masses_kg=i.masses, sections=i.sections, largest_change_kg=i.largest_change)
                    for i in r.iterations],
        analyses=len(r.iterations), mass_residual_kg=r.residual, closure_N=r.closure,
        summary=summary_out(r.analysis.summary()), notes=list(r.warnings))


