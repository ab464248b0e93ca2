"""Where many independent tries run: here, on local processes, or on a Dask cluster.

A search (``puppet tune``) and a playtest (``puppet playtest``) both run batches of
tries that depend only on their arguments, so they can run anywhere and come back in
any order. ``Executor.map`` runs a batch and returns the results in the order of the
tasks, whatever order they finished in: what the caller does with them (and so every
figure and file it writes) does not depend on the engine or the number of workers.

- ``jobs=1``: in this process (no pickling, the easiest to debug);
- ``jobs=N``: a ``concurrent.futures.ProcessPoolExecutor`` of N processes, kept for
  the executor's life (each worker keeps what it prepared: a log read, a checkpoint);
- ``cluster=ADDRESS``: Dask distributed (``pip install 'puppet[cluster]'``), a
  scheduler at ``tcp://HOST:8786`` that workers on other machines joined, or
  ``cluster="local"`` for a ``LocalCluster`` of ``jobs`` worker processes here.

Why Dask and not Ray: ``distributed`` is pure Python (a wheel with no compiled core,
so it installs wherever puppet does), its ``LocalCluster`` starts real worker processes
in a second for tests, and a cluster is one ``dask scheduler`` plus ``dask worker
ADDRESS`` per machine; the tasks here are plain functions on small picklable
arguments, which is all its ``Client.map`` needs (Ray's actors and object store are
more than this uses, and its install is a large platform-specific one).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from puppet.data.errors import UsageError

CLUSTER_HINT = "pip install 'puppet[cluster]' (Dask distributed)"


class Executor:
    """Runs tasks: ``map(fn, tasks, progress)`` -> results in task order. ``fn`` must be
    a module-level function (it is pickled by name for other processes)."""

    workers = 1
    name = "here"

    def map(self, fn: Callable[[Any], Any], tasks: Sequence[Any],
            progress: Callable[[int], None] | None = None) -> list[Any]:
        out = []
        for task in tasks:
            out.append(fn(task))
            if progress is not None:
                progress(1)
        return out

    def close(self) -> None:
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class ProcessExecutor(Executor):
    """A pool of local processes. Ctrl+C drops the tasks not begun (not waited for)."""

    def __init__(self, jobs: int):
        from concurrent.futures import ProcessPoolExecutor

        self.workers = jobs
        self.name = f"{jobs} local processes"
        self._pool = ProcessPoolExecutor(max_workers=jobs)

    def map(self, fn, tasks, progress=None):
        from concurrent.futures import as_completed

        if len(tasks) <= 1:  # not worth a round trip
            return super().map(fn, tasks, progress)
        futures = {self._pool.submit(fn, t): i for i, t in enumerate(tasks)}
        out: list[Any] = [None] * len(tasks)
        try:
            for fut in as_completed(futures):
                out[futures[fut]] = fut.result()
                if progress is not None:
                    progress(1)
        except BaseException:  # Ctrl+C: the tasks not begun are dropped, not waited for
            self._pool.shutdown(wait=False, cancel_futures=True)
            self._stopped = True
            raise
        return out

    def close(self) -> None:
        if not getattr(self, "_stopped", False):
            self._pool.shutdown(wait=True, cancel_futures=True)


class DaskExecutor(Executor):
    """Tasks on a Dask distributed cluster (``address``), or on a ``LocalCluster`` of
    ``jobs`` single-threaded worker processes (``address="local"``)."""

    def __init__(self, address: str, jobs: int = 2):
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise UsageError(f"--cluster needs Dask distributed: {CLUSTER_HINT}") from None
        self._cluster = None
        if address == "local":
            # processes, one thread each: the physics holds the GIL, threads would queue
            self._cluster = LocalCluster(n_workers=jobs, threads_per_worker=1,
                                         processes=True, dashboard_address=None)
            self._client = Client(self._cluster)
        else:
            try:
                self._client = Client(address, timeout="10s")
            except OSError as exc:
                raise UsageError(f"--cluster {address}: no Dask scheduler answered ({exc}); "
                                 "start one with 'dask scheduler' and workers with "
                                 "'dask worker ADDRESS'") from None
        self.workers = max(1, len(self._client.scheduler_info().get("workers", {})))
        self.name = f"Dask at {self._client.scheduler.address} ({self.workers} workers)"

    def map(self, fn, tasks, progress=None):
        from distributed import as_completed

        if not tasks:
            return []
        # pure=False: a task sent twice (a resumed search) is run again, not looked up
        futures = self._client.map(fn, list(tasks), pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        out: list[Any] = [None] * len(tasks)
        try:
            for fut in as_completed(futures):
                out[index[fut.key]] = fut.result()
                if progress is not None:
                    progress(1)
        except BaseException:
            self._client.cancel(futures)
            raise
        return out

    def close(self) -> None:
        self._client.close()
        if self._cluster is not None:
            self._cluster.close()


def make_executor(jobs: int = 1, cluster: str | None = None) -> Executor:
    """Here (jobs 1), local processes (jobs > 1), or Dask (``cluster``: an address, or
    'local' for a LocalCluster of ``jobs`` workers)."""
    if cluster:
        return DaskExecutor(cluster, max(jobs, 1))
    if jobs > 1:
        return ProcessExecutor(jobs)
    return Executor()
