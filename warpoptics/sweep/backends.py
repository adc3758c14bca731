"""Sweep backends: where jobs run.  Each takes the job function and its payloads and yields the
results as they finish: in this process, in a process or thread pool, or on a Dask cluster.
The job function is a parameter (the runner's :func:`~warpoptics.sweep.runner.run_job`), so
that this module depends on nothing of the sweep; it must be importable by name in a worker
process (spawned pools and Dask pickle it by reference).
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections import deque
from collections.abc import Callable, Iterator
from dataclasses import dataclass

from ..errors import InputError

__all__ = ["LostJob", "local_results", "pool_results", "dask_results", "local_cluster"]


@dataclass(frozen=True)
class LostJob:
    """A job that no worker finished: its ``key``, ``index`` and the one-line ``reason`` (its
    worker process died, e.g. killed by the out-of-memory killer).  Backends yield it in place
    of the job's result."""

    key: str
    index: int
    reason: str


def local_results(fn: Callable[[dict], dict], payloads) -> Iterator[dict]:
    """``fn`` of each payload in turn, in this process."""
    for p in payloads:
        yield fn(p)


def pool_results(
    fn: Callable[[dict], dict], payloads, workers: int, kind: str, *, retries: int = 1
) -> Iterator[dict | LostJob]:
    """``fn`` of the payloads on a pool of ``workers``: ``kind`` "process" (spawned worker
    processes, :func:`_process_results`) or "thread".  A job whose worker process dies is run
    again ``retries`` times in a fresh worker, then yielded as a :class:`LostJob`."""
    if kind == "process":
        yield from _process_results(fn, payloads, workers, retries)
        return
    import concurrent.futures as cf

    ex = cf.ThreadPoolExecutor(max_workers=workers, thread_name_prefix="sweep")
    futures = []
    try:
        if payloads:
            # Warp modules load on this (the main) thread: the first job runs here
            yield fn(payloads[0])
            payloads = payloads[1:]
        futures = [ex.submit(fn, p) for p in payloads]
        for f in cf.as_completed(futures):
            yield f.result()
    finally:
        for f in futures:
            f.cancel()
        ex.shutdown(wait=True, cancel_futures=True)


def _die_with_parent(parent_pid: int) -> None:
    """Linux: have the kernel SIGKILL this process when its parent dies (``PR_SET_PDEATHSIG``),
    so that a sweep killed itself (SIGKILL, the out-of-memory killer) leaves no worker rendering
    on for nobody; elsewhere a worker ends after its job, when it finds its pipe closed."""
    if not sys.platform.startswith("linux"):
        return
    import ctypes

    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))  # 1: PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return
    if os.getppid() != parent_pid:  # the parent died before the request took effect
        os._exit(1)


def _worker_main(conn, fn: Callable[[dict], dict], parent_pid: int) -> None:
    """A pool worker: run ``fn`` on each payload received on ``conn`` and send back ``("ok",
    result)`` or ``("error", exception)``, until ``None`` or the parent's end closes."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's: it stops the workers
    _die_with_parent(parent_pid)
    while True:
        try:
            payload = conn.recv()
        except (EOFError, OSError):
            return  # the parent is gone
        if payload is None:
            return
        try:
            reply: tuple = ("ok", fn(payload))
        except Exception as exc:
            reply = ("error", exc)
        try:
            conn.send(reply)
        except (BrokenPipeError, EOFError, ConnectionResetError):
            return
        except Exception as exc:  # an exception that does not pickle: its text instead
            conn.send(("error", RuntimeError(f"{type(exc).__name__}: {exc}")))


def _death(exitcode: int | None) -> str:
    """Why a worker process ended, in words."""
    if exitcode is not None and exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = f"signal {-exitcode}"
        hint = " (what the out-of-memory killer sends)" if -exitcode == signal.SIGKILL else ""
        return f"its worker process was killed by {name}{hint}"
    return f"its worker process exited with status {exitcode} before finishing it"


@contextlib.contextmanager
def _children_ignore_sigint() -> Iterator[None]:
    """Processes started within start with SIGINT ignored (a disposition survives exec, and
    Python then installs no KeyboardInterrupt handler), so that Ctrl-C in a terminal, sent to the
    whole process group, reaches only this process, even while a child imports: one
    "interrupted" line, no traceback per worker; this process stops its workers itself.  A
    Ctrl-C pressed within is lost (only the main thread can change the handler)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:  # (None: a handler set outside Python, which cannot be restored: Python's own)
        signal.signal(signal.SIGINT, signal.default_int_handler if previous is None else previous)


