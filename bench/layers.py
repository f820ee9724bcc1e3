"""How often the call path of ``synth.balance_static`` on a four-bar climbs back up the engine's layers.

The engine's layers, lowest first: the model (``model``, ``mechanism``, ``topology``, ``errors``), the kinematics,
the kinetostatics, and the capabilities on top (dynamics, analysis, balancing, ...). The profiler follows which
engine function runs; a *climb back* is a lower-layer function handing control back to a higher-layer caller
that asked it for something. Reads of a record's field (property getters, generated ``__init__``/``__hash__``)
and the plain-array helpers (``perp``, ``cross``, ``dot``, ``magnitude``, ``unit``, ``xy``, ``complex_of`` and their complex
forms) are not asks and are left out.

Two figures are printed: every climb back on the whole path, and the ones the per-link data cause, where the
model or the motion hand data back to their consumers (the kinetostatics, the reduced model and the analysis).
Data handed down once per motion keeps the second small and independent of the number of links; asking the model
and the motion link by link makes it grow with every link and every consumer.
"""

from __future__ import annotations

import collections
import importlib
import inspect
import pkgutil
import sys
from collections.abc import Callable
from types import CodeType, FrameType

import synth

LAYERS = {"model": 0, "mechanism": 0, "topology": 0, "errors": 0, "kinematics": 1, "kinetostatics": 2}
CAPABILITIES = 3
DATA = (0, 1)
CONSUMERS = ("synth.kinetostatics", "synth.dynamics", "synth.analysis")
# Pure functions of plain arrays: no layer's data passes through them.
HELPERS = {"perp", "cross", "dot", "unit", "xy", "complex_of", "cross_c", "dot_c", "magnitude"}


def layer_of(module: str) -> int | None:
    """Layer of an engine module (None outside the engine)."""
    parts = module.split(".")
    if parts[0] != "synth" or len(parts) < 2:
        return None
    return LAYERS.get(parts[1], CAPABILITIES)


def _accessors() -> set[CodeType]:
    """Code objects of every property getter in the engine's classes."""
    codes: set[CodeType] = set()
    names = [m.name for m in pkgutil.walk_packages(synth.__path__, "synth.")]
    for name in ["synth", *names]:
        try:
            module = importlib.import_module(name)
        except ImportError:
            continue
        for _, cls in inspect.getmembers(module, inspect.isclass):
            for attr in vars(cls).values():
                if isinstance(attr, property) and attr.fget is not None and hasattr(attr.fget, "__code__"):
                    codes.add(attr.fget.__code__)
    return codes


def climbs(fn: Callable[[], object]) -> collections.Counter[tuple[str, str]]:
    """Run ``fn()`` and count the climbs back up per (lower-layer function, higher-layer caller)."""
    accessors = _accessors()
    stack: list[tuple[int, str] | None] = []
    where: collections.Counter[tuple[str, str]] = collections.Counter()

    def profile(frame: FrameType, event: str, _arg: object) -> None:
        if event not in ("call", "return"):
            return
        module = frame.f_globals.get("__name__", "")
        layer = layer_of(module)
        code = frame.f_code
        if layer is None or code.co_name in HELPERS or code.co_name.startswith(("<", "__")) or code in accessors:
            return
        if event == "call":
            stack.append((layer, f"{module}.{code.co_qualname}"))
        elif stack:
            entry = stack.pop()
            if entry is not None and stack and (caller := stack[-1]) is not None and caller[0] > entry[0]:
                where[(entry[1], caller[1])] += 1

    sys.setprofile(profile)
    try:
        fn()
    finally:
        sys.setprofile(None)
    return where


def fourbar() -> synth.Linkage:
    """The manual's four-bar example with mass on every link."""
    mech = synth.FourBar(0.3, 0.1, 0.35, 0.25)
    links = {"crank": synth.MassProps(1.0, (0.05, 0.0), 0.001), "coupler": synth.MassProps(2.0, (0.175, 0.0), 0.02),
             "rocker": synth.MassProps(1.5, (0.125, 0.0), 0.008)}
    return synth.Linkage(mech, links)


def main() -> None:
    linkage = fourbar()
    synth.balance_static(linkage, 31.4, samples=90)  # imports and caches settle outside the count
    where = climbs(lambda: synth.balance_static(linkage, 31.4, samples=90))
    data = {edge: n for edge, n in where.items()
            if layer_of(edge[0].rsplit(".", 2)[0]) in DATA and edge[1].startswith(CONSUMERS)}
    print(f"balance_static on a four-bar: {sum(where.values())} climbs back up a layer "
          f"({len(where)} distinct call sites)")
    print(f"  of which the model or the motion hand data back to the kinetostatics, the reduced model or the "
          f"analysis: {sum(data.values())}")
    for (callee, caller), times in where.most_common():
        print(f"  {times:3d}  {callee} -> {caller}{'   (data)' if (callee, caller) in data else ''}")


if __name__ == "__main__":
    main()
