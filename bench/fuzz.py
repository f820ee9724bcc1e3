"""schemathesis against a real server for a bounded time: every operation of the OpenAPI document, positive and
negative data, and every 5xx answer counted by operation.

``python -m bench.fuzz`` starts the service as it is deployed (``python -m api.serve``, 2 workers, loopback, a
scratch store) and runs schemathesis's command line (``st run``) on it for ``--minutes`` (10 by default): the
schema's examples, then requests drawn from each operation's schema, ``--examples`` per operation. It checks only
that no answer is a server error; the suite's ``tests/test_openapi_fuzz.py`` checks conformance to the document in
process, at a few examples per operation. A 504 that is the documented solver time-out (a problem saying how far
the work got) is counted apart: it is the one 5xx the service promises. It prints, per operation, the requests
sent and the 5xx received, and ends with the totals and the operations never reached in the time.
"""

from __future__ import annotations

import argparse
import base64
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import httpx

from bench.load import server


def _interactions(path: Path) -> list[tuple[str, int, bytes]]:
    """Each request of the run's ndjson report as (operation, status, answer's body); status 0 when no answer came."""
    out = []
    for line in path.read_text().splitlines():
        try:
            event = json.loads(line)
        except ValueError:
            continue
        finished = event.get("ScenarioFinished") if isinstance(event, dict) else None
        if not isinstance(finished, dict):
            continue
        label = str(finished.get("recorder", {}).get("label", "?"))
        for interaction in (finished.get("recorder", {}).get("interactions") or {}).values():
            response = interaction.get("response") if isinstance(interaction, dict) else None
            if not isinstance(response, dict):
                out.append((label, 0, b""))
                continue
            content = response.get("content") or {}
            body = base64.b64decode(content["$base64"]) if isinstance(content, dict) and "$base64" in content else b""
            out.append((label, int(response.get("status_code", 0)), body))
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--examples", type=int, default=12, help="generated requests per operation")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        env = {"SYNTH_STUDIES_DB": str(Path(tmp) / "store.sqlite")}
        with server(2, extra_env=env, module="api.serve") as (url, _pid):
            document = httpx.get(f"{url}/openapi.json", timeout=120).json()
            operations = [f"{method.upper()} {path}" for path, item in document["paths"].items()
                          for method in item if method in {"get", "post", "put", "patch", "delete"}]
            report = Path(tmp) / "events.ndjson"
            start = time.monotonic()
            subprocess.run([sys.executable, "-m", "schemathesis.cli", "run", f"{url}/openapi.json",
                            "--phases", "examples,fuzzing", "--max-examples", str(args.examples),
                            "--max-time", str(int(args.minutes * 60)), "--workers", "2",
                            "--checks", "not_a_server_error", "--continue-on-failure",
                            "--request-timeout", "60", "--report", "ndjson", "--report-ndjson-path", str(report),
                            "--suppress-health-check", "all", "--no-color"],
                           env={**os.environ}, stdout=subprocess.DEVNULL, check=False)
            took = time.monotonic() - start
            interactions = _interactions(report) if report.exists() else []
    sent: Counter[str] = Counter()
    server_errors: Counter[str] = Counter()
    timeouts: Counter[str] = Counter()
    unanswered: Counter[str] = Counter()
    for label, status, body in interactions:
        sent[label] += 1
        if status == 0:
            unanswered[label] += 1
        elif status == 504 and b"solver-timeout" in body:
            timeouts[label] += 1
        elif status >= 500:
            server_errors[label] += 1
    print(f"{'operation':52s} {'sent':>6s} {'5xx':>5s} {'504 time-out':>13s} {'no answer':>10s}")
    for label in sorted(sent):
        print(f"{label:52s} {sent[label]:6d} {server_errors[label]:5d} {timeouts[label]:13d} {unanswered[label]:10d}")
    never = sorted(set(operations) - set(sent))
    print(f"\n{sum(sent.values())} requests in {took / 60:.1f} min to {len(sent)} of {len(operations)} operations; "
          f"5xx: {sum(server_errors.values())}; documented 504 time-outs: {sum(timeouts.values())}; no answer: "
          f"{sum(unanswered.values())}; load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    if never:
        print("never reached: " + ", ".join(never))


if __name__ == "__main__":
    main()
