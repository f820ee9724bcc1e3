"""Service limits and budgets, read once from the environment (``SYNTH_*``) and validated at start."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, SecretStr, ValidationError
from pydantic_settings import BaseSettings, SettingsConfigDict


SECRET_SETTINGS = frozenset({"session_key", "admin_password", "database_url"})


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

    study_workers: int = Field(0, ge=0, le=256, description="Worker processes of the study lane, at a lower "
                               "scheduling priority than the request workers; 0 means as many as those.")
    study_lane: Literal["separate", "shared"] = Field(
        "separate", description="separate: study tasks run on workers of their own (niced); shared: on the "
                                "request workers, requests first, studies holding at most all but one.")
    study_nice: int = Field(19, ge=0, le=19, description="Niceness of the study workers (0..19).")
    warm_workers: bool = Field(True, description="Every request worker (a replaced one too) runs each capability "
                                                 "once before it takes work, and the service starts answering "
                                                 "when they are warm.")
    warm_limit_s: float = Field(120.0, gt=0, le=3600, description="Longest the start waits for the workers "
                                                                  "to warm up [s]; past it, it answers anyway.")
    max_running_studies: int = Field(4, ge=1, le=1000, description="Studies running at once; the others wait as "
                                                                   "queued, owners taking turns.")
    max_study_work_s: float = Field(7200.0, gt=0, le=1e9, description="A study's estimated work, its variants "
                                    "times the estimated cost of one [worker-seconds]; 413 beyond it.")
    max_owner_work_s: float = Field(21600.0, gt=0, le=1e10, description="Estimated work of one owner's queued and "
                                    "running studies together [worker-seconds]; 413 beyond it.")
    max_request_work_s: float = Field(120.0, gt=0, le=1e6, description="A request's estimated time on the "
                                      "workers it is dealt to (path synthesis: starts x points); 413 beyond it.")
    max_answer_bytes: int = Field(64_000_000, ge=10_000, le=10_000_000_000, description="Estimated size of an "
                                  "answer; 413 beyond it (with the hint to ask for npz or fewer samples).")
    spool_above_bytes: int = Field(1_000_000, ge=0, le=1_000_000_000, description="Answers larger than this are "
                                   "written to a file by the worker and streamed from it.")
    header_timeout_s: float = Field(10.0, gt=0, le=600, description="Time a client has to send a request's "
                                    "headers; the connection is closed past it.")
    keep_alive_s: float = Field(5.0, gt=0, le=600, description="Idle time a kept-alive connection stays open.")
    max_connections: int = Field(1000, ge=1, le=1_000_000, description="Open connections at once; beyond, "
                                 "new connections are answered 503 and closed.")
    database_url: str | None = Field(None, description="The store on a PostgreSQL server "
                                     "(postgresql://user:password@host:5432/db), shared by several service "
                                     "processes; unset: the SQLite file SYNTH_STUDIES_DB.")
    max_import_bytes: int = Field(50_000_000, ge=1_000, le=10_000_000_000,
                                  description="Body size of a library import (a project's export: answers and "
                                              "design records of every revision); 413 beyond it.")
    study_lease_s: float = Field(30.0, ge=0.5, le=3600,
                                 description="How long a running study's claim lasts unless its process renews it "
                                             "(a third of this apart); another process takes a study whose "
                                             "process stopped this long after.")

    auth: Literal["off", "on"] = Field("off", description="on: every /v1 request needs a signed-in user or an API "
                                      "token with a role that allows it (an office server); off: open (a laptop).")
    allowed_hosts: str = Field("localhost,127.0.0.1,::1", min_length=1,
                               description="Comma-separated host names the service answers to (the Host header; "
                                           "*.example.com for subdomains, * for any); 400 for others.")
    cors_origins: str = Field("", description="Comma-separated origins (https://cad.example.com) whose pages may "
                                             "call the API from another site; none by default.")
    behind_tls: bool = Field(False, description="The service is reached over HTTPS (a TLS proxy in front): cookies "
                                                "are Secure and browsers are told to keep to HTTPS.")
    session_key: SecretStr | None = Field(None, min_length=32, max_length=1024, description="Key signing the sign-in cookies (32+ characters); "
                                                            "unset: a random key, so restarts sign everyone out.")
    session_hours: float = Field(8.0, gt=0, le=24 * 30, description="How long a browser sign-in lasts [h].")
    sign_ins_per_minute: int = Field(10, ge=1, le=100_000, description="Sign-in attempts one client address may "
                                     "make per minute, right or wrong; 429 with Retry-After beyond.")
    token_days: float = Field(90.0, ge=0, le=36_500, description="How long a new API token lasts unless its "
                              "maker says otherwise [days]; 0: new tokens last until revoked.")
    max_connections_per_client: int = Field(100, ge=1, le=1_000_000, description="Open connections from one "
                                            "client address at once; beyond, its new connections wait a second "
                                            "unread, are answered 503 and closed (the others' are not).")
    accept_backlog: int = Field(128, ge=1, le=65_535, description="Connections the kernel holds waiting to be "
                                "accepted, and the most the service accepts in one turn of its event loop; a "
                                "flood of new connections beyond waits in the kernel instead of stalling the "
                                "requests in progress.")
    admin_name: str | None = Field(None, min_length=1, max_length=64,
                                   description="A first admin created at start when no user of that name exists.")
    admin_password: SecretStr | None = Field(None, description="The first admin's password (with admin_name).")

    def host_list(self) -> list[str]:
        """The allowed hosts as the Host header spells them (IPv6 addresses in brackets)."""
        hosts = [h.strip().lower() for h in self.allowed_hosts.split(",") if h.strip()]
        return [f"[{h}]" if ":" in h and not h.startswith("[") else h for h in hosts]

    def origin_list(self) -> list[str]:
        """The origins allowed to call from another site, without a trailing slash."""
        return [o.strip().rstrip("/") for o in self.cors_origins.split(",") if o.strip()]

    @classmethod
    def from_env(cls) -> Settings:
        """Settings from the environment; a bad value stops the service with the variable's name and the reason."""
        try:
            return cls()
        except ValidationError as exc:
            # a secret's value is never echoed (the message may end up in a log)
            lines = [f"SYNTH_{'_'.join(str(p) for p in e['loc']).upper()}: {e['msg']}"
                     + ("" if e["loc"][:1] and e["loc"][0] in SECRET_SETTINGS else f" (got {e.get('input')!r})")
                     for e in exc.errors()]
            raise SystemExit("invalid service settings:\n  " + "\n  ".join(lines)) from None
