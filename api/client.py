"""Python client of the service: typed methods over the same pydantic models, against a URL or in-process.

>>> client = SynthClient("http://127.0.0.1:8000")          # a running service
>>> client = SynthClient.in_process()                       # the app in this process (tests, notebooks)
>>> out = client.analysis(AnalysisIn(mechanism=..., speed_rpm=300))

A problem response raises a :class:`ProblemError` subclass carrying the problem details.
"""

from __future__ import annotations

import warnings
from typing import Any, TypeVar

import httpx
from pydantic import BaseModel

from .schemas.analysis import AnalysisIn, AnalysisOut
from .schemas.balancing import (
    BalanceIn,
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
from .schemas.gearing import DriveIn, DriveOut, MotorOut, SplitIn, SplitOut, StageTypeOut, TeethIn, TeethOut
from .schemas.machine import MachineDesignOut, MachineIn
from .schemas.structure import StructureIn, StructureOut
from .schemas.train import TrainIn, TrainOut
from .schemas.synthesis import (
    CrankRockerIn,
    CrankRockerOut,
    PathIn,
    PathOut,
    SliderCrankSynthesisIn,
    SliderCrankSynthesisOut,
)
from .schemas.studies import StudyIn, StudyOut
from .study_client import StudyHandle

M = TypeVar("M", bound=BaseModel)


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


_BY_TYPE: dict[str, type[ProblemError]] = {
    "/problems/invalid-input": InvalidInputError,
    "/problems/not-assemblable": NotAssemblableError,
    "/problems/infeasible": InfeasibleError,
    "/problems/solver-failed": SolverFailedError,
    "/problems/solver-timeout": SolverTimeoutError,
    "/problems/too-large": TooLargeError,
}


class SynthClient:
    """Client of the mechanism synthesis service over a given ``httpx.Client`` or a base URL."""

    def __init__(self, base_url: str | None = None, *, http: httpx.Client | None = None, timeout_s: float = 60.0):
        if http is None and base_url is None:
            raise ValueError("give a base_url or an httpx.Client")
        self.http = http if http is not None else httpx.Client(base_url=base_url or "", timeout=timeout_s)

    @classmethod
    def in_process(cls, executor: str = "serial") -> SynthClient:
        """A client speaking to a fresh app in this process, without a network.

        Solver work runs in one background thread (``executor="serial"``), which works from any script or notebook;
        ``"pool"`` uses worker processes as the service does (a script then needs an ``if __name__ == "__main__"``
        guard, as every multiprocessing program does).
        """
        with warnings.catch_warnings():
            # starlette announces a future move of its test client to another HTTP library; ours speaks httpx.
            warnings.filterwarnings("ignore", message="Using `httpx` with `starlette.testclient`")
            from fastapi.testclient import TestClient

        from .app import create_app
        from .settings import Settings

        return cls(http=TestClient(create_app(Settings(executor=executor))))  # type: ignore[arg-type]

    def close(self) -> None:
        """Close the underlying HTTP client."""
        self.http.close()

    def __enter__(self) -> SynthClient:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

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
        cls = _BY_TYPE.get(str(body.get("type", "")), ProblemError)
        raise cls(response.status_code, body)

    def _post(self, path: str, body: BaseModel, out: type[M]) -> M:
        response = self.http.post(path, json=body.model_dump(mode="json", exclude_none=True))
        self._raise_for_problem(response)
        return out.model_validate_json(response.content)

    def _post_png(self, path: str, body: BaseModel, **params: Any) -> bytes:
        query = {"format": "png", **{k: v for k, v in params.items() if v is not None}}
        response = self.http.post(path, json=body.model_dump(mode="json", exclude_none=True), params=query)
        self._raise_for_problem(response)
        return response.content

    def health(self) -> dict[str, Any]:
        """GET /health."""
        response = self.http.get("/health")
        self._raise_for_problem(response)
        result: dict[str, Any] = response.json()
        return result

    def analysis(self, body: AnalysisIn) -> AnalysisOut:
        """POST /v1/analysis: the linkage's kinematic and kinetostatic picture over the cycle."""
        return self._post("/v1/analysis", body, AnalysisOut)

    def analysis_png(self, body: AnalysisIn, angle_deg: float | None = None) -> bytes:
        """POST /v1/analysis?format=png: driving torque, shaking force polar diagram, mechanism drawing."""
        return self._post_png("/v1/analysis", body, angle_deg=angle_deg)

    def machine_types(self) -> list[MachineTypeOut]:
        """GET /v1/machine-types: admissible coefficient of speed fluctuation per machine type."""
        response = self.http.get("/v1/machine-types")
        self._raise_for_problem(response)
        return [MachineTypeOut.model_validate(row) for row in response.json()]

    def flywheel(self, body: FlywheelIn) -> FlywheelOut:
        """POST /v1/flywheel: flywheel sizing by every method, each with its simulated delta."""
        return self._post("/v1/flywheel", body, FlywheelOut)

    def flywheel_png(self, body: FlywheelIn) -> bytes:
        """POST /v1/flywheel?format=png: energy-mass diagram with its tangents and the speed over the cycle."""
        return self._post_png("/v1/flywheel", body)

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
        response = self.http.get("/v1/gears/stage-types")
        self._raise_for_problem(response)
        return [StageTypeOut.model_validate(row) for row in response.json()]

    def gears_motors(self) -> list[MotorOut]:
        """GET /v1/gears/motors: the shipped motor catalogue."""
        response = self.http.get("/v1/gears/motors")
        self._raise_for_problem(response)
        return [MotorOut.model_validate(row) for row in response.json()]

    def balance_static(self, body: BalanceIn) -> BalanceOut:
        """POST /v1/balancing/static: counterweights that zero the shaking force."""
        return self._post("/v1/balancing/static", body, BalanceOut)

    def balance_full(self, body: FullBalanceIn) -> BalanceOut:
        """POST /v1/balancing/full: shaking force and moment zero (counterweights, pendulum coupler, counter-rotors)."""
        return self._post("/v1/balancing/full", body, BalanceOut)

    def balance_optimal(self, body: OptimalBalanceIn) -> OptimalBalanceOut:
        """POST /v1/balancing/optimal: weighted trade-off within a mass budget, with the trade-off curve."""
        return self._post("/v1/balancing/optimal", body, OptimalBalanceOut)

    def balance_png(self, mode: str, body: BalanceIn) -> bytes:
        """Before/after figure of a balancing mode (`static`, `full` or `optimal`)."""
        return self._post_png(f"/v1/balancing/{mode}", body)

    def balance_rotor(self, body: RotorIn) -> RotorOut:
        """POST /v1/balancing/rotor: single-plane static or two-plane dynamic rotor balance."""
        return self._post("/v1/balancing/rotor", body, RotorOut)

    def balance_slider_crank(self, body: SliderCrankBalanceIn) -> SliderCrankBalanceOut:
        """POST /v1/balancing/slider-crank: crank counterweight and Lanchester balancer."""
        return self._post("/v1/balancing/slider-crank", body, SliderCrankBalanceOut)

    def design_machine(self, body: MachineIn) -> MachineDesignOut:
        """POST /v1/machines/design: the whole machine, linkage to motor, checked by simulating it."""
        return self._post("/v1/machines/design", body, MachineDesignOut)

    def design_machine_png(self, body: MachineIn) -> bytes:
        """POST /v1/machines/design?format=png: the one-page summary of the design."""
        return self._post_png("/v1/machines/design", body)

    def design_report_pdf(self, body: MachineIn) -> bytes:
        """POST /v1/machines/design?format=pdf: the multi-page design report (with the alternatives when the
        request asks for them)."""
        response = self.http.post("/v1/machines/design", json=body.model_dump(mode="json", exclude_none=True),
                                  params={"format": "pdf"})
        self._raise_for_problem(response)
        return response.content

    def synthesise_crank_rocker(self, body: CrankRockerIn) -> CrankRockerOut:
        """POST /v1/synthesis/crank-rocker: the best crank-rocker for a rocker swing and a time ratio."""
        return self._post("/v1/synthesis/crank-rocker", body, CrankRockerOut)

    def synthesise_slider_crank(self, body: SliderCrankSynthesisIn) -> SliderCrankSynthesisOut:
        """POST /v1/synthesis/slider-crank: the best offset slider-crank for a stroke and a time ratio."""
        return self._post("/v1/synthesis/slider-crank", body, SliderCrankSynthesisOut)

    def synthesise_path(self, body: PathIn) -> PathOut:
        """POST /v1/synthesis/path: a four-bar whose coupler point passes through (or nearest to) the targets."""
        return self._post("/v1/synthesis/path", body, PathOut)

    def synthesis_png(self, kind: str, body: CrankRockerIn | SliderCrankSynthesisIn | PathIn) -> bytes:
        """Figure of a synthesis answer (`crank-rocker`, `slider-crank` or `path`): dead centres or coupler curve."""
        return self._post_png(f"/v1/synthesis/{kind}", body)

    def study(self, body: StudyIn) -> StudyHandle:
        """POST /v1/studies: start a design study; the handle follows, waits for, reads and cancels it."""
        # Sent whole: a null (objective_digits) means something here, unlike a left-out field elsewhere.
        response = self.http.post("/v1/studies", json=body.model_dump(mode="json"))
        self._raise_for_problem(response)
        return StudyHandle(self, StudyOut.model_validate_json(response.content))

    def study_handle(self, study_id: str) -> StudyHandle:
        """A handle on an existing study, by id (for example after a restart of this program)."""
        handle = StudyHandle(self, StudyOut.model_construct(id=study_id))
        handle.status()
        return handle
