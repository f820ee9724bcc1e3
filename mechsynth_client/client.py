"""Python client of the service: typed methods over the same pydantic models, against a URL or in-process.

>>> client = SynthClient("http://127.0.0.1:8000")          # a running service
>>> client = SynthClient.in_process()                       # the app in this process (tests, notebooks)
>>> out = client.analysis(AnalysisIn(mechanism=..., speed_rpm=300))

:class:`AsyncSynthClient` has the same methods as coroutines, over an ``httpx.AsyncClient``. A problem response
raises a :class:`ProblemError` subclass carrying the problem details. A busy service (503) is asked again after
the ``Retry-After`` it names, at most ``retries`` times and never waiting longer than ``max_retry_wait_s``.

Every export has a method: the figures as PNG, SVG or PDF (``format=`` on the ``*_png`` methods, PNG by default),
the curves as CSV text (``*_csv``, one row per crank angle), the arrays of array-heavy answers as numpy arrays
(``analysis_arrays``, ``flywheel_arrays``: a NumPy ``.npz`` answer, the only methods that need numpy), the drawings as DXF or SVG (``analysis_drawing``,
``balance_dxf``) and the machine's design report as PDF (``design_report_pdf``).

The arrays of a JSON answer (the curves over the crank angles) come at one quantum per array, as the service
writes them by default (eight significant digits at an array's largest magnitude, every value within 5e-8 of
it); ``SynthClient(..., precision="full")`` asks every answer for the float64 values exactly (``?precision=full``).

The client needs only httpx and pydantic (``pip install ./client``): its models are the wire (fields, validation,
examples) and import nothing of the engine or the service. The in-process mode needs the service installed, which
offers itself through the entry point group ``mechsynth_client.inprocess``.
"""

from __future__ import annotations

import asyncio
import time
from datetime import datetime, timezone
from email.utils import parsedate_to_datetime
from importlib.metadata import entry_points
from typing import Any, Literal, TypeVar

import httpx
from pydantic import BaseModel

from .library import AsyncLibraryClient, LibraryClient
from .schemas.analysis import AnalysisIn, AnalysisOut
from .schemas.balancing import (
    BalanceIn,
    BalanceMode,
    BalanceOut,
    FullBalanceIn,
    OptimalBalanceIn,
    OptimalBalanceOut,
    RotorIn,
    RotorOut,
    SliderCrankBalanceIn,
    SliderCrankBalanceOut,
)
from .schemas.flywheel import FlywheelIn, FlywheelOut, MachineTypeOut
from .schemas.engines import EngineIn, EngineOut
from .schemas.gearing import DriveIn, DriveOut, MotorOut, SplitIn, SplitOut, StageTypeOut, TeethIn, TeethOut
from .schemas.rating import GearMaterialOut, RatingIn, RatingOut
from .schemas.machine import MachineDesignOut, MachineIn
from .schemas.foundation import (
    ElasticDriveIn,
    ElasticDriveOut,
    IsolationDesignIn,
    IsolationDesignOut,
    IsolationIn,
    IsolationOut,
    RegulationIn,
    RegulationOut,
)
from .schemas.optimise import LinkageOptimiseIn, LinkageOptimiseOut, MachineOptimiseIn, MachineOptimiseOut
from .schemas.structure import StructureIn, StructureOut
from .schemas.train import TrainIn, TrainOut
from .schemas.strength import StrengthSizingIn, StrengthSizingOut
from .schemas.cams import CamAnalysisIn, CamAnalysisOut, CamSynthesisIn, CamSynthesisOut, MotionLawOut
from .schemas.synthesis import (
    CrankRockerIn,
    CrankRockerOut,
    PathIn,
    PathOut,
    SliderCrankSynthesisIn,
    SliderCrankSynthesisOut,
)
from .schemas.studies import StudyIn, StudyOut
from .schemas.auth import NewTokenOut, SessionOut, SignInIn, TokenIn, TokenOut, UserIn, UserOut, UserPatchIn
from .studies import AsyncStudyHandle, StudyHandle

__all__ = [
    "AsyncSynthClient",
    "BalanceMode",
    "DrawingFormat",
    "FigureFormat",
    "InfeasibleError",
    "InvalidInputError",
    "NotAssemblableError",
    "ProblemError",
    "ServiceBusyError",
    "ServiceUnreachableError",
    "SolverFailedError",
    "SolverTimeoutError",
    "SynthClient",
    "SynthesisKind",
    "TooLargeError",
    "UnauthorizedError",
    "ForbiddenError",
]

M = TypeVar("M", bound=BaseModel)
InProcessExecutor = Literal["serial", "pool"]
SynthesisKind = Literal["crank-rocker", "slider-crank", "path"]
DrawingFormat = Literal["dxf", "svg"]
FigureFormat = Literal["png", "svg", "pdf"]
#: Digits of the arrays of a JSON answer: ``single`` (the service's default: one quantum per array, eight
#: significant digits at its largest magnitude, within 5e-8 of it) or ``full`` (every float64 exactly).
Precision = Literal["single", "full"]


class ProblemError(Exception):
    """An RFC 9457 problem answered by the service; ``problem`` holds the whole body."""

    def __init__(self, status: int, problem: dict[str, Any]) -> None:
        self.status = status
        self.problem = problem
        self.type = str(problem.get("type", ""))
        self.title = str(problem.get("title", ""))
        self.detail = str(problem.get("detail", ""))
        super().__init__(f"{status} {self.title}: {self.detail}")


class InvalidInputError(ProblemError):
    """The request had a field the service cannot use (``problem['field']`` names it)."""


class NotAssemblableError(ProblemError):
    """The linkage does not close at some crank angles (``problem['not_assemblable_ranges_deg']``)."""


class InfeasibleError(ProblemError):
    """No admissible design meets the target (``problem['constraint']`` names the binding limit)."""


class SolverFailedError(ProblemError):
    """A solver stopped without an optimal answer (``problem['solver_status']``)."""


class SolverTimeoutError(ProblemError):
    """A solve ran past its time budget."""


