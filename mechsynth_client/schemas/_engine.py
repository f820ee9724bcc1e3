"""The engine and numpy for the schemas' conversions, imported on first use.

The schemas are also the light client's models, installed with pydantic and httpx only: their modules load
without the engine, and only the conversions to and from engine objects (which run in the service) import it.
Write ``from ._engine import np, synth`` in a schema module instead of importing either directly.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import TYPE_CHECKING, Any


class _OnFirstUse:
    """Stands for a module until an attribute is read; then imports it and answers from it."""

    def __init__(self, name: str) -> None:
        self._name = name
        self._module: ModuleType | None = None

    def __getattr__(self, attr: str) -> Any:
        if self._module is None:
            self._module = importlib.import_module(self._name)
        return getattr(self._module, attr)


if TYPE_CHECKING:
    import numpy as np
    import synth as synth
else:
    np = _OnFirstUse("numpy")
    synth = _OnFirstUse("synth")

__all__ = ["np", "synth"]