class _Worker:
    """One spawned worker process and the parent's end of its pipe."""

    def __init__(self, ctx, fn):
        parent_end, child_end = ctx.Pipe(duplex=True)
        self.conn = parent_end
        self.job: int | None = None  # the payload index it is running
        self.process = ctx.Process(
            target=_worker_main, args=(child_end, fn, os.getpid()), name="warpoptics-sweep", daemon=True
        )
        try:
            with _children_ignore_sigint():
                self.process.start()
        finally:
            child_end.close()

    def stop(self, timeout: float) -> None:
        """End the process: ask an idle one to exit, terminate a busy one, kill what remains."""
        if self.job is None:
            with contextlib.suppress(OSError, ValueError):
                self.conn.send(None)
        elif self.process.is_alive():
            self.process.terminate()
        self.process.join(timeout)
        if self.process.is_alive():
            self.process.kill()
            self.process.join(timeout)
        self.conn.close()


def _process_results(fn, payloads, workers: int, retries: int) -> Iterator[dict | LostJob]:
    """The process pool: ``workers`` spawned processes, one job at a time each, over a pipe per
    worker.  The parent waits on the pipes and on the processes' sentinels together, so a worker
    that dies (SIGKILL, out of memory) is noticed at once: its job is queued again up to
    ``retries`` times (to a fresh worker), then yielded as a :class:`LostJob`; nothing waits on a
    process that is gone.  A job's exception is raised here, after the workers are stopped."""
    import multiprocessing
    from multiprocessing.connection import wait

    ctx = multiprocessing.get_context("spawn")
    queue = deque(range(len(payloads)))
    tries = [0] * len(payloads)
    pool: list[_Worker] = []
    try:
        while queue or any(w.job is not None for w in pool):
            busy = sum(w.job is not None for w in pool)
            while len(pool) < min(workers, busy + len(queue)):
                pool.append(_Worker(ctx, fn))
            for w in pool:
                if w.job is None and queue:
                    w.job = queue.popleft()
                    tries[w.job] += 1
                    with contextlib.suppress(OSError):  # a dead worker: its sentinel says so below
                        w.conn.send(payloads[w.job])
            ready = set(wait([w.conn for w in pool] + [w.process.sentinel for w in pool], timeout=5.0))
            for w in list(pool):
                reply = None
                if w.conn in ready:
                    with contextlib.suppress(EOFError, OSError):
                        reply = w.conn.recv()
                if reply is not None:
                    job, w.job = w.job, None
                    status, value = reply
                    if status == "error":
                        raise value
                    yield value
                elif w.conn in ready or w.process.sentinel in ready or not w.process.is_alive():
                    w.process.join(5.0)
                    w.conn.close()
                    pool.remove(w)
                    job = w.job
                    if job is None:
                        continue
                    if tries[job] <= retries:
                        queue.appendleft(job)  # again, in a fresh worker
                    else:
                        jd = payloads[job]["job"]
                        reason = f"{_death(w.process.exitcode)} (tried {tries[job]} times)"
                        yield LostJob(key=jd["key"], index=int(jd["index"]), reason=reason)
    finally:
        for w in pool:
            w.stop(timeout=10.0)


def _distributed(field: str):
    try:
        import distributed
    except ImportError:
        raise InputError(
            "Dask is not installed: pip install 'warpoptics[distributed]' (dask[distributed])", field=field
        ) from None
    return distributed


@contextlib.contextmanager
def local_cluster(n_workers: int) -> Iterator[str]:
    """A local Dask cluster of ``n_workers`` worker processes (one thread each), for as long as
    the ``with`` block lasts: yields its scheduler address.  Runs that share it (the cut
    optimizer's generations) keep their workers, with Warp started and the kernels loaded."""
    distributed = _distributed("--dask-local")
    with _children_ignore_sigint():  # the workers leave Ctrl-C to this process (it closes them)
        cluster = distributed.LocalCluster(
            n_workers=int(n_workers),
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,  # type: ignore[arg-type]  # dask documents None: no dashboard
            silence_logs=40,
        )
    try:
        yield str(cluster.scheduler_address)
    finally:
        cluster.close()


def dask_results(
    fn: Callable[[dict], dict], payloads, *, scheduler: str | None, dask_local: int | None
) -> Iterator[dict | LostJob]:
    """``fn`` of the payloads on the Dask scheduler at ``scheduler`` or on a local cluster of
    ``dask_local`` worker processes (one thread each, :func:`local_cluster`); a job Dask gives up
    on (``KilledWorker``: its workers died) is yielded as a :class:`LostJob`."""
    distributed = _distributed("--scheduler" if scheduler else "--dask-local")
    with contextlib.ExitStack() as stack:
        address = scheduler or stack.enter_context(local_cluster(int(dask_local or 1)))
        client = distributed.Client(address)
        stack.callback(client.close)
        futures = [
            client.submit(fn, p, key=f"warpoptics-job-{p['job']['key']}-{i}", pure=False)
            for i, p in enumerate(payloads)
        ]
        for fut in distributed.as_completed(futures):
            try:
                yield fut.result()
            except distributed.KilledWorker as exc:  # Dask gave up after its workers died on it
                job = payloads[futures.index(fut)]["job"]
                reason = f"the Dask workers that ran it died ({exc})".splitlines()[0]
                yield LostJob(key=job["key"], index=int(job["index"]), reason=reason)
