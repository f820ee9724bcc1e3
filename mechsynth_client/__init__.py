"""Python client of the mechanism synthesis service, and the request and answer models it shares with it.

>>> from mechsynth_client import SynthClient
>>> from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
>>> from mechsynth_client.schemas.analysis import AnalysisIn
>>> with SynthClient("http://127.0.0.1:8000") as client:
...     out = client.analysis(AnalysisIn(mechanism=FOURBAR_EXAMPLE, speed_rpm=300))

Installed on its own (``pip install ./client``) it needs httpx and pydantic only; the service imports the same
models (:mod:`mechsynth_client.schemas`) for its requests and answers.
"""

from .client import (
    AsyncSynthClient,
    InfeasibleError,
    InvalidInputError,
    NotAssemblableError,
    ProblemError,
    ServiceBusyError,
    ServiceUnreachableError,
    SolverFailedError,
    SolverTimeoutError,
    SynthClient,
    TooLargeError,
)
from .studies import AsyncStudyHandle, StudyHandle

__all__ = [
    "AsyncStudyHandle", "AsyncSynthClient", "InfeasibleError", "InvalidInputError", "NotAssemblableError",
    "ProblemError", "ServiceBusyError", "ServiceUnreachableError", "SolverFailedError", "SolverTimeoutError",
    "StudyHandle", "SynthClient", "TooLargeError",
]