class TooLargeError(ProblemError):
    """The request exceeded a size limit."""


class UnauthorizedError(ProblemError):
    """401: the service has authentication on and the client gave no valid token (``SynthClient(url, token=...)``)."""


class ForbiddenError(ProblemError):
    """403: the caller's roles do not allow the request, or it came from another site's page."""


class ServiceBusyError(ProblemError):
    """The service stayed busy (503) through every retry; ``retry_after_s`` is what it asked for last."""

    def __init__(self, status: int, problem: dict[str, Any], retry_after_s: float | None = None) -> None:
        super().__init__(status, problem)
        self.retry_after_s = retry_after_s


class ServiceUnreachableError(ConnectionError):
    """No answer from the service at ``url`` (not running, wrong address or port, or the network); the
    underlying httpx error is the ``__cause__``."""

    def __init__(self, url: str, reason: str) -> None:
        self.url = url
        super().__init__(f"no answer from the mechanism synthesis service at {url} ({reason}): is it running "
                         f"(`make run`) and is the address right?")


def _unreachable(request: httpx.Request, exc: httpx.TransportError) -> ServiceUnreachableError:
    return ServiceUnreachableError(str(request.url.copy_with(path="/", query=None)).rstrip("/"),
                                   type(exc).__name__)


#: Entry-point group through which an installed service offers itself for the in-process mode.
IN_PROCESS_GROUP = "mechsynth_client.inprocess"


def _in_process_service() -> Any:
    """The installed service's in-process adapter (a module with ``app(executor)`` and ``http_client(executor)``),
    found by the entry point the service's distribution declares: this package imports nothing of the service."""
    for entry in entry_points(group=IN_PROCESS_GROUP):
        return entry.load()
    raise RuntimeError("in-process mode runs the service itself: install the service (`pip install mechsynth`) "
                       "or give the client a base_url")


_BY_TYPE: dict[str, type[ProblemError]] = {
    "/problems/invalid-input": InvalidInputError,
    "/problems/not-assemblable": NotAssemblableError,
    "/problems/infeasible": InfeasibleError,
    "/problems/solver-failed": SolverFailedError,
    "/problems/solver-timeout": SolverTimeoutError,
    "/problems/too-large": TooLargeError,
    "/problems/overloaded": ServiceBusyError,
}


def _retry_after_s(response: httpx.Response) -> float | None:
    """The wait a 503 asks for [s]: ``Retry-After`` in seconds or as an HTTP date; None when absent or unreadable."""
    raw = response.headers.get("retry-after")
    if raw is None:
        return None
    try:
        return max(0.0, float(raw))
    except ValueError:
        pass
    try:
        when = parsedate_to_datetime(raw)
    except (TypeError, ValueError):
        return None
    if when.tzinfo is None:
        when = when.replace(tzinfo=timezone.utc)
    return max(0.0, (when - datetime.now(timezone.utc)).total_seconds())


class _Policy:
    """What the sync and async clients share: the retry policy, encoding requests and decoding problems."""

    def __init__(self, retries: int, max_retry_wait_s: float, token: str | None = None,
                 precision: Precision = "single") -> None:
        if retries < 0 or not max_retry_wait_s >= 0:
            raise ValueError("retries and max_retry_wait_s must not be negative")
        if precision not in ("single", "full"):
            raise ValueError("precision must be 'single' or 'full'")
        self.precision: Precision = precision
        # the service's default is not sent, so a service that predates the option answers as before
        self._answer_query: dict[str, str] = {"precision": precision} if precision == "full" else {}
        self.retries = retries
        self.max_retry_wait_s = max_retry_wait_s
        # kept out of repr and logs; sent on every request
        self._token = token
        self._csrf: str | None = None

    def _credentials(self, kwargs: dict[str, Any]) -> dict[str, Any]:
        """The request's keyword arguments with the API token (or a signed-in session's CSRF token) added."""
        headers = dict(kwargs.get("headers") or {})
        if self._token is not None:
            headers["authorization"] = f"Bearer {self._token}"
        if self._csrf is not None:
            headers["x-csrf-token"] = self._csrf
        return {**kwargs, "headers": headers} if headers else kwargs

    def _wait_s(self, response: httpx.Response, attempt: int) -> float | None:
        """Seconds to wait before asking again, or None when this answer is final."""
        if response.status_code != 503 or attempt >= self.retries:
            return None
        asked = _retry_after_s(response)
        # Without Retry-After, back off 0.5 s, 1 s, 2 s, ...; either way never past the cap.
        return min(self.max_retry_wait_s, 0.5 * 2.0**attempt if asked is None else asked)

    @staticmethod
    def _raise_for_problem(response: httpx.Response) -> None:
        if response.is_success:
            return
        try:
            body = response.json()
        except ValueError:
            body = {"title": response.reason_phrase, "detail": response.text, "status": response.status_code}
        if not isinstance(body, dict):
            body = {"detail": str(body)}
        if response.status_code == 503:
            raise ServiceBusyError(response.status_code, body, _retry_after_s(response))
        cls = _BY_TYPE.get(str(body.get("type", "")), ProblemError)
        if cls is ProblemError and response.status_code in (401, 403):
            cls = UnauthorizedError if response.status_code == 401 else ForbiddenError
        raise cls(response.status_code, body)

    @staticmethod
    def _json(body: BaseModel) -> Any:
        return body.model_dump(mode="json", exclude_none=True)

    @staticmethod
    def _export_query(fmt: str, params: dict[str, Any]) -> dict[str, Any]:
        """The query of an export: its format and the extras given (an angle), left out when None."""
        return {"format": fmt, **{k: v for k, v in params.items() if v is not None}}

    @staticmethod
    def _arrays(response: httpx.Response) -> dict[str, Any]:
        """An ``.npz`` answer as a dict of numpy arrays keyed by JSON path (numpy is needed only here)."""
        import io

        import numpy as np

        with np.load(io.BytesIO(response.content), allow_pickle=False) as archive:
            return {key: archive[key] for key in archive.files}

    @staticmethod
    def _rows(response: httpx.Response, model: type[M]) -> list[M]:
        return [model.model_validate(row) for row in response.json()]


