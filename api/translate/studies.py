"""Studies: the stored study, its variants, results and Pareto front as the wire shows them."""

from __future__ import annotations

import synth

from mechsynth_client.schemas.studies import ParetoOut, ResultsOut, StudyIn, StudyLinks, StudyOut, VariantOut


def study_from(body: StudyIn) -> synth.Study:
    """The engine's study (checks paths, objectives and constraints against the metrics)."""
    return synth.study_from_dict(body.model_dump())


def study_out(r: synth.StudyRecord, position: int | None = None) -> StudyOut:
    """Schema from the stored study, with its place in the queue while it waits."""
    base = f"/v1/studies/{r.id}"
    return StudyOut(id=r.id, name=r.spec.get("name"), endpoint=r.spec["endpoint"],
                    state=r.state,  # type: ignore[arg-type]
                    total=r.total, done=r.done, failed=r.failed, elapsed_s=round(r.elapsed_s, 3),
                    eta_s=None if r.eta_s is None else round(r.eta_s, 1), created_at=r.created_at, message=r.message,
                    links=StudyLinks(self=base, results=f"{base}/results", pareto=f"{base}/pareto"),
                    owner=str(r.spec.get("owner") or "anonymous"),
                    position=position if r.state == "queued" else None)


def variant_out(row: synth.VariantRow, paths: list[str], metrics: list[str]) -> VariantOut:
    """Schema from a stored row."""
    return VariantOut(index=row.index, parameters=dict(zip(paths, row.values)),
                      metrics=None if row.metrics is None else dict(zip(metrics, row.metrics)),
                      feasible=row.feasible, problem_type=None if row.ok else f"/problems/{row.problem_type}",
                      detail=row.detail)


def results_out(r: synth.StudyRecord, rows: list[synth.VariantRow], offset: int, limit: int) -> ResultsOut:
    """Schema from a stored page of rows."""
    paths, metrics = _columns(r)
    return ResultsOut(id=r.id, total=r.total, done=r.done, offset=offset, limit=limit, parameters=paths,
                      metrics=metrics, variants=[variant_out(row, paths, metrics) for row in rows])


def pareto_out(r: synth.StudyRecord, candidates: int, rows: list[synth.VariantRow]) -> ParetoOut:
    """Schema from the rows on the front."""
    paths, metrics = _columns(r)
    return ParetoOut(id=r.id, objectives=r.spec["objectives"], candidates=candidates,
                     front=[variant_out(row, paths, metrics) for row in rows])


def _columns(r: synth.StudyRecord) -> tuple[list[str], list[str]]:
    return [p["path"] for p in r.spec["parameters"]], list(r.spec["metrics"])
