"""Command-line options of the commands that run many analyses on Dask (``sweep``, ``fragility``)."""

from __future__ import annotations

import argparse

from pounding.errors import InputError


def add_cluster_options(p: argparse.ArgumentParser) -> None:
    """``--workers``, ``--scheduler`` and ``--serial``: where the runs execute."""
    p.add_argument("--workers", type=int, default=None, metavar="N", help="worker processes of the local cluster (default: the number of cores)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS", help="use an existing dask.distributed scheduler (tcp://host:port)")
    p.add_argument("--serial", action="store_true", help="run in this process, without Dask")


def check_cluster_options(args: argparse.Namespace) -> None:
    """Refuse contradictory choices (InputError naming the option)."""
    if args.workers is not None and args.workers < 1:
        raise InputError(f"expected a positive number of workers, got {args.workers}", field="--workers")
    if args.serial and (args.scheduler or args.workers):
        raise InputError("--serial runs without Dask: drop --scheduler/--workers", field="--serial")
    if args.scheduler and args.workers:
        raise InputError("--workers sizes the local cluster; an existing cluster (--scheduler) has its own workers", field="--workers")
