"""``sweep(run, params)``: ``run(p)`` for every ``p`` of ``params``, in local
processes or on a ``dask.distributed`` cluster, results in the order of
``params``.

Runs are sent in chunks (one task per chunk, so a short run does not pay a
round trip each). A run that raises does not stop the others: its exception is
caught where it ran and comes back as a :class:`SweepFailure` (its index, its
parameters, the error and its traceback). With ``errors="raise"`` (default) the
sweep raises one :class:`SweepError` at the end listing every failed run, and
carries every result (failures in place) as ``.results``; with
``errors="return"`` the failures are returned in place of results.
"""
from __future__ import annotations

import importlib
import math
import multiprocessing
import os
import pickle
import sys
import traceback
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import Future, ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from typing import Any, TextIO


@dataclass(frozen=True)
class SweepFailure:
    """A run that raised: ``index`` in ``params``, the ``params`` it was given,
    ``error`` (``"TypeName: message"``) and the ``traceback`` where it ran."""

    index: int
    params: Any
    error: str
    traceback: str

    def __str__(self) -> str:
        return f"run {self.index} with params {self.params!r}: {self.error}"


class SweepError(RuntimeError):
    """Runs of a sweep failed; ``failures`` lists them, ``results`` holds every
    result in order with a :class:`SweepFailure` where a run failed."""

    def __init__(self, failures: list[SweepFailure], results: list[Any]) -> None:
        self.failures, self.results = failures, results
        lines = "\n".join(f"  {f}" for f in failures)
        super().__init__(f"{len(failures)} of {len(results)} runs failed:\n{lines}")


def _run_chunk(run: Callable[[Any], Any] | bytes, items: list[tuple[int, Any]]) -> list[tuple[int, bool, Any]]:
    """Runs one chunk where it was sent: ``(index, ok, result or failure)``;
    ``run`` may come as cloudpickle's bytes (see ``_portable``)."""
    if isinstance(run, bytes):
        run = pickle.loads(run)
    assert callable(run)
    out: list[tuple[int, bool, Any]] = []
    for index, p in items:
        try:
            out.append((index, True, run(p)))
        except Exception as e:  # a failed run is reported, never lost with its chunk
            failure = SweepFailure(index, p, f"{type(e).__name__}: {e}", traceback.format_exc())
            out.append((index, False, failure))
    return out


class _Counter:
    """tqdm's bar when it is installed, else a ``k/n runs`` line on stderr."""

    def __init__(self, total: int, enabled: bool, stream: TextIO | None = None) -> None:
        self.total, self.done, self.enabled = total, 0, enabled
        self.stream = stream or sys.stderr
        self.bar: Any = None
        if enabled:
            try:
                self.bar = importlib.import_module("tqdm").tqdm(total=total, unit="run", file=self.stream)
            except ImportError:
                self.bar = None

    def add(self, k: int) -> None:
        self.done += k
        if not self.enabled:
            return
        if self.bar is not None:
            self.bar.update(k)
        else:
            self.stream.write(f"\rsweep: {self.done}/{self.total} runs")
            self.stream.flush()

    def close(self) -> None:
        if self.enabled and self.bar is not None:
            self.bar.close()
        elif self.enabled:
            self.stream.write("\n")
            self.stream.flush()


def _chunks(items: list[tuple[int, Any]], size: int) -> list[list[tuple[int, Any]]]:
    return [items[i : i + size] for i in range(0, len(items), size)]


def _workers(client: Any, max_workers: int | None) -> int:
    if client is not None:
        try:
            return max(1, sum(client.nthreads().values()))
        except Exception:  # a client that cannot tell: chunks as for one worker
            return 1
    return max_workers or os.cpu_count() or 1


def _portable(run: Callable[[Any], Any]) -> Callable[[Any], Any] | bytes:
    """``run`` as the worker processes can load it: itself when pickle takes it
    (a module-level function), else cloudpickle's bytes of it (a lambda, a
    function of a notebook or a script), when cloudpickle is installed."""
    try:
        pickle.dumps(run)
        return run
    except Exception:
        try:
            cloudpickle = importlib.import_module("cloudpickle")
        except ImportError:
            raise TypeError(
                f"sweep: {run!r} cannot be sent to worker processes (define it at module level, "
                "or pip install cloudpickle, which rigidrs[dask] brings)"
            ) from None
        data: bytes = cloudpickle.dumps(run)
        return data


