"""The parts that carry the cycle's forces: links as beams, pins, bearings, shafts and keys.

Links: :mod:`.materials` (limits, stiffness and density with their sources), :mod:`.sections` (round, tube, rectangle,
IPE), :mod:`.links` (each bar's internal forces over the cycle, its static, fatigue and buckling checks and its
least section), :mod:`.sizing` (the sized links' masses fed back into the analysis to a fixed point),
:mod:`.fatigue` (Marin and Goodman) and :mod:`.columns` (Euler and Johnson).
"""

from .links import BeamForces, LinkCheck, LinkSizing, LinkSpec, StrengthLimits, beam_forces, beam_links, size_link
from .materials import MATERIALS, Material, material
from .sections import Section, SectionFamily, ipe, rectangle, round_bar, tube
from .sizing import LinkStrength, SizingIteration, size_links

__all__ = [
    "BeamForces", "LinkCheck", "LinkSizing", "LinkSpec", "LinkStrength", "MATERIALS", "Material", "Section",
    "SectionFamily", "SizingIteration", "StrengthLimits", "beam_forces", "beam_links", "ipe", "material",
    "rectangle", "round_bar", "size_link", "size_links", "tube",
]
