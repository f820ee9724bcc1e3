"""Service limits and budgets, read once from the environment (``SYNTH_*``) and validated at start."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, ValidationError
from pydantic_settings import BaseSettings, SettingsConfigDict


class Settings(BaseSettings):
    """Limits of one service instance; each field is read from ``SYNTH_<FIELD>`` (e.g. ``SYNTH_WORKERS=4``)."""

    model_config = SettingsConfigDict(env_prefix="SYNTH_", frozen=True, extra="ignore")

    max_samples: int = Field(20_000, ge=2, le=1_000_000, description="Crank angles per request.")
    max_body_bytes: int = Field(2_000_000, ge=1_000, le=1_000_000_000,
                                description="Request body size; 413 beyond it, declared or streamed.")
    body_timeout_s: float = Field(10.0, gt=0, le=600,
                                  description="Time a client has to send its whole body; 408 past it.")
    solver_time_limit_s: float = Field(20.0, gt=0, le=3600, description="Each solver's own time limit.")
    request_deadline_s: float = Field(30.0, gt=0, le=3600,
                                      description="One deadline for all of a request's work, queueing included; "
                                                  "504 past it and the worker is replaced.")
    max_stages: int = Field(6, ge=1, le=12, description="Gear stages per drive.")
    executor: Literal["pool", "serial"] = Field("pool", description="Where requests' solver work runs: worker "
                                                "processes, or one thread of the web process.")
    workers: int = Field(0, ge=0, le=256, description="Worker processes; 0 means one per core.")
    queue_size: int = Field(16, ge=0, le=10_000,
                            description="Requests that may wait for a worker; beyond it 503 with Retry-After.")
    worker_memory_mb: int = Field(4096, ge=256, le=1_048_576,
                                  description="Address-space limit of each worker [MiB].")
    dask_scheduler: str | None = Field(None, description="Address of a Dask scheduler for studies "
                                                         "(tcp://host:8786); unset: the local workers.")
    studies_db: str = Field("./synth-studies.sqlite", min_length=1,
                            description="SQLite file of the embedded store (studies, designs, users) when "
                                        "SYNTH_DATABASE_URL is unset.")
    max_study_variants: int = Field(100_000, ge=1, le=10_000_000,
                                    description="Variants per design study; 413 beyond it.")

    database_url: str | None = Field(None, description="The store on a PostgreSQL server "
                                     "(postgresql://user:password@host:5432/db), shared by several service "
                                     "processes; unset: the SQLite file SYNTH_STUDIES_DB.")
    study_lease_s: float = Field(30.0, ge=0.5, le=3600,
                                 description="How long a running study's claim lasts unless its process renews it "
                                             "(a third of this apart); another process takes a study whose "
                                             "process stopped this long after.")

    @classmethod
    def from_env(cls) -> Settings:
        """Settings from the environment; a bad value stops the service with the variable's name and the reason."""
        try:
            return cls()
        except ValidationError as exc:
            lines = [f"SYNTH_{'_'.join(str(p) for p in e['loc']).upper()}: {e['msg']} (got {e.get('input')!r})"
                     for e in exc.errors()]
            raise SystemExit("invalid service settings:\n  " + "\n  ".join(lines)) from None
