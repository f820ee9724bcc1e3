"""Where solver work runs: in this process, on a local pool of worker processes, or on a Dask cluster.

Solves are CPU-bound, cvxpy problems are not thread-safe and IPOPT can crash when two solves share a process, so
solver work is a plain function of plain data submitted as a task. Three executors share one interface
(``submit(fn, *args, timeout=..., **kwargs) -> concurrent.futures.Future``) and give bit-identical results for the
same input, because every task runs the same function with BLAS limited to one thread:

- :class:`SerialExecutor` runs each task in one background thread of this process (tests, the engine as a library);
- :class:`LocalPoolExecutor` runs tasks on worker processes (the service's default, one per core); a task past its
  timeout, or cancelled while running, has its worker killed and replaced, and a worker that dies (segfault, out
  of memory) fails only its own task with :class:`WorkerLost`;
- :class:`DaskExecutor` sends tasks to a ``distributed`` scheduler (a ``LocalCluster`` or ``Client(address)``).
"""

from __future__ import annotations

import concurrent.futures as cf
import ctypes
import functools
import gc
import multiprocessing
import os
import resource
import threading
from collections.abc import Callable, Sequence
from typing import Any, Protocol, TypeVar

from .errors import SolverTimeout, TooLarge, WorkerLost

T = TypeVar("T")

# Read by OpenBLAS, MKL and OpenMP when a worker first loads them; threadpoolctl covers libraries loaded earlier.
_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS", "VECLIB_MAXIMUM_THREADS")


class Executor(Protocol):
    """Runs plain functions of plain data and answers with futures."""

    workers: int

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Schedule ``fn(*args, **kwargs)``; past ``timeout`` seconds of running, the task fails with SolverTimeout."""
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

    def __init__(self) -> None:
        self._pool = cf.ThreadPoolExecutor(max_workers=1, thread_name_prefix="synth-serial")

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Queue ``fn(*args, **kwargs)`` on the one thread."""
        return self._pool.submit(run_task, fn, args, kwargs)

    def shutdown(self) -> None:
        """Finish the queued tasks and stop the thread."""
        self._pool.shutdown(wait=False, cancel_futures=True)


class LocalPoolExecutor:
    """Worker processes on this machine (pebble's ProcessPool), started from a fork server that preloads the engine.

    Parameters
    ----------
    workers
        Number of worker processes [-]; each runs one task at a time.
    memory_limit_mb
        Address-space limit of each worker [MiB]; ``None`` for none.
    preload
        Modules the fork server imports besides the engine (those the tasks' functions live in).
    """

    def __init__(self, workers: int, memory_limit_mb: int | None = None, preload: Sequence[str] = ()) -> None:
        import pebble

        if workers < 1:
            raise ValueError("a worker pool needs at least one worker")
        self.workers = workers
        context = multiprocessing.get_context("forkserver")
        # Forked from a server that imported the engine once: a replaced worker is ready in milliseconds.
        context.set_forkserver_preload(["numpy", "scipy.linalg", "synth", *preload])
        limit = memory_limit_mb * 2**20 if memory_limit_mb else None
        self._pool = pebble.ProcessPool(max_workers=workers, initializer=_init_worker, initargs=(limit,),
                                        context=context)
        self._lock = threading.Lock()

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Schedule ``fn(*args, **kwargs)`` on a worker; errors come back as the engine's typed errors."""
        with self._lock:
            inner = self._pool.schedule(run_task, args=(fn, args, kwargs), timeout=timeout)
        outer = _Linked(inner)
        inner.add_done_callback(lambda f: _settle(f, outer, timeout))
        return outer

    def shutdown(self) -> None:
        """Stop the workers, killing any task still running."""
        self._pool.stop()  # type: ignore[no-untyped-call]
        self._pool.join(timeout=5)


class _Linked(cf.Future):  # type: ignore[type-arg]
    """A future whose cancellation reaches the pool's future (which kills a running worker).

    The pool's future keeps its done-callback, which refers to this one: once settled, this future lets go of
    the pool's, or the pair would be a reference cycle holding the task's answer (megabytes of JSON) until the
    cyclic garbage collector happens to run.
    """

    def __init__(self, inner: cf.Future[Any]) -> None:
        super().__init__()
        self._inner: cf.Future[Any] | None = inner

    def cancel(self) -> bool:
        if self._inner is not None:
            self._inner.cancel()
        return super().cancel()

    def release(self) -> None:
        """Drop the link to the pool's future once this one is settled."""
        self._inner = None


def _settle(inner: cf.Future[Any], outer: _Linked, timeout: float | None) -> None:
    try:
        _transfer(inner, outer, timeout)
    finally:
        outer.release()


def _transfer(inner: cf.Future[Any], outer: cf.Future[Any], timeout: float | None) -> None:
    import pebble

    if outer.done():
        return
    if inner.cancelled():
        outer.cancel()
        return
    exc = inner.exception()
    if isinstance(exc, cf.TimeoutError):
        exc = SolverTimeout(timeout or 0.0, f"the task ran past its deadline of {timeout or 0:.3g} s; "
                                             "its worker was stopped")
    elif isinstance(exc, pebble.ProcessExpired):
        exc = WorkerLost(f"the worker process died while running the task (exit code {exc.exitcode})",
                         exit_code=exc.exitcode)
    try:
        if exc is not None:
            outer.set_exception(exc)
        else:
            outer.set_result(inner.result())
    except cf.InvalidStateError:
        pass  # cancelled meanwhile by the caller


class DaskExecutor:
    """Tasks on a Dask.distributed cluster: ``address`` of a scheduler, or an existing ``distributed.Client``.

    A running task cannot be interrupted on a Dask worker, so ``timeout`` is enforced by failing the future;
    studies keep tasks short (0.2-2 s) so a cancel takes effect within one task.
    """

    def __init__(self, address: str | None = None, client: Any = None) -> None:
        from distributed import Client

        self._own = client is None
        if client is None:
            client = Client(address, set_as_default=False)  # type: ignore[no-untyped-call]
        self.client = client
        self.workers = max(1, sum(w.get("nthreads", 1) for w in self.client.scheduler_info()["workers"].values()))

    def submit(self, fn: Callable[..., T], /, *args: Any, timeout: float | None = None,
               **kwargs: Any) -> cf.Future[T]:
        """Send ``fn(*args, **kwargs)`` to the cluster; the answer is bridged into a concurrent future."""
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
    limit_threads()
    keep_freed_memory()
    return run_task(fn, args, kwargs)


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
                  memory_limit_mb: int | None = None, preload: Sequence[str] = ()) -> Executor:
    """An executor by name: ``serial``, ``pool`` (``workers`` processes; 0 means one per core) or ``dask``."""
    if kind == "serial":
        return SerialExecutor()
    if kind == "pool":
        return LocalPoolExecutor(workers or os.cpu_count() or 1, memory_limit_mb, preload)
    if kind == "dask":
        return DaskExecutor(dask_address)
    raise ValueError(f"unknown executor {kind!r}; expected serial, pool or dask")