class SynthClient(_Policy):
    """Client of the mechanism synthesis service over a given ``httpx.Client`` or a base URL."""

    def __init__(self, base_url: str | None = None, *, http: httpx.Client | None = None, timeout_s: float = 60.0,
                 retries: int = 3, max_retry_wait_s: float = 30.0, token: str | None = None,
                 precision: Precision = "single") -> None:
        if http is None and base_url is None:
            raise ValueError("give a base_url or an httpx.Client")
        super().__init__(retries, max_retry_wait_s, token, precision)
        self.http = http if http is not None else httpx.Client(base_url=base_url or "", timeout=timeout_s)

    @classmethod
    def in_process(cls, executor: InProcessExecutor = "serial", precision: Precision = "single") -> SynthClient:
        """A client speaking to a fresh app in this process, without a network (needs the service installed).

        Solver work runs in one background thread (``executor="serial"``), which works from any script or notebook;
        ``"pool"`` uses worker processes as the service does (a script then needs an ``if __name__ == "__main__"``
        guard, as every multiprocessing program does).
        """
        return cls(http=_in_process_service().http_client(executor, base_url="http://localhost"), precision=precision)

    def close(self) -> None:
        """Close the underlying HTTP client."""
        self.http.close()

    def __enter__(self) -> SynthClient:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

    def _send(self, method: str, path: str, **kwargs: Any) -> httpx.Response:
        attempt = 0
        while True:
            request = self.http.build_request(method, path, **self._credentials(kwargs))
            try:
                response = self.http.send(request)
            except httpx.TransportError as exc:
                raise _unreachable(request, exc) from exc
            wait = self._wait_s(response, attempt)
            if wait is None:
                self._raise_for_problem(response)
                return response
            time.sleep(wait)
            attempt += 1

    def _post(self, path: str, body: BaseModel, out: type[M]) -> M:
        response = self._send("POST", path, json=self._json(body), params=self._answer_query)
        return out.model_validate_json(response.content)

    def _export(self, path: str, body: BaseModel, fmt: str, **params: Any) -> httpx.Response:
        return self._send("POST", path, json=self._json(body), params=self._export_query(fmt, params))

    def _get_rows(self, path: str, model: type[M]) -> list[M]:
        return self._rows(self._send("GET", path), model)

    def health(self) -> dict[str, Any]:
        """GET /health."""
        result: dict[str, Any] = self._send("GET", "/health").json()
        return result

    def ready(self) -> dict[str, Any]:
        """GET /ready: the executor, its workers, running and queued requests, and the admission capacity."""
        result: dict[str, Any] = self._send("GET", "/ready").json()
        return result

    def analysis(self, body: AnalysisIn) -> AnalysisOut:
        """POST /v1/analysis: the linkage's kinematic and kinetostatic picture over the cycle."""
        return self._post("/v1/analysis", body, AnalysisOut)

    def analysis_png(self, body: AnalysisIn, angle_deg: float | None = None, format: FigureFormat = "png") -> bytes:
        """POST /v1/analysis?format=png|svg|pdf: driving torque, shaking moment, shaking force polar diagram and
        the mechanism at ``angle_deg``."""
        return self._export("/v1/analysis", body, format, angle_deg=angle_deg).content

    def analysis_csv(self, body: AnalysisIn) -> str:
        """POST /v1/analysis?format=csv: every curve as CSV text, one row per crank angle, units in the column
        names."""
        return self._export("/v1/analysis", body, "csv").text

    def analysis_arrays(self, body: AnalysisIn) -> dict[str, Any]:
        """POST /v1/analysis?format=npz: every number of the answer as numpy arrays keyed by JSON path
        (``driving_torque_Nm``, ``joint_reactions_N/A``, ``links/crank/angle_deg``); needs numpy."""
        return self._arrays(self._export("/v1/analysis", body, "npz"))

    def analysis_drawing(self, body: AnalysisIn, format: DrawingFormat = "dxf",
                         angle_deg: float | None = None) -> bytes:
        """POST /v1/analysis/drawing: the mechanism to scale in millimetres with its counterweights, DXF or SVG."""
        return self._export("/v1/analysis/drawing", body, format, angle_deg=angle_deg).content

    def machine_types(self) -> list[MachineTypeOut]:
        """GET /v1/machine-types: admissible coefficient of speed fluctuation per machine type."""
        return self._get_rows("/v1/machine-types", MachineTypeOut)

    def flywheel(self, body: FlywheelIn) -> FlywheelOut:
        """POST /v1/flywheel: flywheel sizing by every method, each with its simulated delta."""
        return self._post("/v1/flywheel", body, FlywheelOut)

    def flywheel_png(self, body: FlywheelIn, format: FigureFormat = "png") -> bytes:
        """POST /v1/flywheel?format=png|svg|pdf: energy-mass diagram with its tangents and the speed over the
        cycle."""
        return self._export("/v1/flywheel", body, format).content

    def flywheel_csv(self, body: FlywheelIn) -> str:
        """POST /v1/flywheel?format=csv: the cycle as sized (J_red, reduced torque, excess work) and every method's
        simulated speed as CSV text, one row per sample of the cycle."""
        return self._export("/v1/flywheel", body, "csv").text

    def flywheel_arrays(self, body: FlywheelIn) -> dict[str, Any]:
        """POST /v1/flywheel?format=npz: every number of the answer as numpy arrays keyed by JSON path; needs
        numpy."""
        return self._arrays(self._export("/v1/flywheel", body, "npz"))

    def gears_split(self, body: SplitIn) -> SplitOut:
        """POST /v1/gears/split: stage ratios (motor side first) for minimum inertia, volume or the handbook rule."""
        return self._post("/v1/gears/split", body, SplitOut)

    def gears_teeth(self, body: TeethIn) -> TeethOut:
        """POST /v1/gears/teeth: tooth numbers of the whole train by an exact search."""
        return self._post("/v1/gears/teeth", body, TeethOut)

    def gears_drive(self, body: DriveIn) -> DriveOut:
        """POST /v1/gears/drive: motor choice, ratio split, every shaft's speed, power, torque and inertia."""
        return self._post("/v1/gears/drive", body, DriveOut)

    def gears_train(self, body: TrainIn) -> TrainOut:
        """POST /v1/gears/train."""
        return self._post("/v1/gears/train", body, TrainOut)

    def structure(self, body: StructureIn) -> StructureOut:
        """POST /v1/structure: mobility, redundant constraints, Assur groups."""
        return self._post("/v1/structure", body, StructureOut)

    def gears_stage_types(self) -> list[StageTypeOut]:
        """GET /v1/gears/stage-types: the shipped stage-type table."""
        return self._get_rows("/v1/gears/stage-types", StageTypeOut)

    def gears_motors(self) -> list[MotorOut]:
        """GET /v1/gears/motors: the shipped motor catalogue."""
        return self._get_rows("/v1/gears/motors", MotorOut)

    def gears_rating(self, body: RatingIn) -> RatingOut:
        """POST /v1/gears/rating: ISO 6336 method B load capacity of a pair."""
        return self._post("/v1/gears/rating", body, RatingOut)

    def gears_materials(self) -> list[GearMaterialOut]:
        """GET /v1/gears/materials: the shipped gear material grades."""
        return self._get_rows("/v1/gears/materials", GearMaterialOut)

    def balance_static(self, body: BalanceIn) -> BalanceOut:
        """POST /v1/balancing/static: counterweights that zero the shaking force."""
        return self._post("/v1/balancing/static", body, BalanceOut)

    def balance_full(self, body: FullBalanceIn) -> BalanceOut:
        """POST /v1/balancing/full: shaking force and moment zero (counterweights, pendulum coupler, counter-rotors)."""
        return self._post("/v1/balancing/full", body, BalanceOut)

    def balance_optimal(self, body: OptimalBalanceIn) -> OptimalBalanceOut:
        """POST /v1/balancing/optimal: weighted trade-off within a mass budget, with the trade-off curve."""
        return self._post("/v1/balancing/optimal", body, OptimalBalanceOut)

    def balance_png(self, mode: BalanceMode, body: BalanceIn, format: FigureFormat = "png") -> bytes:
        """Before/after figure of a balancing mode (`static`, `full` or `optimal`) as PNG, SVG or PDF."""
        return self._export(f"/v1/balancing/{mode}", body, format).content

    def balance_csv(self, mode: BalanceMode, body: BalanceIn) -> str:
        """Shaking force, shaking moment and driving torque before and after a balancing mode as CSV text, one row
        per crank angle."""
        return self._export(f"/v1/balancing/{mode}", body, "csv").text

    def balance_dxf(self, mode: BalanceMode, body: BalanceIn) -> bytes:
        """The balanced mechanism with its counterweights at the first crank angle, as a DXF drawing in
        millimetres."""
        return self._export(f"/v1/balancing/{mode}", body, "dxf").content

    def balance_rotor(self, body: RotorIn) -> RotorOut:
        """POST /v1/balancing/rotor: single-plane static or two-plane dynamic rotor balance."""
        return self._post("/v1/balancing/rotor", body, RotorOut)

    def balance_engine(self, body: EngineIn) -> EngineOut:
        """POST /v1/balancing/engine: an engine's shaking force and moment by orders and what cancels each."""
        return self._post("/v1/balancing/engine", body, EngineOut)

    def balance_slider_crank(self, body: SliderCrankBalanceIn) -> SliderCrankBalanceOut:
        """POST /v1/balancing/slider-crank: crank counterweight and Lanchester balancer."""
        return self._post("/v1/balancing/slider-crank", body, SliderCrankBalanceOut)

    def balance_slider_crank_png(self, body: SliderCrankBalanceIn, format: FigureFormat = "png") -> bytes:
        """Figure of a slider-crank balance as PNG, SVG or PDF: shaking force and moment before and after, the
        force by crank order, the mechanism with its counterweight and Lanchester shafts."""
        return self._export("/v1/balancing/slider-crank", body, format).content

    def design_machine(self, body: MachineIn) -> MachineDesignOut:
        """POST /v1/machines/design: the whole machine, linkage to motor, checked by simulating it."""
        return self._post("/v1/machines/design", body, MachineDesignOut)

    def design_machine_png(self, body: MachineIn) -> bytes:
        """POST /v1/machines/design?format=png: the one-page summary of the design."""
        return self._export("/v1/machines/design", body, "png").content

    def design_report_pdf(self, body: MachineIn) -> bytes:
        """POST /v1/machines/design?format=pdf: the multi-page design report (with the alternatives when the
        request asks for them)."""
        return self._export("/v1/machines/design", body, "pdf").content

    def optimise_machine(self, body: MachineOptimiseIn) -> MachineOptimiseOut:
        """POST /v1/machines/optimise: the machine optimised as a whole over its linkage family."""
        return self._post("/v1/machines/optimise", body, MachineOptimiseOut)

    def optimisation_record_pdf(self, body: MachineOptimiseIn) -> bytes:
        """POST /v1/machines/optimise?format=pdf: the optimised machine's design record with a page for the
        optimisation's certificate."""
        return self._export("/v1/machines/optimise", body, "pdf").content

    def optimise_linkage(self, body: LinkageOptimiseIn) -> LinkageOptimiseOut:
        """POST /v1/machines/optimise-linkage: any linkage's free dimensions chosen with its machine."""
        return self._post("/v1/machines/optimise-linkage", body, LinkageOptimiseOut)

    def isolate_machine(self, body: IsolationIn) -> IsolationOut:
        """POST /v1/machines/isolation: the machine's frame on isolators and what the foundation feels."""
        return self._post("/v1/machines/isolation", body, IsolationOut)

    def isolation_png(self, body: IsolationIn, format: FigureFormat = "png") -> bytes:
        """POST /v1/machines/isolation?format=png: force to the foundation, the frame's orbit, transmissibility."""
        return self._export("/v1/machines/isolation", body, format).content

    def design_isolation(self, body: IsolationDesignIn) -> IsolationDesignOut:
        """POST /v1/machines/isolation/design: one isolator type (and an inertia block) for a force or amplitude
        limit."""
        return self._post("/v1/machines/isolation/design", body, IsolationDesignOut)

    def elastic_drive(self, body: ElasticDriveIn) -> ElasticDriveOut:
        """POST /v1/machines/elastic-drive: the two-mass drive with an elastic link, its natural frequency, the
        torque in the link and the run-up."""
        return self._post("/v1/machines/elastic-drive", body, ElasticDriveOut)

    def elastic_drive_png(self, body: ElasticDriveIn, format: FigureFormat = "png") -> bytes:
        """POST /v1/machines/elastic-drive?format=png: the link's torque against the rigid model's, the run-up."""
        return self._export("/v1/machines/elastic-drive", body, format).content

    def regulation(self, body: RegulationIn) -> RegulationOut:
        """POST /v1/machines/regulation: the speed after a load step, self-regulated or with a PI controller."""
        return self._post("/v1/machines/regulation", body, RegulationOut)

    def regulation_png(self, body: RegulationIn, format: FigureFormat = "png") -> bytes:
        """POST /v1/machines/regulation?format=png: speed and torques over time."""
        return self._export("/v1/machines/regulation", body, format).content

    def synthesise_crank_rocker(self, body: CrankRockerIn) -> CrankRockerOut:
        """POST /v1/synthesis/crank-rocker: the best crank-rocker for a rocker swing and a time ratio."""
        return self._post("/v1/synthesis/crank-rocker", body, CrankRockerOut)

    def synthesise_slider_crank(self, body: SliderCrankSynthesisIn) -> SliderCrankSynthesisOut:
        """POST /v1/synthesis/slider-crank: the best offset slider-crank for a stroke and a time ratio."""
        return self._post("/v1/synthesis/slider-crank", body, SliderCrankSynthesisOut)

    def synthesise_path(self, body: PathIn) -> PathOut:
        """POST /v1/synthesis/path: a four-bar whose coupler point passes through (or nearest to) the targets."""
        return self._post("/v1/synthesis/path", body, PathOut)

    def synthesis_png(self, kind: SynthesisKind, body: CrankRockerIn | SliderCrankSynthesisIn | PathIn) -> bytes:
        """Figure of a synthesis answer (`crank-rocker`, `slider-crank` or `path`): dead centres or coupler curve."""
        return self._export(f"/v1/synthesis/{kind}", body, "png").content

    def study(self, body: StudyIn) -> StudyHandle:
        """POST /v1/studies: start a design study; the handle follows, waits for, reads and cancels it."""
        # Sent whole: a null (objective_digits) means something here, unlike a left-out field elsewhere.
        response = self._send("POST", "/v1/studies", json=body.model_dump(mode="json"))
        status = StudyOut.model_validate_json(response.content)
        return StudyHandle(self, status.id, status)

    def studies(self) -> list[StudyOut]:
        """GET /v1/studies: the latest studies first, with their state and progress."""
        return self._get_rows("/v1/studies", StudyOut)

    def study_handle(self, study_id: str) -> StudyHandle:
        """A handle on an existing study, by id (for example after a restart of this program)."""
        handle = StudyHandle(self, study_id)
        handle.status()
        return handle

    def cam_analysis(self, body: CamAnalysisIn) -> CamAnalysisOut:
        """POST /v1/cams/analysis: a disc cam over one turn with its checks."""
        return self._post("/v1/cams/analysis", body, CamAnalysisOut)

    def strength(self, body: StrengthSizingIn) -> StrengthSizingOut:
        """POST /v1/strength: the linkage's bars sized for the cycle's forces, to the fixed point."""
        return self._post("/v1/strength", body, StrengthSizingOut)

    def cam_synthesis(self, body: CamSynthesisIn) -> CamSynthesisOut:
        """POST /v1/cams/synthesis: the least cam for pressure-angle and curvature limits."""
        return self._post("/v1/cams/synthesis", body, CamSynthesisOut)

    def cam_file(self, body: CamAnalysisIn | CamSynthesisIn, format: Literal["png", "svg", "pdf", "csv", "dxf"]
                 = "png") -> bytes:
        """The cam's figure (png, svg, pdf), point table (csv) or profile drawing (dxf, millimetres)."""
        kind = "analysis" if isinstance(body, CamAnalysisIn) else "synthesis"
        return self._export(f"/v1/cams/{kind}", body, format).content

    def cam_laws(self) -> list[MotionLawOut]:
        """GET /v1/cams/laws: the standard motion laws' peak coefficients."""
        return self._get_rows("/v1/cams/laws", MotionLawOut)

    @property
    def library(self) -> LibraryClient:
        """The design library: save, history, search, diff, restore, sign-off, export and import."""
        return LibraryClient(self)

    def session(self) -> SessionOut:
        """GET /v1/auth/session: whether authentication is on, and who this client acts as, with which roles."""
        return SessionOut.model_validate_json(self._send("GET", "/v1/auth/session").content)

    def sign_in(self, name: str, password: str) -> SessionOut:
        """POST /v1/auth/signin: sign in with a name and password (a notebook without a token); the session cookie
        and its CSRF token go with every later request of this client."""
        body = SignInIn(name=name, password=password)
        out = SessionOut.model_validate_json(self._send("POST", "/v1/auth/signin", json=self._json(body)).content)
        self._csrf = out.csrf_token
        return out

    def sign_out(self) -> None:
        """POST /v1/auth/signout: end this client's signed-in session."""
        self._send("POST", "/v1/auth/signout")
        self._csrf = None

    def users(self) -> list[UserOut]:
        """GET /v1/users (admins): every user with its roles."""
        return self._get_rows("/v1/users", UserOut)

    def user(self, name: str) -> UserOut:
        """GET /v1/users/{name} (admins)."""
        return UserOut.model_validate_json(self._send("GET", f"/v1/users/{name}").content)

    def add_user(self, body: UserIn) -> UserOut:
        """POST /v1/users (admins): make a user with a password and roles."""
        return self._post("/v1/users", body, UserOut)

    def update_user(self, name: str, body: UserPatchIn) -> UserOut:
        """PATCH /v1/users/{name} (admins): a new password, new roles, or both."""
        response = self._send("PATCH", f"/v1/users/{name}", json=self._json(body))
        return UserOut.model_validate_json(response.content)

    def remove_user(self, name: str) -> None:
        """DELETE /v1/users/{name} (admins): the user and its tokens."""
        self._send("DELETE", f"/v1/users/{name}")

    def user_tokens(self, name: str) -> list[TokenOut]:
        """GET /v1/users/{name}/tokens (admins): a user's tokens, without their secrets."""
        return self._get_rows(f"/v1/users/{name}/tokens", TokenOut)

    def add_token(self, name: str, body: TokenIn) -> NewTokenOut:
        """POST /v1/users/{name}/tokens (admins): a new API token for a user, its secret shown this once."""
        return self._post(f"/v1/users/{name}/tokens", body, NewTokenOut)

    def revoke_token(self, token_id: int) -> None:
        """DELETE /v1/tokens/{token_id} (admins): revoke a token at once."""
        self._send("DELETE", f"/v1/tokens/{token_id}")


