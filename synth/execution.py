"""Where solver work runs: in this process, on a local pool of worker processes, or on a Dask cluster.

Solves are CPU-bound, cvxpy problems are not thread-safe and IPOPT can crash when two solves share a process, so
solver work is a plain function of plain data submitted as a task. Three executors share one interface
(``submit(fn, *args, timeout=..., **kwargs) -> concurrent.futures.Future``) and give bit-identical results for the
same input, because every task runs the same function with BLAS limited to one thread:

- :class:`SerialExecutor` runs each task in one background thread of this process (tests, the engine as a library);
- :class:`LocalPoolExecutor` runs tasks on worker processes (the service's default, one per core), each watched by
  a thread of this process; a task past its timeout, or cancelled while running, has its worker killed and
  replaced; a worker that dies (segfault, out of memory, killed) is replaced whether it was idle or busy, and
  fails only its own task with :class:`WorkerLost`; background tasks (studies) run in a lane of their own;
- :class:`DaskExecutor` sends tasks to a ``distributed`` scheduler (a ``LocalCluster`` or ``Client(address)``).
"""

from __future__ import annotations

import atexit
import collections
import concurrent.futures as cf
import ctypes
import functools
import gc
import logging
import math
import multiprocessing
import multiprocessing.connection
import os
import resource
import threading
import time
import traceback
import weakref
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol, TypeVar

from .errors import SolverTimeout, SynthError, TooLarge, WorkerLost

T = TypeVar("T")
log = logging.getLogger("synth.execution")

# Read by OpenBLAS, MKL and OpenMP when a worker first loads them; threadpoolctl covers libraries loaded earlier.
_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS", "VECLIB_MAXIMUM_THREADS")


class Executor(Protocol):
    """Runs plain functions of plain data and answers with futures."""

    workers: int
    #: Tasks worth keeping submitted beyond one per worker, so that a worker that finishes starts the next task
    #: without waiting for this process to hear of it and send one: one for a local pool, one per worker where a
    #: task's dispatch and answer take a scheduler's round trips (Dask).
    spare_tasks: int

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None, prefer: str | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Schedule ``fn(*args, **kwargs)``; past ``timeout`` seconds of running, the task fails with SolverTimeout.
        ``prefer`` names the worker the task would rather run on (one that ran an earlier task of the same work
        and kept what it computed: a future's ``worker``), where the executor has named workers."""
        ...

    def share(self, value: Any) -> Any:
        """``value`` as an argument that many tasks take: on a cluster it is sent to every worker once and the
        tasks get a reference to it; elsewhere it is ``value`` itself."""
        ...

    def shutdown(self) -> None:
        """Stop accepting tasks and release the workers."""
        ...


def limit_threads() -> None:
    """Keep BLAS and OpenMP to one thread in this process: parallelism comes from workers, not threads."""
    for name in _THREAD_VARIABLES:
        os.environ[name] = "1"
    from threadpoolctl import threadpool_limits

    threadpool_limits(1)


# glibc's allocator hands arrays above its (dynamic) mmap threshold back to the kernel when they are freed, and
# trims the heap's free top; a cycle-sized array (a 9x9 system over 3600 angles is 2.3 MB) is then faulted in
# page by page on every request, which costs as much as the arithmetic on it. Workers keep such memory instead.
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
_KEEP_HEAP_BYTES = 64 * 2**20
_MMAP_ABOVE_BYTES = 16 * 2**20


@functools.cache
def keep_freed_memory() -> bool:
    """Ask glibc to reuse freed cycle-sized arrays instead of returning them to the kernel; False elsewhere."""
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError, TypeError):  # not glibc: nothing to tune
        return False
    return bool(mallopt(_M_TRIM_THRESHOLD, _KEEP_HEAP_BYTES)) and bool(mallopt(_M_MMAP_THRESHOLD, _MMAP_ABOVE_BYTES))


