"""Where sweep tasks run: in-process, local processes, or a Dask cluster — same numbers everywhere.

An executor takes a list of tasks ``(key, function, args)`` and yields
``(key, result)`` as tasks finish, in any order; the engine puts results back
in trial order, so the order of completion never changes a number.

* :class:`SerialExecutor` — in this process (``workers=1``).
* :class:`LocalExecutor` — :class:`concurrent.futures.ProcessPoolExecutor` on
  ``workers`` local processes (default: every core); no server needed.
* :class:`DaskExecutor` — a ``dask.distributed`` cluster, given a scheduler
  address (``"tcp://host:8786"``) or an existing ``distributed.Client`` (e.g. on
  a ``LocalCluster``). ``dask.distributed`` is an optional extra, imported only here.

:func:`make_executor` picks one from ``workers`` / ``scheduler``.

Examples
--------
>>> ex = make_executor(workers=1)
>>> sorted(ex.run([("a", pow, (2, 3)), ("b", pow, (3, 2))]))
[('a', 8), ('b', 9)]
"""

from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from typing import Iterable, Iterator

__all__ = ["SerialExecutor", "LocalExecutor", "DaskExecutor", "make_executor"]

Task = tuple  # (key, function, args)


def _init_worker() -> None:
    """One BLAS/OpenMP thread per worker process: the processes are the parallelism."""
    try:
        from threadpoolctl import threadpool_limits

        threadpool_limits(1)
    except ImportError:  # pragma: no cover - optional
        pass


class SerialExecutor:
    """Run every task in this process, in order."""

    workers = 1
    description = "serial (1 worker, in-process)"

    def run(self, tasks: Iterable[Task]) -> Iterator[tuple]:
        for key, fn, args in tasks:
            yield key, fn(*args)

    def close(self) -> None:
        pass


class LocalExecutor:
    """Local worker processes (:class:`~concurrent.futures.ProcessPoolExecutor`).

    Parameters
    ----------
    workers : int, optional
        Number of processes; default ``os.cpu_count()``.
    max_pending : int
        Tasks in flight at once (bounds the driver's memory for huge grids);
        default 4 × workers.
    """

    def __init__(self, workers: int | None = None, max_pending: int | None = None):
        n = (os.cpu_count() or 1) if workers is None else workers
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise ValueError(f"workers must be a positive integer, got {workers!r}")
        self.workers = n
        self.max_pending = max_pending or 4 * n
        self.description = f"local processes ({n} workers)"
        method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
        self._pool = ProcessPoolExecutor(max_workers=n, mp_context=multiprocessing.get_context(method),
                                         initializer=_init_worker)

    def run(self, tasks: Iterable[Task]) -> Iterator[tuple]:
        it = iter(tasks)
        pending: dict = {}
        while True:
            while len(pending) < self.max_pending:
                try:
                    key, fn, args = next(it)
                except StopIteration:
                    break
                pending[self._pool.submit(fn, *args)] = key
            if not pending:
                return
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                yield pending.pop(fut), fut.result()

    def close(self) -> None:
        self._pool.shutdown(wait=True, cancel_futures=True)


class DaskExecutor:
    """A ``dask.distributed`` cluster.

    Parameters
    ----------
    client : distributed.Client or str
        A connected client, or a scheduler address such as ``"tcp://10.0.0.5:8786"``
        (a client is then opened here and closed by :meth:`close`).
    max_pending : int, optional
        Tasks in flight at once; default 4 × the cluster's threads (at least 8).
    """

    def __init__(self, client, max_pending: int | None = None):
        try:
            from distributed import Client
        except ImportError:  # pragma: no cover - optional
            raise ImportError("a Dask scheduler needs the optional package 'distributed' "
                              "(pip install 'mtcal[sweep]')") from None
        self._own = isinstance(client, str)
        if self._own:
            if not client.startswith(("tcp://", "tls://", "inproc://", "ws://", "wss://", "ucx://")):
                raise ValueError(f"scheduler must be an address like tcp://host:8786, got {client!r}")
            try:
                client = Client(client, timeout="10s")
            except OSError as exc:
                raise ValueError(f"cannot connect to the Dask scheduler {client!r}: {exc}") from None
        elif not isinstance(client, Client):
            raise TypeError(f"client must be a distributed.Client or an address str, got {type(client).__name__}")
        self.client = client
        threads = sum(client.nthreads().values()) or 1
        self.workers = threads
        self.max_pending = max_pending or max(8, 4 * threads)
        self.description = f"dask.distributed ({len(client.nthreads())} workers, {threads} threads)"

    def run(self, tasks: Iterable[Task]) -> Iterator[tuple]:
        from distributed import as_completed

        it = iter(tasks)
        keys: dict = {}
        ac = as_completed()

        def submit_one() -> bool:
            try:
                key, fn, args = next(it)
            except StopIteration:
                return False
            fut = self.client.submit(fn, *args, pure=False)
            keys[fut.key] = key
            ac.add(fut)
            return True

        n = 0
        while n < self.max_pending and submit_one():
            n += 1
        for fut in ac:
            result = fut.result()
            key = keys.pop(fut.key)
            fut.release()
            submit_one()
            yield key, result

    def close(self) -> None:
        if self._own:
            self.client.close()


def make_executor(workers: int | None = None, scheduler=None):
    """Executor for ``workers`` local processes, or a Dask ``scheduler`` (address or Client).

    ``workers=1`` runs in-process; ``None`` uses every local core. Giving both a
    scheduler and workers is an error (the cluster decides its workers).
    """
    if scheduler is not None:
        if workers is not None:
            raise ValueError("give either workers (local processes) or scheduler (Dask cluster), not both")
        return DaskExecutor(scheduler)
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers must be a positive integer, got {workers!r}")
    n = (os.cpu_count() or 1) if workers is None else workers
    return SerialExecutor() if n == 1 else LocalExecutor(n)
