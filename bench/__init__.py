"""Benchmarks: each module prints medians and the ratio to a baseline measured in the same run.

BLAS runs one thread, as in the service's worker processes (one per core): a threaded BLAS spinning after a
small factorisation would time the machine's scheduler, not the code. Set before numpy is first imported.
"""

import os

for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")
