"""Sweep backends: where jobs run.  Each takes the job function and its payloads and yields the
results as they finish: in this process, in a process or thread pool, or on a Dask cluster.
The job function is a parameter (the runner's :func:`~warpoptics.sweep.runner.run_job`), so
that this module depends on nothing of the sweep; it must be importable by name in a worker
process (spawned pools and Dask pickle it by reference).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator

from ..errors import InputError

__all__ = ["local_results", "pool_results", "dask_results", "local_cluster"]


def local_results(fn: Callable[[dict], dict], payloads) -> Iterator[dict]:
    """``fn`` of each payload in turn, in this process."""
    for p in payloads:
        yield fn(p)


def pool_results(fn: Callable[[dict], dict], payloads, workers: int, kind: str) -> Iterator[dict]:
    """``fn`` of the payloads on a pool of ``workers``: ``kind`` "process" (spawned) or "thread"."""
    import concurrent.futures as cf
    import multiprocessing

    ex: cf.Executor
    if kind == "process":
        ex = cf.ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"))
    else:
        ex = cf.ThreadPoolExecutor(max_workers=workers, thread_name_prefix="sweep")
    futures = []
    try:
        if kind == "thread" and payloads:
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
) -> Iterator[dict]:
    """``fn`` of the payloads on the Dask scheduler at ``scheduler`` or on a local cluster of
    ``dask_local`` worker processes (one thread each, :func:`local_cluster`)."""
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
            yield fut.result()
