"""Links sized for the forces their own masses make: a fixed point of sizing and analysis.

A link's section sets its mass, centre and inertia; these set the inertia loads and the joint reactions; these
size the section. Starting from the masses the linkage is given with, every bar is sized from the analysis, its
sized mass properties go back into the analysis, and this repeats until no section changes: then the masses the
last analysis used are the sized ones, and that analysis is the machine as built. The sizes come from a discrete
series, so the iteration either stops on a repeated choice or swings between two; a swing is settled by taking
each link's larger section of the two, analysed and checked once more.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from ..analysis import Analysis, analyse
from ..counter_rotors import CounterRotor
from ..errors import InvalidInput, SolverFailed
from ..kinematics import MAX_SAMPLES
from ..model import Linkage, MassProps
from .links import LinkSizing, LinkSpec, StrengthLimits, beam_forces, beam_links, size_link

#: Iterations of the fixed point before it is given up (each is one analysis).
MAX_ITERATIONS = 30


@dataclass(frozen=True, slots=True)
class SizingIteration:
    """One pass: the masses the analysis used [kg] and the sections it chose, per link."""

    masses: dict[str, float]
    sections: dict[str, str]
    largest_change: float


@dataclass(frozen=True, slots=True)
class LinkStrength:
    """The sized links, the passes that reached them and the analysis of the linkage as built.

    ``linkage`` carries the sized links' mass properties; ``analysis`` is its analysis (the one every check is
    made on); ``residual`` the largest difference between a link's mass in that analysis and its section's mass
    [kg] (zero at the fixed point); ``closure`` the largest force [N] left over by any link's beam equilibrium.
    """

    links: dict[str, LinkSizing]
    iterations: tuple[SizingIteration, ...]
    linkage: Linkage
    analysis: Analysis
    residual: float
    closure: float
    warnings: tuple[str, ...] = ()

    @property
    def mass(self) -> float:
        """Mass of all the sized bars [kg]."""
        return sum(s.mass for s in self.links.values())

    @property
    def passed(self) -> bool:
        """Every check of every link met."""
        return all(s.passed for s in self.links.values())


def _with_links(linkage: Linkage, props: Mapping[str, MassProps]) -> Linkage:
    merged = dict(linkage.links)
    merged.update(props)
    return dataclasses.replace(linkage, links=merged)


def size_links(linkage: Linkage, speed: float, specs: Mapping[str, LinkSpec], limits: StrengthLimits, *,
               samples: int = 360, crank_acceleration: float = 0.0, counter_rotors: Sequence[CounterRotor] = (),
               max_samples: int = MAX_SAMPLES, max_iterations: int = MAX_ITERATIONS) -> LinkStrength:
    """Size every link of ``specs`` (each must be a bar) at crank speed ``speed`` [rad/s] to the fixed point.

    Raises InvalidInput for a link that is not a bar, Infeasible (naming the link, check and crank angle) when a
    family cannot carry its load, SolverFailed when the passes do not settle within ``max_iterations``.
    """
    limits.validate()
    for name, spec in specs.items():
        spec.material.validate(f"links.{name}.material")
    def again(props: Mapping[str, MassProps]) -> Analysis:
        return analyse(_with_links(linkage, props), speed, samples=samples, crank_acceleration=crank_acceleration,
                       counter_rotors=counter_rotors, max_samples=max_samples, base_motion=base)

    current = analyse(linkage, speed, samples=samples, crank_acceleration=crank_acceleration,
                      counter_rotors=counter_rotors, max_samples=max_samples)
    bars = set(beam_links(current))
    if missing := [name for name in specs if name not in bars]:
        raise InvalidInput(f"links {missing} are not bars (a block, or an unknown link); the bars are "
                           f"{sorted(bars)}", field="links")
    base = current.mechanism_motion
    history: list[SizingIteration] = []
    chosen: list[dict[str, str]] = []
    sized: dict[str, LinkSizing] = {}
    for _ in range(max_iterations):
        sized = {name: size_link(beam_forces(current, name), spec, limits) for name, spec in specs.items()}
        used = {name: current.linkage.links.get(name, MassProps()).mass for name in specs}
        labels = {name: s.section.label for name, s in sized.items()}
        change = max((abs(sized[n].mass - used[n]) for n in specs), default=0.0)
        history.append(SizingIteration(used, labels, change))
        if chosen and labels == chosen[-1]:
            break
        if len(chosen) >= 2 and labels == chosen[-2]:
            # a swing between two choices: each link takes the larger of its two sections
            prev = {n: s for n, s in zip(specs, _resize_previous(current, specs, limits, chosen[-1]))}
            sized = {n: (prev[n] if prev[n].section.area > sized[n].section.area else sized[n]) for n in specs}
            chosen.append({n: s.section.label for n, s in sized.items()})
            current = again({n: s.mass_props for n, s in sized.items()})
            sized = {name: _check_as_built(current, name, specs[name], sized[name], limits) for name in specs}
            history.append(SizingIteration({n: current.linkage.links[n].mass for n in specs},
                                           {n: s.section.label for n, s in sized.items()}, 0.0))
            break
        chosen.append(labels)
        current = again({n: s.mass_props for n, s in sized.items()})
    else:
        raise SolverFailed("not_converged", f"the links' sections still changed after {max_iterations} analyses")
    residual = max((abs(current.linkage.links[n].mass - s.mass) for n, s in sized.items()), default=0.0)
    closure = max((s.forces.closure[0] for s in sized.values()), default=0.0)
    warnings = tuple(
        f"off_axis_joints: link {n!r} has a load point {s.forces.off_axis * 1e3:.0f} mm off its axis; it is taken "
        "as a bar with rigid brackets, a plate's own stresses are not modelled"
        for n, s in sized.items() if s.forces.off_axis > 0.05 * s.forces.length)
    return LinkStrength(sized, tuple(history), current.linkage, current, residual, closure, warnings)


def _resize_previous(analysis: Analysis, specs: Mapping[str, LinkSpec], limits: StrengthLimits,
                     labels: Mapping[str, str]) -> list[LinkSizing]:
    """The previous pass's sections checked on ``analysis`` (to compare areas in a swing)."""
    out = []
    for name, spec in specs.items():
        section = next(s for s in ((spec.section,) if spec.section else spec.family.candidates())
                       if s.label == labels[name])
        out.append(size_link(beam_forces(analysis, name), dataclasses.replace(spec, section=section), limits))
    return out


def _check_as_built(analysis: Analysis, name: str, spec: LinkSpec, sizing: LinkSizing, limits: StrengthLimits
                    ) -> LinkSizing:
    """``sizing``'s section checked on the analysis made with it; it stays sized as it was."""
    checked = size_link(beam_forces(analysis, name), dataclasses.replace(spec, section=sizing.section), limits)
    return dataclasses.replace(checked, sized=spec.section is None)


def mass_ratio(before: float, after: float) -> float:
    """after / before, or nan for a massless start."""
    return after / before if before > 0 else math.nan
