"""The engine's layers: imports flow model -> kinematics -> kinetostatics -> capabilities, and the per-link data
reach the kinetostatics once per motion, as the same numbers the model and the motion give link by link."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
from hypothesis import given, settings

import synth
from helpers import crank_fourbars
from synth.kinetostatics import link_arrays

ENGINE = Path(synth.__file__).resolve().parent
# Lowest first; a module may import only from its own layer or the ones below.
LAYERS = {"errors": 0, "topology": 0, "mechanism": 0, "model": 0, "structure": 0, "kinematics": 1,
          "kinetostatics": 2, "counter_rotors": 3, "dynamics": 3, "analysis": 4}


def _layer(module: str) -> int | None:
    parts = module.split(".")
    return LAYERS.get(parts[1]) if parts[0] == "synth" and len(parts) > 1 else None


def _imports(path: Path, module: str) -> set[str]:
    """Engine modules imported by ``path`` (TYPE_CHECKING imports too: a circle in types is a circle)."""
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")
            if node.level:
                base = base[: len(base) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            out.add(name)
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
    return {m for m in out if m.startswith("synth")}


def test_no_import_climbs_a_layer() -> None:
    # Every import edge of the layered modules, checked against the layer order written above.
    upward = []
    for path in ENGINE.rglob("*.py"):
        module = "synth." + ".".join(path.relative_to(ENGINE).with_suffix("").parts).removesuffix(".__init__")
        here = _layer(module)
        if here is None:
            continue
        for target in _imports(path, module):
            there = _layer(target)
            if there is not None and there > here:
                upward.append(f"{module} -> {target}")
    assert upward == []


@settings(max_examples=15)
@given(crank_fourbars())
def test_link_arrays_match_the_model_and_the_motion(linkage: synth.Linkage) -> None:
    # Identity: the stacked arrays are the per-link mass properties and Motion.point_on, to rounding.
    mot = synth.motion(linkage.mechanism, synth.cycle_angles(36), 10.0, 3.0)
    arrays = link_arrays(mot, linkage)
    for i, link in enumerate(linkage.mechanism.topology.links):
        props = linkage.mass_props(link)
        state = mot.point_on(link, props.com)
        assert arrays.mass[i] == props.mass
        np.testing.assert_allclose(arrays.inertia[i], props.inertia, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(arrays.com_pos[i], state.pos, rtol=0, atol=1e-12)
        np.testing.assert_allclose(arrays.com_vel[i], state.vel, rtol=0, atol=1e-10)
        np.testing.assert_allclose(arrays.com_acc[i], state.acc, rtol=0, atol=1e-8)


def test_static_balance_asks_the_model_and_motion_a_handful_of_times() -> None:
    # Counted by the profiler in bench/layers.py: the model and the motion hand data back up to the
    # kinetostatics, the reduced model and the analysis once per motion (3 here), not once per link and consumer.
    from bench.layers import CONSUMERS, DATA, climbs, fourbar, layer_of

    linkage = fourbar()
    where = climbs(lambda: synth.balance_static(linkage, 31.4, samples=36))
    data = sum(n for (callee, caller), n in where.items()
               if layer_of(callee.rsplit(".", 2)[0]) in DATA and caller.startswith(CONSUMERS))
    assert data <= 6
