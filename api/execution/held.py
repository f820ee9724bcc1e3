"""The last engine results of an endpoint whose answer also comes as a document: the machine's design, held in the
web process so that its record (?format=pdf) or summary (?format=png) of the same request is written from the
design already made instead of designing the machine again.

The engine is deterministic (the same request gives the same design to the last bit, on any worker), so a result
held under the hash of its canonical request is the result a new design would give. The bound is small: a result
is what one person just looked at, and an office keeps a few open at once. With sign-in on, each user's results
are held apart (one user never receives a design another user's request made).
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from typing import Any

#: Results held per web process, the least recently used dropped first.
HELD_RESULTS = 8


class HeldResults:
    """A small least-recently-used map from (user, request hash) to an engine result."""

    def __init__(self, capacity: int = HELD_RESULTS) -> None:
        self.capacity = capacity
        self._items: OrderedDict[tuple[str, str], Any] = OrderedDict()
        self._lock = threading.Lock()
        self.hits = 0

    def get(self, key: tuple[str, str]) -> Any | None:
        """The result held under ``key`` (now the most recently used), or None."""
        with self._lock:
            if key not in self._items:
                return None
            self._items.move_to_end(key)
            self.hits += 1
            return self._items[key]

    def put(self, key: tuple[str, str], result: Any) -> None:
        """Hold ``result`` under ``key``, dropping the least recently used beyond the capacity."""
        with self._lock:
            self._items[key] = result
            self._items.move_to_end(key)
            while len(self._items) > self.capacity:
                self._items.popitem(last=False)

    def __len__(self) -> int:
        return len(self._items)
