"""Service limits and budgets, read once from the environment (``SYNTH_*``) with sensible defaults."""

from __future__ import annotations

import os
from dataclasses import dataclass


def _env(name: str, default: float) -> float:
    raw = os.environ.get(name)
    return default if raw is None else float(raw)


@dataclass(frozen=True, slots=True)
class Settings:
    """Limits of one service instance.

    max_samples: crank angles per request; max_body_bytes: request body size (413 beyond);
    solver_time_limit_s: each solver's own time limit; solver_wait_s: how long a request waits for a
    solver slot before answering 504; max_stages: gear stages per drive.
    """

    max_samples: int = 20_000
    max_body_bytes: int = 2_000_000
    solver_time_limit_s: float = 20.0
    solver_wait_s: float = 30.0
    max_stages: int = 6

    @classmethod
    def from_env(cls) -> Settings:
        """Settings with any ``SYNTH_<FIELD>`` environment variable applied."""
        d = cls()
        return cls(
            max_samples=int(_env("SYNTH_MAX_SAMPLES", d.max_samples)),
            max_body_bytes=int(_env("SYNTH_MAX_BODY_BYTES", d.max_body_bytes)),
            solver_time_limit_s=_env("SYNTH_SOLVER_TIME_LIMIT_S", d.solver_time_limit_s),
            solver_wait_s=_env("SYNTH_SOLVER_WAIT_S", d.solver_wait_s),
            max_stages=int(_env("SYNTH_MAX_STAGES", d.max_stages)),
        )
