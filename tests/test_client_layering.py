"""The client package is the wire and nothing else: in a fresh interpreter where the engine, numpy and the
service cannot be imported at all (an import of any of them raises, however late or hidden), every module of
``mechsynth_client`` loads and every example of every model validates."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

PROBE = r'''
import importlib, importlib.abc, json, pkgutil, sys

BLOCKED = ("synth", "numpy", "api")


class Refuse(importlib.abc.MetaPathFinder):
    """Any import of the engine, numpy or the service fails, whoever asks and whenever."""

    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in BLOCKED:
            raise ImportError(f"the client package imported {name}")
        return None


sys.meta_path.insert(0, Refuse())
import mechsynth_client
from pydantic import BaseModel

modules = [importlib.import_module(m.name)
           for m in pkgutil.walk_packages(mechsynth_client.__path__, "mechsynth_client.")]
models = [obj for mod in modules for obj in vars(mod).values()
          if isinstance(obj, type) and issubclass(obj, BaseModel) and obj.__module__ == mod.__name__]
examples = 0
for model in models:
    for example in model.model_json_schema().get("examples", []):
        model.model_validate(example)
        examples += 1


def fits(value):
    """The names of the strict models (unknown fields refused) ``value`` validates as."""
    names = []
    for model in models:
        if model.model_config.get("extra") != "forbid":
            continue
        try:
            model.model_validate(value)
        except Exception:
            continue
        names.append(model.__qualname__)
    return names


constants = {}
for mod in modules:
    for name, value in vars(mod).items():
        if name.endswith("_EXAMPLE"):
            items = value if isinstance(value, list) else [value]
            constants[f"{mod.__name__}.{name}"] = [fits(item) for item in items]
print(json.dumps({"modules": [m.__name__ for m in modules], "models": len(models), "examples": examples,
                  "constants": constants,
                  "loaded": sorted({m.split(".")[0] for m in sys.modules} & set(BLOCKED))}))
'''


def test_client_loads_and_validates_its_examples_without_engine_numpy_or_service() -> None:
    run = subprocess.run([sys.executable, "-c", PROBE], cwd=REPO, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-3000:]
    found = json.loads(run.stdout)
    on_disk = {".".join(p.relative_to(REPO).with_suffix("").parts).removesuffix(".__init__")
               for p in (REPO / "mechsynth_client").rglob("*.py")} - {"mechsynth_client"}
    assert set(found["modules"]) == on_disk
    assert found["loaded"] == []
    # Every request model of an endpoint carries examples (the manual's); far more than one per module.
    assert found["models"] > 100 and found["examples"] > 50
    assert found["constants"], "the *_EXAMPLE constants were not found"
    for name, fits in found["constants"].items():
        assert all(fits), f"{name}: an item validates as none of the client's models"