def _local(
    run: Callable[[Any], Any], chunks: list[list[tuple[int, Any]]], workers: int, tick: Callable[[list[Any]], None]
) -> None:
    # spawn, not fork: a forked child of a process whose worlds started worker
    # threads can deadlock, and spawn behaves the same on every platform.
    ctx = multiprocessing.get_context("spawn")
    portable = _portable(run)
    with ProcessPoolExecutor(max_workers=min(workers, len(chunks)) or 1, mp_context=ctx) as pool:
        futures: dict[Future[Any], list[tuple[int, Any]]] = {pool.submit(_run_chunk, portable, c): c for c in chunks}
        for fut in as_completed(futures):
            tick(_collect(fut, futures[fut]))


def _dask(
    run: Callable[[Any], Any], chunks: list[list[tuple[int, Any]]], client: Any, tick: Callable[[list[Any]], None]
) -> None:
    try:
        distributed = importlib.import_module("distributed")
    except ImportError as e:
        raise ImportError("sweep(client=...) needs dask.distributed: pip install rigidrs[dask]") from e
    futures = [client.submit(_run_chunk, run, c, pure=False) for c in chunks]
    where = {f.key: c for f, c in zip(futures, chunks)}
    for fut in distributed.as_completed(futures):
        tick(_collect(fut, where[fut.key]))


def _collect(fut: Any, chunk: list[tuple[int, Any]]) -> list[tuple[int, bool, Any]]:
    """A chunk's results, or each of its runs failed by what lost the chunk
    (a worker that died, a function that could not be sent)."""
    try:
        return list(fut.result())
    except Exception as e:
        tb = traceback.format_exc()
        return [(i, False, SweepFailure(i, p, f"{type(e).__name__}: {e}", tb)) for i, p in chunk]


def sweep(
    run: Callable[[Any], Any],
    params: Iterable[Any],
    client: Any = None,
    chunksize: int | None = None,
    progress: bool = True,
    errors: str = "raise",
    max_workers: int | None = None,
) -> list[Any]:
    """``[run(p) for p in params]``, computed in parallel, in the order of ``params``.

    ``client``: a ``dask.distributed.Client`` (``Client("tcp://scheduler:8786")`` or a
    ``LocalCluster``'s) to run on its workers; default None: local processes
    (``ProcessPoolExecutor``, spawned, ``max_workers`` default every core), for which
    ``run`` and each ``p`` must pickle (a module-level function; worlds and scenes
    pickle). ``chunksize``: runs per task (default: about four tasks per worker).
    ``progress``: a bar (tqdm when installed, else a counter on stderr).
    ``errors``: ``"raise"`` (default) raises :class:`SweepError` after every run,
    listing each failed run with its parameters (``.results`` still holds every
    result); ``"return"`` puts a :class:`SweepFailure` in place of each failed result.
    """
    if errors not in ("raise", "return"):
        raise ValueError(f"errors must be 'raise' or 'return', got {errors!r}")
    items = list(enumerate(params))
    if chunksize is not None and (not isinstance(chunksize, int) or chunksize < 1):
        raise ValueError(f"chunksize must be a positive integer, got {chunksize!r}")
    if max_workers is not None and (not isinstance(max_workers, int) or max_workers < 1):
        raise ValueError(f"max_workers must be a positive integer, got {max_workers!r}")
    results: list[Any] = [None] * len(items)
    if not items:
        return results
    workers = _workers(client, max_workers)
    size = chunksize or max(1, math.ceil(len(items) / (4 * workers)))
    chunks = _chunks(items, size)
    counter = _Counter(len(items), progress)

    failed: list[int] = []

    def tick(rows: Sequence[tuple[int, bool, Any]]) -> None:
        for index, ok, value in rows:
            results[index] = value
            if not ok:
                failed.append(index)
        counter.add(len(rows))

    try:
        if client is None:
            _local(run, chunks, workers, tick)
        else:
            _dask(run, chunks, client, tick)
    finally:
        counter.close()
    failures = [results[i] for i in sorted(failed)]
    if failures and errors == "raise":
        raise SweepError(failures, results)
    return results