def _init_worker(memory_limit_bytes: int | None) -> None:
    limit_threads()
    keep_freed_memory()
    if memory_limit_bytes:
        # A runaway allocation ends in MemoryError inside the task instead of the machine's OOM killer.
        resource.setrlimit(resource.RLIMIT_AS, (memory_limit_bytes, memory_limit_bytes))


def run_task(fn: Callable[..., T], args: tuple[Any, ...], kwargs: dict[str, Any]) -> T:
    """Run one task the same way on every executor; memory exhaustion becomes a typed error."""
    try:
        return fn(*args, **kwargs)
    except MemoryError as exc:
        limit = resource.getrlimit(resource.RLIMIT_AS)[0]
        limit = limit if limit > 0 else 0
        raise TooLarge("worker memory [bytes]", limit, limit,
                       "the task ran out of memory in its worker; reduce the request's size") from exc
    finally:
        settle_heap()


@functools.cache
def settle_heap() -> None:
    """Once per process, after its first task: collect, then exempt every object alive (the imported engine,
    schemas and solvers, hundreds of thousands of objects kept for the process's life) from later collections.

    A task that keeps many objects alive at once (a study's batch keeps every variant's analysis until it
    answers) promotes them to the oldest generation, whose collection walks the whole heap: without this, those
    walks cost a batched study about a fifth of its time. Objects made later are collected as before.
    """
    gc.collect()
    gc.freeze()


