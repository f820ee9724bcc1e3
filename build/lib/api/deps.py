"""Shared request dependencies as ``Annotated`` aliases: the app's settings and its solver gate."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, Request

from .settings import Settings
from .solvers import SolverGate


def get_settings(request: Request) -> Settings:
    """The settings the app was created with."""
    settings: Settings = request.app.state.settings
    return settings


def get_solver_gate(request: Request) -> SolverGate:
    """The app's one solver gate (one solve at a time per process)."""
    gate: SolverGate = request.app.state.solver_gate
    return gate


SettingsDep = Annotated[Settings, Depends(get_settings)]
SolverGateDep = Annotated[SolverGate, Depends(get_solver_gate)]
