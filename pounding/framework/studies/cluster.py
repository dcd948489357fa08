"""Running many independent analyses: in this process or on a dask.distributed cluster.

Shared by ``pounding sweep`` and ``pounding fragility``. A study is a list of
jobs ``(tag, args)``; :func:`run_jobs` calls ``fn(*args)`` for each and hands
``(tag, value)`` to ``done`` as each completes, in completion order. Large
inputs used by many jobs (a scene, a record) are passed once per worker:
put them in ``shared`` and refer to them in ``args`` by :class:`Shared`.

Scheduling: serial in this process, a local cluster of worker processes (one
per core by default: the runs are CPU-bound Python and numba code that would
hold the GIL in threads) or an existing cluster by scheduler address. ``fn``
should not raise (it records its own failure); if a job cannot run at all (a
worker died, the task could not be unpickled) ``failed(tag, exc)`` is called
and the study goes on.
"""

from __future__ import annotations

import logging
import os
import time
from dataclasses import dataclass

from pounding.errors import InputError

__all__ = ["Shared", "run_jobs"]


@dataclass(frozen=True)
class Shared:
    """A reference, inside a job's arguments, to ``shared[key]``."""

    key: str


def _resolve(args, shared):
    return tuple(shared[a.key] if isinstance(a, Shared) else a for a in args)


def run_jobs(fn, jobs, done, failed, *, shared=None, serial: bool = False, workers: int | None = None,
             scheduler: str | None = None, name: str = "pounding-job") -> int:
    """Run ``fn(*args)`` for every ``(tag, args)`` of ``jobs``; returns the number of Dask workers (0: serial).

    Parameters
    ----------
    fn : callable
        Importable at module level (it is sent to the workers by reference).
    jobs : list of (tag, tuple)
    done : callable(tag, value)
        Called in this process as each job completes.
    failed : callable(tag, exc)
        Called when a job could not run on the cluster.
    shared : dict, optional
        Objects referred to by :class:`Shared` in the arguments; scattered
        once to the cluster.
    serial : run in this process, without Dask
    workers : worker processes of the local cluster (default: the number of cores)
    scheduler : address of an existing dask.distributed scheduler (``tcp://host:port``)
    name : prefix of the task keys on the cluster

    Notes
    -----
    The local cluster starts worker processes with ``spawn``: a script that
    calls this must do so under ``if __name__ == "__main__":``.
    """
    shared = dict(shared or {})
    if serial:
        for tag, args in jobs:
            done(tag, fn(*_resolve(args, shared)))
        return 0
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError as exc:  # the 'parallel' extra
        raise InputError(f"parallel runs need dask[distributed] (pip install 'pounding[parallel]'), or use --serial: {exc}",
                         field="--scheduler" if scheduler else "--workers") from None
    if not jobs:
        return 0
    cluster = None
    if scheduler:
        try:
            client = Client(scheduler, timeout=30)
        except (OSError, TimeoutError) as exc:
            raise InputError(f"cannot reach the scheduler {scheduler!r}: {exc}", field="--scheduler") from None
    else:
        n = workers or os.cpu_count() or 1
        # no dashboard; the scheduler's HTTP server (metrics) on a free port, not on a possibly taken 8787
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                               scheduler_kwargs={"dashboard_address": ":0"}, silence_logs=logging.CRITICAL)
        client = Client(cluster)
    try:
        n_workers = len(client.nthreads())
        scattered = {key: client.scatter(obj, broadcast=False, hash=False) for key, obj in shared.items()}
        futures = {}
        stamp = f"{os.getpid()}-{time.time_ns()}"
        for i, (tag, args) in enumerate(jobs):
            fut = client.submit(fn, *_resolve(args, scattered), pure=False, key=f"{name}-{i}-{stamp}")
            futures[fut] = tag
        for fut in as_completed(futures):
            tag = futures[fut]
            try:
                value = fut.result()
            except Exception as exc:  # noqa: BLE001 - a worker died or the task could not run
                failed(tag, exc)
                continue
            done(tag, value)
        return n_workers
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