class SerialExecutor:
    """One task at a time in one background thread of this process; timeouts are not enforced here."""

    workers = 1
    spare_tasks = 1

    def __init__(self) -> None:
        self._pool = cf.ThreadPoolExecutor(max_workers=1, thread_name_prefix="synth-serial")

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None, prefer: str | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Queue ``fn(*args, **kwargs)`` on the one thread."""
        return self._pool.submit(run_task, fn, args, kwargs)

    def share(self, value: Any) -> Any:
        """``value`` itself: the tasks run in this process."""
        return value

    def shutdown(self) -> None:
        """Finish the queued tasks and stop the thread."""
        self._pool.shutdown(wait=False, cancel_futures=True)


#: The lanes of a pool: requests someone is waiting for, and background work (design studies).
INTERACTIVE, BATCH = "interactive", "batch"
# How often a slot looks at a running task's cancellation and at an idle worker's life [s].
_POLL_S = 0.05
_IDLE_CHECK_S = 0.25
#: Longest a new worker is waited for to warm up before it is given tasks anyway [s].
WARM_LIMIT_S = 120.0


class _PoolFuture(cf.Future):  # type: ignore[type-arg]
    """A pool task's future: cancelling it while it runs stops its worker (a plain Future refuses that), and it
    records when its task left the queue (``started_at``, ``time.monotonic()`` seconds; None while queued) and
    the worker that took it (``worker``, its slot's name)."""

    def __init__(self) -> None:
        super().__init__()
        self.started_at: float | None = None
        self.worker: str | None = None

    def cancel(self) -> bool:
        with self._condition:
            if self._state == "FINISHED":
                return False
            if self._state in ("CANCELLED", "CANCELLED_AND_NOTIFIED"):
                return True
            self._state = "CANCELLED"
            self._condition.notify_all()
        self._invoke_callbacks()  # type: ignore[attr-defined]
        return True


@dataclass(slots=True, eq=False)
class _Task:
    fn: Callable[..., Any]
    args: tuple[Any, ...]
    kwargs: dict[str, Any]
    timeout: float | None
    future: _PoolFuture
    lane: str
    group: str
    prefer: str | None = None


class _Scheduler:
    """Tasks waiting for a worker: interactive ones first-in first-out, except that a worker takes the tasks that
    prefer it (or no worker) first, and one that prefers another worker only while that worker is busy (so that
    no worker idles while a task waits, and an idle worker takes the tasks meant for it); batch ones round-robin
    between their groups (a study's owner), first-in first-out within a group, and at most ``batch_cap`` running
    at once."""

    def __init__(self, batch_cap: int) -> None:
        self._cond = threading.Condition()
        self._interactive: collections.deque[_Task] = collections.deque()
        self._batch: dict[str, collections.deque[_Task]] = {}
        self.batch_cap = batch_cap
        self.batch_running = 0
        self.closed = False
        self._idle: set[str] = set()  # the workers waiting in take()

    def put(self, task: _Task) -> None:
        with self._cond:
            if self.closed:
                raise RuntimeError("the worker pool is shut down")
            if task.lane == INTERACTIVE:
                self._interactive.append(task)
            else:
                self._batch.setdefault(task.group, collections.deque()).append(task)
            self._cond.notify_all()

    def take(self, lanes: tuple[str, ...], timeout: float, worker: str | None = None) -> _Task | None:
        """The next task of the first of ``lanes`` that has one for ``worker``, marked running; None after
        ``timeout`` [s]."""
        deadline = time.monotonic() + timeout
        with self._cond:
            if worker is not None:
                self._idle.add(worker)
            try:
                while True:
                    task = self._pop(lanes, worker)
                    remaining = deadline - time.monotonic()
                    if task is not None or self.closed or remaining <= 0:
                        return task
                    self._cond.wait(remaining)
            finally:
                if worker is not None:
                    self._idle.discard(worker)
                if self._interactive:
                    self._cond.notify_all()  # the tasks that prefer it may now go to another

    def _pop(self, lanes: tuple[str, ...], worker: str | None) -> _Task | None:
        for lane in lanes:
            if lane == INTERACTIVE:
                queue = self._interactive
                while queue:
                    # a few tasks wait at most (the requests' slots): the scans cost nothing beside a task
                    k = next((i for i, t in enumerate(queue) if t.prefer is None or t.prefer == worker), None)
                    if k is None:
                        k = next((i for i, t in enumerate(queue) if t.prefer not in self._idle), None)
                    if k is None:
                        break  # each task waiting prefers another worker, which is idle and takes it
                    task = queue[k]
                    del queue[k]
                    if task.future.set_running_or_notify_cancel():
                        return task
            elif self.batch_running < self.batch_cap:
                while self._batch:
                    group = next(iter(self._batch))
                    queue = self._batch.pop(group)
                    task = queue.popleft()
                    if queue:
                        self._batch[group] = queue  # the group goes to the back: round robin
                    if task.future.set_running_or_notify_cancel():
                        self.batch_running += 1
                        return task
        return None

    def finished(self, task: _Task) -> None:
        if task.lane == BATCH:
            with self._cond:
                self.batch_running -= 1
                self._cond.notify_all()

    def queued(self) -> dict[str, int]:
        with self._cond:
            return {INTERACTIVE: len(self._interactive), BATCH: sum(len(q) for q in self._batch.values())}

    def close(self) -> list[_Task]:
        """Refuse new tasks; the tasks still waiting."""
        with self._cond:
            self.closed = True
            left = [*self._interactive, *(t for q in self._batch.values() for t in q)]
            self._interactive.clear()
            self._batch.clear()
            self._cond.notify_all()
            return left


#: The message a worker sends its slot once it has warmed up, before it is sent any task.
WARM = "warm"


def _warm(warm: Callable[[], object]) -> None:
    """Run the function that warms a worker up (imports, compiled programs); its failure is logged."""
    try:
        warm()
    except Exception:
        log.exception("warming the worker up with %s failed; it takes work without it",
                      getattr(warm, "__qualname__", warm))
    finally:
        settle_heap()


def _worker_main(conn: Any, memory_limit_bytes: int | None, nice: int,
                 warm: Callable[[], object] | None = None) -> None:
    """A worker process: warm up, say so, then run the tasks its slot sends, one at a time, and send back each
    outcome."""
    import signal

    # The web process decides when a worker stops (it kills it, or closes its pipe by exiting): Ctrl-C in a
    # terminal or a SIGTERM to the whole process group would otherwise end the workers under a service that is
    # still finishing its requests.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    if nice:
        os.nice(nice)
    _init_worker(memory_limit_bytes)
    if warm is not None:
        _warm(warm)
        try:
            conn.send(WARM)
        except (BrokenPipeError, ConnectionError):
            return
    while True:
        try:
            fn, args, kwargs = conn.recv()
            conn.send(None)  # received: from now on a death of this process is this task's
        except (EOFError, OSError):
            return  # the web process is gone
        try:
            outcome: tuple[bool, Any] = (True, run_task(fn, args, kwargs))
        except BaseException as exc:  # every outcome goes back; the worker lives on
            outcome = (False, _with_worker_traceback(exc))
        del fn, args, kwargs
        try:
            conn.send(outcome)
        except (BrokenPipeError, ConnectionError):
            return
        except Exception as exc:  # an answer or error that does not pickle
            conn.send((False, RuntimeError(f"the task's outcome could not be sent back "
                                           f"({type(exc).__name__}: {exc})")))
        del outcome


def _with_worker_traceback(exc: BaseException) -> BaseException:
    """``exc`` ready to go back to the web process: an unexpected one (not the engine's own, typed errors) carries
    the worker's traceback as text in ``worker_traceback`` (a traceback object does not pickle), so the web
    process's log shows where in the engine it arose."""
    if not isinstance(exc, SynthError):
        try:
            exc.worker_traceback = traceback.format_exc()  # type: ignore[attr-defined]
        except AttributeError:
            pass   # an exception type without a __dict__: it goes back without it
    return exc.with_traceback(None)


class _Slot:
    """One worker process and the thread that feeds it tasks, watches it, and replaces it whenever it dies."""

    def __init__(self, pool: LocalPoolExecutor, lanes: tuple[str, ...], nice: int, name: str,
                 warm_with: Callable[[], object] | None = None) -> None:
        self.pool = pool
        self.warm_with = warm_with
        self.lanes = lanes
        self.nice = nice
        self.process: Any = None
        self.conn: Any = None
        self.born = 0.0
        self.quick = 0
        self.busy = False
        self.warm = False
        self.thread = threading.Thread(target=self._loop, daemon=True, name=name)

    # -- the process -------------------------------------------------------------------------------------------
    def alive(self) -> bool:
        """The worker process is up (read without reaping it, so any thread may ask)."""
        process = self.process
        if process is None:
            return False
        try:
            return not multiprocessing.connection.wait([process.sentinel], 0)
        except (OSError, ValueError):
            return False

    def _spawn(self) -> bool:
        """Start a worker process; False (after a pause) when it cannot be started."""
        if self.pool.stopping:
            return False
        # Workers that keep dying as soon as they start, or cannot start, are not restarted in a tight loop.
        self.quick = self.quick + 1 if self.born and time.monotonic() - self.born < 1.0 else 0
        if self.quick >= 3:
            time.sleep(min(1.0, 0.1 * self.quick))
        self.born = time.monotonic()
        parent, child = self.pool.context.Pipe(duplex=True)
        process = self.pool.context.Process(target=_worker_main, args=(child, self.pool.memory_limit, self.nice,
                                                                       self.warm_with), daemon=True,
                                            name=self.thread.name)
        try:
            process.start()
        except Exception as exc:
            log.error("a worker process could not be started (%s: %s); trying again", type(exc).__name__, exc)
            parent.close()
            return False
        finally:
            child.close()
        self.process, self.conn, self.warm = process, parent, self.warm_with is None
        return True

    def _warming(self) -> None:
        """Wait a moment for the new worker to say it is warm; past WARM_LIMIT_S it is given tasks anyway (they
        wait in its pipe, their time starting when it takes them)."""
        ready = multiprocessing.connection.wait([self.conn, self.process.sentinel], _IDLE_CHECK_S)
        if self.conn in ready:
            try:
                self.warm = self.conn.recv() == WARM
            except (EOFError, OSError):
                return  # it died: the loop replaces it
        if time.monotonic() - self.born > WARM_LIMIT_S:
            self.warm = True

    def _retire(self) -> int | None:
        """Stop the worker (killing it if it still runs); its exit code."""
        process, conn = self.process, self.conn
        self.process = self.conn = None
        self.warm = False
        if process is None:
            return None
        if process.exitcode is None:
            process.kill()
        process.join(timeout=10)
        code: int | None = process.exitcode
        conn.close()
        try:
            process.close()
        except ValueError:
            pass  # not reaped yet: the system will
        return code

    def _replace(self) -> int | None:
        code = self._retire()
        if not self.pool.stopping:
            with self.pool.lock:
                self.pool.restarts += 1
            self._spawn()
        return code

    # -- the loop ----------------------------------------------------------------------------------------------
    def _loop(self) -> None:
        try:
            while not self.pool.stopping:
                if self.process is None:
                    self._spawn()
                    continue
                if not self.alive():
                    code = self._replace()
                    if not self.pool.stopping:
                        log.warning("an idle worker process died (exit code %s) and was replaced", code)
                    continue
                if not self.warm:
                    self._warming()
                    continue
                task = self.pool.scheduler.take(self.lanes, _IDLE_CHECK_S, self.thread.name)
                if task is None:
                    continue
                self.busy = True
                try:
                    self._run(task)
                finally:
                    self.busy = False
                    self.pool.scheduler.finished(task)
                    del task  # the answer is the future's alone
        finally:
            self._retire()

    def _run(self, task: _Task) -> None:
        future = task.future
        future.started_at = started = time.monotonic()
        future.worker = self.thread.name
        deadline = math.inf if task.timeout is None else started + task.timeout
        # A worker that dies before it has received the task (killed while idle, an instant before) costs the
        # task nothing: it goes to the replacement.
        for _ in range(3):
            if not self.alive():
                self._replace()
            if self.process is None:
                _settle(future, WorkerLost("no worker process could be started for the task"))
                return
            try:
                self.conn.send((task.fn, task.args, task.kwargs))
            except (BrokenPipeError, ConnectionError, EOFError):
                continue
            except Exception as exc:  # the task does not pickle: nothing was written
                _settle(future, exc)
                return
            if self._await(task, deadline):
                return
        _settle(future, WorkerLost("the worker processes died before they could receive the task"))

    def _await(self, task: _Task, deadline: float) -> bool:
        """Wait for the outcome of the task just sent and settle its future; False when the worker died before
        it received the task."""
        future = task.future
        conn, sentinel = self.conn, self.process.sentinel
        received = False
        # The task's own time starts when its worker has it (a new worker first sets itself up); until then a
        # worker that never answers is given a minute more.
        deadline = deadline + 60.0
        while True:
            now = time.monotonic()
            ready = multiprocessing.connection.wait([conn, sentinel], max(0.0, min(_POLL_S, deadline - now)))
            if conn in ready:
                try:
                    message = conn.recv()
                except (EOFError, OSError):
                    ready = [sentinel]
                except Exception as exc:  # an outcome that does not unpickle here
                    _settle(future, exc)
                    return True
                else:
                    if message == WARM:  # warmed up late, after it was given the task anyway
                        continue
                    if message is None:
                        received = True
                        if task.timeout is not None:
                            deadline = time.monotonic() + task.timeout
                        continue
                    ok, payload = message
                    _settle(future, None, payload) if ok else _settle(future, payload)
                    return True
            if sentinel in ready:
                code = self._replace()
                if not received:
                    return False
                _settle(future, WorkerLost(f"the worker process died while running the task (exit code {code})",
                                           exit_code=code))
                return True
            if future.cancelled() or self.pool.stopping:
                self._replace()
                _settle(future, WorkerLost("the worker pool stopped while the task ran"))
                return True
            if time.monotonic() >= deadline:
                self._replace()
                timeout = task.timeout or 0.0
                _settle(future, SolverTimeout(timeout, f"the task ran past its deadline of {timeout:.3g} s; "
                                                       "its worker was stopped"))
                return True


def _settle(future: cf.Future[Any], exc: BaseException | None, result: Any = None) -> None:
    try:
        if exc is not None:
            future.set_exception(exc)
        else:
            future.set_result(result)
    except cf.InvalidStateError:
        pass  # cancelled meanwhile by the caller


class LocalPoolExecutor:
    """Worker processes on this machine, forked from a fork server that preloads the engine, each fed by a
    supervising thread of this process that replaces its worker whenever it dies, idle or busy.

    Two lanes: ``workers`` processes for interactive tasks (``submit``) and ``batch_workers`` processes for
    background tasks (``lane(BATCH, group).submit``), the latter at a lower scheduling priority (``batch_nice``)
    so that the system gives the interactive workers the cores the moment they have work, and the batch workers
    every cycle they leave. With ``batch_workers=0`` both lanes share the ``workers`` processes: a free worker
    takes an interactive task first, and batch tasks hold at most all but one of them.

    Parameters
    ----------
    workers
        Number of interactive worker processes [-]; each runs one task at a time.
    memory_limit_mb
        Address-space limit of each worker [MiB]; ``None`` for none.
    preload
        Modules the fork server imports besides the engine (those the tasks' functions live in).
    warm
        The function every request worker runs once when it starts, before it is given a task (its
        programs built and exercised, so that its first task pays nothing for them); None for none. The batch
        workers do not: a study's first task pays once what its many variants share.
    batch_workers
        Number of batch worker processes [-]; 0 to share the interactive ones.
    batch_nice
        Niceness added to the batch workers [-] (0..19).
    """

    def __init__(self, workers: int, memory_limit_mb: int | None = None, preload: Sequence[str] = (),
                 batch_workers: int = 0, batch_nice: int = 19, warm: Callable[[], object] | None = None) -> None:
        if workers < 1 or batch_workers < 0:
            raise ValueError("a worker pool needs at least one worker")
        self.workers = workers
        self.spare_tasks = 1
        self.batch_workers = batch_workers
        self.context = multiprocessing.get_context("forkserver")
        # Forked from a server that imported the engine once: a replaced worker is ready in milliseconds.
        self.context.set_forkserver_preload(["numpy", "scipy.linalg", "synth", *preload])
        self.memory_limit = memory_limit_mb * 2**20 if memory_limit_mb else None
        self.warm = warm
        self.lock = threading.Lock()
        self.restarts = 0
        self.stopping = False
        shared = batch_workers == 0
        self.scheduler = _Scheduler(max(1, workers - 1) if shared else batch_workers)
        # only the request workers warm up: a study's first task pays once what thousands of variants share
        self._slots = [_Slot(self, (INTERACTIVE, BATCH) if shared else (INTERACTIVE,), 0, f"synth-worker-{k}", warm)
                       for k in range(workers)]
        self._slots += [_Slot(self, (BATCH,), batch_nice, f"synth-batch-{k}") for k in range(batch_workers)]
        for slot in self._slots:
            slot.thread.start()
        # At exit multiprocessing sends the workers SIGTERM, which they ignore, and then waits for them while this
        # process still holds their pipes: a pool left running would hold the interpreter's exit for ever.
        atexit.register(_shutdown_at_exit, weakref.ref(self))

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None, prefer: str | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Schedule ``fn(*args, **kwargs)`` on an interactive worker, the worker named ``prefer`` (a future's
        ``worker``) rather than another when both could take it; errors come back as the engine's typed
        errors."""
        return self._put(INTERACTIVE, "", fn, args, kwargs, timeout, prefer)

    def share(self, value: Any) -> Any:
        """``value`` itself: a task's arguments reach its worker through one pipe either way."""
        return value

    def lane(self, lane: str, group: str = "") -> Executor:
        """This pool as seen by one ``group`` (an owner) of the ``lane`` (``BATCH``); an Executor of its own."""
        return _Lane(self, lane, group)

    def _put(self, lane: str, group: str, fn: Callable[..., T], args: tuple[Any, ...], kwargs: dict[str, Any],
             timeout: float | None, prefer: str | None = None) -> cf.Future[T]:
        future = _PoolFuture()
        self.scheduler.put(_Task(fn, args, kwargs, timeout, future, lane, group, prefer))
        return future

    def status(self) -> dict[str, Any]:
        """Workers up per lane, the restarts since the start, the tasks waiting; never waits on a worker."""
        queued = self.scheduler.queued()
        interactive = self._slots[:self.workers]
        batch = self._slots[self.workers:]
        return {
            "workers_alive": sum(s.alive() for s in interactive),
            "workers_warm": sum(s.warm and s.alive() for s in interactive),
            "batch_workers": self.batch_workers,
            "batch_workers_alive": sum(s.alive() for s in batch),
            "worker_restarts": self.restarts,
            "tasks_queued": queued[INTERACTIVE],
            "batch_tasks_queued": queued[BATCH],
            "batch_tasks_running": self.scheduler.batch_running,
        }

    def wait_warm(self, timeout: float) -> bool:
        """Wait until every request worker is up and warm, at most ``timeout`` [s]; whether they are."""
        end = time.monotonic() + timeout
        while not all(s.warm and s.alive() for s in self._slots[:self.workers]):
            if time.monotonic() >= end or self.stopping:
                return False
            time.sleep(0.05)
        return True

    def pids(self) -> list[int]:
        """Process ids of the workers now up (interactive first)."""
        return [s.process.pid for s in self._slots if s.process is not None and s.alive()]

    def shutdown(self) -> None:
        """Stop the workers, killing any task still running; tasks still waiting are cancelled."""
        self.stopping = True
        for task in self.scheduler.close():
            task.future.cancel()
        for slot in self._slots:
            slot.thread.join(timeout=15)
        for slot in self._slots:  # a slot thread that did not finish in time leaves its worker to this
            process = slot.process
            if process is not None and process.exitcode is None:
                process.kill()


def _shutdown_at_exit(ref: weakref.ReferenceType[LocalPoolExecutor]) -> None:
    pool = ref()
    if pool is not None and not pool.stopping:
        pool.shutdown()


class _Lane:
    """One lane and group of a :class:`LocalPoolExecutor`, as an Executor."""

    def __init__(self, pool: LocalPoolExecutor, lane: str, group: str) -> None:
        self.pool = pool
        self.lane_name = lane
        self.group = group
        self.workers = (pool.batch_workers or pool.scheduler.batch_cap) if lane == BATCH else pool.workers
        self.spare_tasks = pool.spare_tasks

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None, prefer: str | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Schedule ``fn(*args, **kwargs)`` in this lane."""
        return self.pool._put(self.lane_name, self.group, fn, args, kwargs, timeout, prefer)

    def share(self, value: Any) -> Any:
        """``value`` itself, as the pool shares it."""
        return self.pool.share(value)

    def shutdown(self) -> None:
        """Nothing to stop: the pool is shared."""


class DaskExecutor:
    """Tasks on a Dask.distributed cluster: ``address`` of a scheduler, or an existing ``distributed.Client``.

    A running task cannot be interrupted on a Dask worker, so ``timeout`` is enforced by failing the future;
    studies keep tasks short (0.2-2 s) so a cancel takes effect within one task. A task's dispatch and its answer
    each take round trips through the scheduler (milliseconds to tens of them), so a task is kept queued behind
    each running one (``spare_tasks``) and what every task of a study takes is sent to the workers once
    (:meth:`share`).
    """

    def __init__(self, address: str | None = None, client: Any = None) -> None:
        from distributed import Client

        self._own = client is None
        if client is None:
            client = Client(address, set_as_default=False)  # type: ignore[no-untyped-call]
        self.client = client
        self.workers = max(1, sum(w.get("nthreads", 1) for w in self.client.scheduler_info()["workers"].values()))
        self.spare_tasks = self.workers

    def share(self, value: Any) -> Any:
        """``value`` scattered to every worker once; tasks given the returned future get ``value`` there. The
        cluster lets go of it when the future is dropped."""
        # in a list, so that a dict or a list is scattered whole rather than item by item
        return self.client.scatter([value], broadcast=True, hash=False)[0]

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None, prefer: str | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Send ``fn(*args, **kwargs)`` to the cluster (the scheduler places it; ``prefer`` is not used); the answer
        is bridged into a concurrent future."""
        remote = self.client.submit(_run_on_dask, fn, args, kwargs, pure=False)
        outer = _DaskLinked(remote)
        if timeout is not None:
            outer.timer = threading.Timer(timeout, _expire, args=(outer, timeout))
            outer.timer.daemon = True
            outer.timer.start()

        def done(f: Any) -> None:
            try:
                if outer.done():
                    return
                if f.status == "finished":
                    outer.set_result(f.result())
                elif f.status == "cancelled":
                    outer.cancel()
                else:
                    outer.set_exception(f.exception())
            except (cf.InvalidStateError, cf.CancelledError):
                pass
            finally:
                outer.release()

        remote.add_done_callback(done)
        return outer

    def shutdown(self) -> None:
        """Close the client if this executor opened it."""
        if self._own:
            self.client.close()


def _run_on_dask(fn: Callable[..., T], args: tuple[Any, ...], kwargs: dict[str, Any]) -> T:
    _dask_worker_ready()
    return run_task(fn, args, kwargs)


@functools.cache
def _dask_worker_ready() -> None:
    """Once per Dask worker process, what a pool's worker does when it starts: BLAS on one thread (threadpoolctl
    looks through every loaded library, milliseconds a call) and freed arrays kept."""
    limit_threads()
    keep_freed_memory()


class _DaskLinked(cf.Future):  # type: ignore[type-arg]
    """A future bridged from a Dask future; once settled it lets go of the Dask future (so the cluster frees the
    answer) and stops its deadline timer (which would otherwise hold the answer until it fires)."""

    def __init__(self, remote: Any) -> None:
        super().__init__()
        self._remote: Any = remote
        self.timer: threading.Timer | None = None

    def cancel(self) -> bool:
        if self._remote is not None:
            self._remote.cancel()
        return super().cancel()

    def release(self) -> None:
        """Drop the Dask future and the timer once this future is settled."""
        self._remote = None
        if self.timer is not None:
            self.timer.cancel()
            self.timer = None


def _expire(outer: cf.Future[Any], timeout: float) -> None:
    if not outer.done():
        try:
            outer.set_exception(SolverTimeout(timeout, f"the task ran past its deadline of {timeout:.3g} s"))
        except cf.InvalidStateError:
            pass


def make_executor(kind: str, workers: int = 0, dask_address: str | None = None,
                  memory_limit_mb: int | None = None, preload: Sequence[str] = (), batch_workers: int = 0,
                  batch_nice: int = 19, warm: Callable[[], object] | None = None) -> Executor:
    """An executor by name: ``serial``, ``pool`` (``workers`` processes; 0 means one per core; and
    ``batch_workers`` for background tasks) or ``dask``."""
    if kind == "serial":
        return SerialExecutor()
    if kind == "pool":
        return LocalPoolExecutor(workers or os.cpu_count() or 1, memory_limit_mb, preload, batch_workers,
                                 batch_nice, warm)
    if kind == "dask":
        return DaskExecutor(dask_address)
    raise ValueError(f"unknown executor {kind!r}; expected serial, pool or dask")