class AsyncSynthClient(_Policy):
    """The same client for asyncio: every method of :class:`SynthClient` as a coroutine, over ``httpx.AsyncClient``."""

    def __init__(self, base_url: str | None = None, *, http: httpx.AsyncClient | None = None,
                 timeout_s: float = 60.0, retries: int = 3, max_retry_wait_s: float = 30.0,
                 token: str | None = None, precision: Precision = "single") -> None:
        if http is None and base_url is None:
            raise ValueError("give a base_url or an httpx.AsyncClient")
        super().__init__(retries, max_retry_wait_s, token, precision)
        self.http = http if http is not None else httpx.AsyncClient(base_url=base_url or "", timeout=timeout_s)

    @classmethod
    def in_process(cls, executor: InProcessExecutor = "serial", precision: Precision = "single"
                   ) -> AsyncSynthClient:
        """A client speaking to a fresh app in this process over ASGI (needs the service installed); ``executor``
        as in :meth:`SynthClient.in_process`."""
        transport = httpx.ASGITransport(app=_in_process_service().app(executor))
        return cls(http=httpx.AsyncClient(transport=transport, base_url="http://localhost"), precision=precision)

    async def aclose(self) -> None:
        """Close the underlying HTTP client."""
        await self.http.aclose()

    async def __aenter__(self) -> AsyncSynthClient:
        return self

    async def __aexit__(self, *_: object) -> None:
        await self.aclose()

    async def _send(self, method: str, path: str, **kwargs: Any) -> httpx.Response:
        attempt = 0
        while True:
            request = self.http.build_request(method, path, **self._credentials(kwargs))
            try:
                response = await self.http.send(request)
            except httpx.TransportError as exc:
                raise _unreachable(request, exc) from exc
            wait = self._wait_s(response, attempt)
            if wait is None:
                self._raise_for_problem(response)
                return response
            await asyncio.sleep(wait)
            attempt += 1

    async def _post(self, path: str, body: BaseModel, out: type[M]) -> M:
        response = await self._send("POST", path, json=self._json(body), params=self._answer_query)
        return out.model_validate_json(response.content)

    async def _export(self, path: str, body: BaseModel, fmt: str, **params: Any) -> httpx.Response:
        return await self._send("POST", path, json=self._json(body), params=self._export_query(fmt, params))

    async def _get_rows(self, path: str, model: type[M]) -> list[M]:
        return self._rows(await self._send("GET", path), model)

    async def health(self) -> dict[str, Any]:
        """GET /health."""
        result: dict[str, Any] = (await self._send("GET", "/health")).json()
        return result

    async def ready(self) -> dict[str, Any]:
        """GET /ready."""
        result: dict[str, Any] = (await self._send("GET", "/ready")).json()
        return result

    async def analysis(self, body: AnalysisIn) -> AnalysisOut:
        """POST /v1/analysis."""
        return await self._post("/v1/analysis", body, AnalysisOut)

    async def analysis_png(self, body: AnalysisIn, angle_deg: float | None = None,
                           format: FigureFormat = "png") -> bytes:
        """POST /v1/analysis?format=png|svg|pdf."""
        return (await self._export("/v1/analysis", body, format, angle_deg=angle_deg)).content

    async def analysis_csv(self, body: AnalysisIn) -> str:
        """POST /v1/analysis?format=csv."""
        return (await self._export("/v1/analysis", body, "csv")).text

    async def analysis_arrays(self, body: AnalysisIn) -> dict[str, Any]:
        """POST /v1/analysis?format=npz."""
        return self._arrays(await self._export("/v1/analysis", body, "npz"))

    async def analysis_drawing(self, body: AnalysisIn, format: DrawingFormat = "dxf",
                               angle_deg: float | None = None) -> bytes:
        """POST /v1/analysis/drawing."""
        return (await self._export("/v1/analysis/drawing", body, format, angle_deg=angle_deg)).content

    async def machine_types(self) -> list[MachineTypeOut]:
        """GET /v1/machine-types."""
        return await self._get_rows("/v1/machine-types", MachineTypeOut)

    async def flywheel(self, body: FlywheelIn) -> FlywheelOut:
        """POST /v1/flywheel."""
        return await self._post("/v1/flywheel", body, FlywheelOut)

    async def flywheel_png(self, body: FlywheelIn, format: FigureFormat = "png") -> bytes:
        """POST /v1/flywheel?format=png|svg|pdf."""
        return (await self._export("/v1/flywheel", body, format)).content

    async def flywheel_csv(self, body: FlywheelIn) -> str:
        """POST /v1/flywheel?format=csv."""
        return (await self._export("/v1/flywheel", body, "csv")).text

    async def flywheel_arrays(self, body: FlywheelIn) -> dict[str, Any]:
        """POST /v1/flywheel?format=npz."""
        return self._arrays(await self._export("/v1/flywheel", body, "npz"))

    async def gears_split(self, body: SplitIn) -> SplitOut:
        """POST /v1/gears/split."""
        return await self._post("/v1/gears/split", body, SplitOut)

    async def gears_teeth(self, body: TeethIn) -> TeethOut:
        """POST /v1/gears/teeth."""
        return await self._post("/v1/gears/teeth", body, TeethOut)

    async def gears_drive(self, body: DriveIn) -> DriveOut:
        """POST /v1/gears/drive."""
        return await self._post("/v1/gears/drive", body, DriveOut)

    async def gears_stage_types(self) -> list[StageTypeOut]:
        """GET /v1/gears/stage-types."""
        return await self._get_rows("/v1/gears/stage-types", StageTypeOut)

    async def gears_motors(self) -> list[MotorOut]:
        """GET /v1/gears/motors."""
        return await self._get_rows("/v1/gears/motors", MotorOut)

    async def gears_rating(self, body: RatingIn) -> RatingOut:
        """POST /v1/gears/rating."""
        return await self._post("/v1/gears/rating", body, RatingOut)

    async def gears_materials(self) -> list[GearMaterialOut]:
        """GET /v1/gears/materials."""
        return await self._get_rows("/v1/gears/materials", GearMaterialOut)

    async def balance_static(self, body: BalanceIn) -> BalanceOut:
        """POST /v1/balancing/static."""
        return await self._post("/v1/balancing/static", body, BalanceOut)

    async def balance_full(self, body: FullBalanceIn) -> BalanceOut:
        """POST /v1/balancing/full."""
        return await self._post("/v1/balancing/full", body, BalanceOut)

    async def balance_optimal(self, body: OptimalBalanceIn) -> OptimalBalanceOut:
        """POST /v1/balancing/optimal."""
        return await self._post("/v1/balancing/optimal", body, OptimalBalanceOut)

    async def balance_png(self, mode: BalanceMode, body: BalanceIn, format: FigureFormat = "png") -> bytes:
        """Before/after figure of a balancing mode."""
        return (await self._export(f"/v1/balancing/{mode}", body, format)).content

    async def balance_csv(self, mode: BalanceMode, body: BalanceIn) -> str:
        """Curves before and after a balancing mode as CSV text."""
        return (await self._export(f"/v1/balancing/{mode}", body, "csv")).text

    async def balance_dxf(self, mode: BalanceMode, body: BalanceIn) -> bytes:
        """The balanced mechanism as a DXF drawing."""
        return (await self._export(f"/v1/balancing/{mode}", body, "dxf")).content

    async def balance_rotor(self, body: RotorIn) -> RotorOut:
        """POST /v1/balancing/rotor."""
        return await self._post("/v1/balancing/rotor", body, RotorOut)

    async def balance_engine(self, body: EngineIn) -> EngineOut:
        """POST /v1/balancing/engine."""
        return await self._post("/v1/balancing/engine", body, EngineOut)

    async def balance_slider_crank(self, body: SliderCrankBalanceIn) -> SliderCrankBalanceOut:
        """POST /v1/balancing/slider-crank."""
        return await self._post("/v1/balancing/slider-crank", body, SliderCrankBalanceOut)

    async def balance_slider_crank_png(self, body: SliderCrankBalanceIn, format: FigureFormat = "png") -> bytes:
        """Figure of a slider-crank balance."""
        return (await self._export("/v1/balancing/slider-crank", body, format)).content

    async def gears_train(self, body: TrainIn) -> TrainOut:
        """POST /v1/gears/train."""
        return await self._post("/v1/gears/train", body, TrainOut)

    async def structure(self, body: StructureIn) -> StructureOut:
        """POST /v1/structure."""
        return await self._post("/v1/structure", body, StructureOut)

    async def design_machine(self, body: MachineIn) -> MachineDesignOut:
        """POST /v1/machines/design."""
        return await self._post("/v1/machines/design", body, MachineDesignOut)

    async def design_machine_png(self, body: MachineIn) -> bytes:
        """POST /v1/machines/design?format=png."""
        return (await self._export("/v1/machines/design", body, "png")).content

    async def design_report_pdf(self, body: MachineIn) -> bytes:
        """POST /v1/machines/design?format=pdf."""
        return (await self._export("/v1/machines/design", body, "pdf")).content

    async def optimisation_record_pdf(self, body: MachineOptimiseIn) -> bytes:
        """POST /v1/machines/optimise?format=pdf."""
        return (await self._export("/v1/machines/optimise", body, "pdf")).content

    async def optimise_linkage(self, body: LinkageOptimiseIn) -> LinkageOptimiseOut:
        """POST /v1/machines/optimise-linkage."""
        return await self._post("/v1/machines/optimise-linkage", body, LinkageOptimiseOut)

    async def optimise_machine(self, body: MachineOptimiseIn) -> MachineOptimiseOut:
        """POST /v1/machines/optimise."""
        return await self._post("/v1/machines/optimise", body, MachineOptimiseOut)

    async def isolate_machine(self, body: IsolationIn) -> IsolationOut:
        """POST /v1/machines/isolation."""
        return await self._post("/v1/machines/isolation", body, IsolationOut)

    async def isolation_png(self, body: IsolationIn, format: FigureFormat = "png") -> bytes:
        """POST /v1/machines/isolation?format=png."""
        return (await self._export("/v1/machines/isolation", body, format)).content

    async def design_isolation(self, body: IsolationDesignIn) -> IsolationDesignOut:
        """POST /v1/machines/isolation/design."""
        return await self._post("/v1/machines/isolation/design", body, IsolationDesignOut)

    async def elastic_drive(self, body: ElasticDriveIn) -> ElasticDriveOut:
        """POST /v1/machines/elastic-drive."""
        return await self._post("/v1/machines/elastic-drive", body, ElasticDriveOut)

    async def elastic_drive_png(self, body: ElasticDriveIn, format: FigureFormat = "png") -> bytes:
        """POST /v1/machines/elastic-drive?format=png."""
        return (await self._export("/v1/machines/elastic-drive", body, format)).content

    async def regulation(self, body: RegulationIn) -> RegulationOut:
        """POST /v1/machines/regulation."""
        return await self._post("/v1/machines/regulation", body, RegulationOut)

    async def regulation_png(self, body: RegulationIn, format: FigureFormat = "png") -> bytes:
        """POST /v1/machines/regulation?format=png."""
        return (await self._export("/v1/machines/regulation", body, format)).content

    async def synthesise_crank_rocker(self, body: CrankRockerIn) -> CrankRockerOut:
        """POST /v1/synthesis/crank-rocker."""
        return await self._post("/v1/synthesis/crank-rocker", body, CrankRockerOut)

    async def synthesise_slider_crank(self, body: SliderCrankSynthesisIn) -> SliderCrankSynthesisOut:
        """POST /v1/synthesis/slider-crank."""
        return await self._post("/v1/synthesis/slider-crank", body, SliderCrankSynthesisOut)

    async def synthesise_path(self, body: PathIn) -> PathOut:
        """POST /v1/synthesis/path."""
        return await self._post("/v1/synthesis/path", body, PathOut)

    async def synthesis_png(self, kind: SynthesisKind, body: CrankRockerIn | SliderCrankSynthesisIn | PathIn) -> bytes:
        """Figure of a synthesis answer."""
        return (await self._export(f"/v1/synthesis/{kind}", body, "png")).content

    async def study(self, body: StudyIn) -> AsyncStudyHandle:
        """POST /v1/studies: start a design study; the handle follows, waits for, reads and cancels it."""
        response = await self._send("POST", "/v1/studies", json=body.model_dump(mode="json"))
        status = StudyOut.model_validate_json(response.content)
        return AsyncStudyHandle(self, status.id, status)

    async def studies(self) -> list[StudyOut]:
        """GET /v1/studies: the latest studies first, with their state and progress."""
        return await self._get_rows("/v1/studies", StudyOut)

    async def study_handle(self, study_id: str) -> AsyncStudyHandle:
        """A handle on an existing study, by id."""
        handle = AsyncStudyHandle(self, study_id)
        await handle.status()
        return handle

    async def cam_analysis(self, body: CamAnalysisIn) -> CamAnalysisOut:
        """POST /v1/cams/analysis."""
        return await self._post("/v1/cams/analysis", body, CamAnalysisOut)

    async def strength(self, body: StrengthSizingIn) -> StrengthSizingOut:
        """POST /v1/strength."""
        return await self._post("/v1/strength", body, StrengthSizingOut)

    async def cam_synthesis(self, body: CamSynthesisIn) -> CamSynthesisOut:
        """POST /v1/cams/synthesis."""
        return await self._post("/v1/cams/synthesis", body, CamSynthesisOut)

    async def cam_file(self, body: CamAnalysisIn | CamSynthesisIn,
                       format: Literal["png", "svg", "pdf", "csv", "dxf"] = "png") -> bytes:
        """The cam's figure, point table or profile drawing."""
        kind = "analysis" if isinstance(body, CamAnalysisIn) else "synthesis"
        return (await self._export(f"/v1/cams/{kind}", body, format)).content

    async def cam_laws(self) -> list[MotionLawOut]:
        """GET /v1/cams/laws."""
        return await self._get_rows("/v1/cams/laws", MotionLawOut)

    @property
    def library(self) -> AsyncLibraryClient:
        """The design library, as coroutines: save, history, revision, diff, sign-off, export and import."""
        return AsyncLibraryClient(self)

    async def session(self) -> SessionOut:
        """GET /v1/auth/session: whether authentication is on, and who this client acts as, with which roles."""
        return SessionOut.model_validate_json((await self._send("GET", "/v1/auth/session")).content)

    async def sign_in(self, name: str, password: str) -> SessionOut:
        """POST /v1/auth/signin: sign in with a name and password (a notebook without a token); the session cookie
        and its CSRF token go with every later request of this client."""
        body = SignInIn(name=name, password=password)
        out = SessionOut.model_validate_json(
            (await self._send("POST", "/v1/auth/signin", json=self._json(body))).content)
        self._csrf = out.csrf_token
        return out

    async def sign_out(self) -> None:
        """POST /v1/auth/signout: end this client's signed-in session."""
        await self._send("POST", "/v1/auth/signout")
        self._csrf = None

    async def users(self) -> list[UserOut]:
        """GET /v1/users (admins): every user with its roles."""
        return await self._get_rows("/v1/users", UserOut)

    async def user(self, name: str) -> UserOut:
        """GET /v1/users/{name} (admins)."""
        return UserOut.model_validate_json((await self._send("GET", f"/v1/users/{name}")).content)

    async def add_user(self, body: UserIn) -> UserOut:
        """POST /v1/users (admins): make a user with a password and roles."""
        return await self._post("/v1/users", body, UserOut)

    async def update_user(self, name: str, body: UserPatchIn) -> UserOut:
        """PATCH /v1/users/{name} (admins): a new password, new roles, or both."""
        response = await self._send("PATCH", f"/v1/users/{name}", json=self._json(body))
        return UserOut.model_validate_json(response.content)

    async def remove_user(self, name: str) -> None:
        """DELETE /v1/users/{name} (admins): the user and its tokens."""
        await self._send("DELETE", f"/v1/users/{name}")

    async def user_tokens(self, name: str) -> list[TokenOut]:
        """GET /v1/users/{name}/tokens (admins): a user's tokens, without their secrets."""
        return await self._get_rows(f"/v1/users/{name}/tokens", TokenOut)

    async def add_token(self, name: str, body: TokenIn) -> NewTokenOut:
        """POST /v1/users/{name}/tokens (admins): a new API token for a user, its secret shown this once."""
        return await self._post(f"/v1/users/{name}/tokens", body, NewTokenOut)

    async def revoke_token(self, token_id: int) -> None:
        """DELETE /v1/tokens/{token_id} (admins): revoke a token at once."""
        await self._send("DELETE", f"/v1/tokens/{token_id}")
