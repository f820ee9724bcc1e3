"""The code's import graph: no circle, and no import from a lower layer to a higher one.

Layers, lowest first: model → kinematics → kinetostatics → capabilities (balancing, flywheel, gearing, synthesis)
→ machine and studies → the engine's public surface (``synth``) → the shared models and client → the HTTP layer.
The client's models are the wire: the client package imports nothing of the engine or the service. Every import
counts, at module level, inside functions and under ``TYPE_CHECKING`` alike: each one is a dependency a reader has
to follow. An import the code spells as a string (``importlib.import_module``, ``__import__``) counts too, and one
that reaches into another room that way is refused: it hides a dependency from this test and from type-checkers.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PACKAGES = ("synth", "mechsynth_client", "api")
# The top-level rooms of the house, and what a module may not name in a dynamic import outside its own room.
ROOMS = ("synth", "mechsynth_client", "api", "store")

# Longest prefix wins. Within one layer, modules may import each other as long as no circle forms.
LAYERS: dict[str, float] = {
    "synth.errors": 0, "synth.model": 0, "synth.topology": 0, "synth.execution": 0, "synth.compiled": 0,
    "synth.kinematics": 1, "synth.structure": 1,
    "synth.kinetostatics": 2, "synth.analysis": 2, "synth.dynamics": 2, "synth.counter_rotors": 2,
    "synth.friction": 2, "synth.mechanism": 0,
    "synth.warnings": 2.5,
    "synth.balancing": 3, "synth.flywheel": 3, "synth.synthesis": 3, "synth.plots": 3, "synth.exports": 3,
    "synth.gearing": 3.5,
    "synth.machine": 4, "synth.studies": 4,
    "synth": 5,
    "mechsynth_client": 6,
    "api": 7,
    "synth.cams": 3,
    "synth.strength": 3.6,
}


def _modules() -> dict[str, Path]:
    found = {}
    for package in PACKAGES:
        for path in (REPO / package).rglob("*.py"):
            parts = list(path.relative_to(REPO).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            found[".".join(parts)] = path
    return found


def _imports(name: str, path: Path, known: set[str]) -> Iterator[str]:
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                parts = parts[:len(parts) - (node.level - 1)]
                base = ".".join(parts + ([node.module] if node.module else []))
            targets = [base, *(f"{base}.{alias.name}" for alias in node.names)]
        else:
            continue
        for target in targets:
            while target and target not in known:
                target = target.rpartition(".")[0]
            if target and target != name:
                yield target


def _graph() -> dict[str, set[str]]:
    modules = _modules()
    known = set(modules)
    return {name: set(_imports(name, path, known)) for name, path in modules.items()}


def _related(a: str, b: str) -> bool:
    """``a`` is a module of package ``b`` or ``b`` one of package ``a``: one place in the layers."""
    return a.startswith(b + ".") or b.startswith(a + ".")


def _up_to_parent(a: str, b: str) -> bool:
    """``a`` imports its own package ``b`` (a name the package gathers from its parts): not a dependency of its
    own, since the package depends on ``a``, not the other way round."""
    return a.startswith(b + ".")


def _layer(name: str) -> float:
    best = max((k for k in LAYERS if name == k or name.startswith(k + ".")), key=len, default=None)
    assert best is not None, f"{name} is in no layer: add it to LAYERS in {Path(__file__).name}"
    return LAYERS[best]


def test_no_import_runs_up_the_layers() -> None:
    upward = sorted(f"{a} -> {b}" for a, targets in _graph().items() for b in targets
                    if not _related(a, b) and _layer(b) > _layer(a))
    assert upward == []


def test_no_import_circle() -> None:
    graph = {a: {b for b in targets if not _up_to_parent(a, b)} for a, targets in _graph().items()}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[list[str]] = []

    def visit(v: str) -> None:  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for v in graph:
        if v not in index:
            visit(v)
    assert circles == []


def test_the_graph_is_read() -> None:
    # The checks above see the real imports: the HTTP layer reaches the engine, the engine never the HTTP layer.
    graph = _graph()
    assert "synth" in graph["api.execution.plans"] or any(t.startswith("synth") for t in graph["api.execution.plans"])
    assert "mechsynth_client.schemas.analysis" in graph["mechsynth_client.client"]
    assert not any(t.startswith(("api", "mechsynth_client")) for a, ts in graph.items() if a.startswith("synth")
                   for t in ts)


def test_client_imports_nothing_of_the_engine_or_the_service() -> None:
    reached = sorted(f"{a} -> {b}" for a, targets in _graph().items() if a.startswith("mechsynth_client")
                     for b in targets if b.split(".")[0] in ("synth", "api"))
    assert reached == []
    # numpy only where the caller asks for an answer's arrays as numpy arrays (the ``.npz`` reader), nowhere else.
    numpy_users = set()
    for path in (REPO / "mechsynth_client").rglob("*.py"):
        tree = ast.parse(path.read_text())
        for scope in ast.walk(tree):
            for node in ast.iter_child_nodes(scope):
                names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                         [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level else [])
                tops = {n.split(".")[0] for n in names}
                assert not tops & {"synth", "api", "store"}, f"{path.relative_to(REPO)} imports {names}"
                if "numpy" in tops:
                    numpy_users.add(f"{path.relative_to(REPO)}:{getattr(scope, 'name', '<module>')}")
    assert numpy_users == {"mechsynth_client/client.py:_arrays"}


_DYNAMIC = {"import_module", "__import__", "find_spec", "spec_from_file_location", "_OnFirstUse"}


def _dynamic_imports(path: Path) -> Iterator[tuple[int, str | None]]:
    """Each call that imports a module named by a string: its line and the module's name, or None when the code
    builds the name so that no reader can tell it (a name built from ``__name__`` is the module's own package)."""
    for node in ast.walk(ast.parse(path.read_text())):
        if not isinstance(node, ast.Call):
            continue
        func = node.func
        called = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""
        if called not in _DYNAMIC or not node.args:
            continue
        arg = node.args[0]
        if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
            yield node.lineno, arg.value
        elif (isinstance(arg, ast.JoinedStr) and arg.values and isinstance(arg.values[0], ast.FormattedValue)
              and isinstance(arg.values[0].value, ast.Name) and arg.values[0].value.id == "__name__"):
            continue
        elif isinstance(arg, ast.JoinedStr) and arg.values and isinstance(arg.values[0], ast.Constant):
            yield node.lineno, str(arg.values[0].value)
        else:
            yield node.lineno, None


def test_no_room_imports_another_behind_a_string() -> None:
    hidden = []
    for room in ROOMS:
        for path in (REPO / room).rglob("*.py"):
            for line, name in _dynamic_imports(path):
                target = None if name is None else name.split(".")[0]
                if target is None or (target != room and target in {*ROOMS, "numpy"}):
                    hidden.append(f"{path.relative_to(REPO)}:{line} imports {name or 'a module it builds'}")
    assert hidden == []


def test_a_hidden_import_is_seen(tmp_path: Path) -> None:
    # The check above reads the tricks the client once used: an importlib call and a first-use stand-in.
    trick = tmp_path / "trick.py"
    trick.write_text('import importlib\nengine = importlib.import_module("synth.machine")\n'
                     'np = _OnFirstUse("numpy")\napp = __import__(name)\n')
    assert list(_dynamic_imports(trick)) == [(2, "synth.machine"), (3, "numpy"), (4, None)]
