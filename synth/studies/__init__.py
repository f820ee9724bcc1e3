"""Design studies: many variants of one request, run on any executor, kept by a store outside the engine
(through the :class:`StudyStore` interface), with a Pareto front.

::

    Study (base request + parameters + metrics + objectives + constraints)
      -> Sampler: parameter values by variant index (grid, random, Latin hypercube; seeded)
      -> run_study: batches of variants as tasks of 0.2-2 s on an executor, about one per worker in flight
      -> a sink (StudyStore.write_rows of the store outside the engine): each finished batch's rows at once
      -> pareto_mask: the non-dominated feasible variants
"""

from .model import DEFAULT_MAX_VARIANTS, StudyConstraint, StudyParameter, Study, study_from_dict
from .paths import get_path, set_path
from .pareto import pareto_mask, quantise
from .runner import BatchFn, BatchSpec, RunReport, VariantRow, run_batch, run_study, run_variant
from .sampling import Sampler, variant_request
from .store import StudyRecord, StudyStore

__all__ = [
    "DEFAULT_MAX_VARIANTS",
    "BatchFn",
    "BatchSpec",
    "StudyConstraint",
    "StudyParameter",
    "RunReport",
    "Sampler",
    "Study",
    "StudyRecord",
    "StudyStore",
    "VariantRow",
    "get_path",
    "pareto_mask",
    "quantise",
    "run_batch",
    "run_study",
    "run_variant",
    "set_path",
    "study_from_dict",
    "variant_request",
]
