"""Where independent pieces of work run: in this process, in local processes, or on a Dask cluster.

A command hands an executor a function and its tasks; the results come back in the tasks' order,
whatever ran them. Without a scheduler the work runs as it always has: one task after another, or
``jobs`` local processes. With one (``--scheduler ADDRESS`` or the LINKSTRESS_SCHEDULER variable)
each task goes to the Dask cluster there, pickled: the task carries everything it needs, never a
path that exists only here. ``local`` starts a cluster of this machine's cores for the command and
closes it after.

When a worker dies while it runs a task (or holds its result not yet fetched) the scheduler runs
that task again on another worker. The executor reads the scheduler's own record of removed
workers, so ``retried`` names each task that ran again and which worker was lost; a task whose
workers died ``distributed.scheduler.allowed-failures`` + 1 times fails the command.

Dask is imported only when a scheduler is asked for: it is an optional dependency (the ``cluster``
extra) and takes a second to import.
"""

from __future__ import annotations

import os
import re
import unicodedata
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import TypeVar

from linkstress.errors import InputError
from linkstress.messages import quoted
from linkstress.threads import cores

Task = TypeVar("Task")
Result = TypeVar("Result")

SCHEDULER_VARIABLE = "LINKSTRESS_SCHEDULER"
OPTION = "--scheduler"
LOCAL = "local"
CONNECT_SECONDS = 5
"""How long to wait for a scheduler to answer before saying it is unreachable."""
WORKER_SECONDS = 30
"""How long to wait for a scheduler's first worker before saying it has none."""
INSTALL = 'pip install "linkstress[cluster]"'
WORKER_THREADS = {"LINKSTRESS_THREADS": "1"}
"""The environment of the workers linkstress starts: one thread each (``linkstress.threads`` would
otherwise run a thread per core in every worker process, and a cluster has a worker per core). Set
in the worker processes alone (a nanny's ``env``, which wins over this process's variables);
Dask's ``pre-spawn-environ`` would set it in this process's own environment too."""
MALLOC_DEFAULTS = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}
"""Dask's configuration for glibc's own malloc thresholds in the workers linkstress starts. A nanny
sets MALLOC_TRIM_THRESHOLD_=65536 in its worker's environment (to hand freed memory back sooner),
which fixes glibc's mmap threshold at 128 kB: every larger numpy array is then mapped and unmapped
anew, page faults included. Measured on the six_bar case: 3.4-3.9 s of CPU per run with it, 1.8-1.9
s without (docs/cluster.md)."""
ADDRESS = re.compile(r"(tcp|tls)://(\[[0-9a-fA-F:.]{2,45}\]|[A-Za-z0-9_-]{1,63}(\.[A-Za-z0-9_-]{1,63})*):[0-9]{1,5}")
"""A scheduler's address as ``dask scheduler`` prints it, matched whole (``fullmatch``: a ``$`` would
let a final newline through): protocol, host (an IPv6 one in brackets; a name's labels of 1 to 63
characters, as DNS allows: a longer one makes the socket module's IDNA codec raise), port (1 to
65535, checked apart)."""
MAX_HOST = 253
"""Longest host name DNS allows [characters]."""
CONTROL = ("Cc", "Cf")
"""Unicode categories of the characters no address may hold: control characters (a newline, a
tab, an escape) and format characters (a zero-width space, a right-to-left override)."""


class ClusterError(InputError):
    """A scheduler that cannot be used, or work the cluster could not finish: exit code 2."""


@dataclass(frozen=True)
class Retry:
    """A task that ran more than once: its ``task`` label and the ``reason`` (which worker was lost)."""

    task: str
    reason: str

    def record(self) -> dict[str, str]:
        return {"task": self.task, "reason": self.reason}


@dataclass
class LocalExecutor:
    """Tasks one after another here, or in ``jobs`` local processes (when there are several tasks)."""

    jobs: int = 1
    retried: list[Retry] = field(default_factory=list)
    """Always empty: here nothing runs twice."""

    @property
    def workers(self) -> int:
        """How many tasks run at once."""
        return self.jobs

    def map(self, work: Callable[[Task], Result], tasks: Sequence[Task], labels: Sequence[str] = ()) -> Iterator[Result]:
        """``work(task)`` for each task, in order (``labels`` name them for a cluster's reports)."""
        if self.jobs > 1 and len(tasks) > 1:
            from concurrent.futures import ProcessPoolExecutor  # multiprocessing: only when processes run

            with ProcessPoolExecutor(max_workers=self.jobs) as pool:
                yield from pool.map(work, tasks)
            return
        for task in tasks:
            yield work(task)


@dataclass
class DaskExecutor:
    """Tasks on the Dask cluster of ``client``; ``scheduler``: the address the user gave (or ``local``)."""

    client: object
    scheduler: str
    retried: list[Retry] = field(default_factory=list)

    @property
    def workers(self) -> int:
        """How many tasks the cluster runs at once now: its workers' threads."""
        return max(1, sum(self.client.nthreads().values()))

    def map(self, work: Callable[[Task], Result], tasks: Sequence[Task], labels: Sequence[str] = ()) -> Iterator[Result]:
        """``work(task)`` for each task on the cluster, results in order; afterwards ``retried``
        holds the tasks that ran again, by their ``labels``."""
        from distributed import KilledWorker

        labels = list(labels) or [f"task {k}" for k in range(len(tasks))]
        run = os.urandom(6).hex()
        keys = [f"linkstress-{k}-{run}" for k in range(len(tasks))]
        futures = [self.client.submit(work, task, key=key, pure=False) for task, key in zip(tasks, keys)]
        try:
            for label, future in zip(labels, futures):
                try:
                    yield future.result()
                except KilledWorker as error:
                    raise ClusterError(
                        f"{label}: the workers running it died {error.allowed_failures + 1} times; it may need more "
                        "memory than a worker has (dask worker --memory-limit), or it crashes the worker"
                    ) from None
                except ModuleNotFoundError as error:
                    raise ClusterError(
                        f"{label}: a worker of {self.scheduler} cannot import {error.name!r}: install linkstress "
                        f"({INSTALL}) in every worker's environment"
                    ) from None
            self.retried += retries(self.client.get_events("all"), dict(zip(keys, labels)))
        finally:
            self.client.cancel(futures)


def retries(events: Sequence[tuple[float, dict]], labels: dict[str, str]) -> list[Retry]:
    """The tasks of ``labels`` (by key) that the scheduler's ``events`` show were sent back for a
    rerun: running on, or holding an unfetched result on, a worker it removed; in event order."""
    out: dict[str, Retry] = {}
    for _, event in events:
        if not isinstance(event, dict) or event.get("action") != "remove-worker":
            continue
        lost = "left" if event.get("expected") else "lost"
        for key in [*event.get("processing-tasks", ()), *event.get("lost-computed-tasks", ())]:
            if str(key) in labels and str(key) not in out:
                out[str(key)] = Retry(labels[str(key)], f"worker {event.get('worker')} {lost}")
    return list(out.values())


def scheduler_choice(option: str | None) -> tuple[str | None, str]:
    """The scheduler asked for, by ``--scheduler`` (``option``) or else the LINKSTRESS_SCHEDULER
    variable (its surrounding spaces dropped), and the name of the one that gave it (for messages);
    (None, "") for neither. A ClusterError at once for one that is not an address (``check_address``)."""
    if option is not None:
        check_address(option, OPTION)
        return option, OPTION
    raw = os.environ.get(SCHEDULER_VARIABLE, "")
    if not raw.strip():
        return None, ""
    value = raw.strip(" ")  # a newline or a tab stays, to be refused
    check_address(value, SCHEDULER_VARIABLE)
    return value, SCHEDULER_VARIABLE


def check_address(scheduler: str, source: str = OPTION) -> None:
    """Refuse (ClusterError naming ``source``, the address quoted by ``repr``) a ``scheduler`` that is
    neither ``local`` nor tcp:// or tls://HOST:PORT, or holds a control or format character."""
    control = _control(scheduler)
    if control is not None:
        raise ClusterError(
            f"{source}: {quoted(scheduler)} holds the control character {control!r}; give the scheduler's address alone, "
            f"tcp://HOST:PORT as `dask scheduler` prints it, or {LOCAL}"
        )
    match = ADDRESS.fullmatch(scheduler)
    if scheduler != LOCAL and not (match and len(match.group(2)) <= MAX_HOST and 0 < int(scheduler.rsplit(":", 1)[1]) < 65536):
        raise ClusterError(
            f"{source}: {quoted(scheduler)} is not a scheduler address: give tcp://HOST:PORT as `dask scheduler` prints it "
            f"(e.g. tcp://10.0.0.5:8786), or {LOCAL} for a cluster on this machine"
        )


def _control(text: str) -> str | None:
    """The first control or format character of ``text`` (``CONTROL``), else None."""
    return next((c for c in text if unicodedata.category(c) in CONTROL), None)


@contextmanager
def executor(scheduler: str | None, source: str = OPTION, jobs: int = 1) -> Iterator[LocalExecutor | DaskExecutor]:
    """The executor for ``scheduler`` (None: this machine, ``jobs`` processes; ``local``: a Dask
    cluster of this machine's cores, closed on leaving; else a scheduler's address); ``source``
    names where the address came from. A ClusterError naming ``source`` for a malformed address,
    a scheduler that does not answer within CONNECT_SECONDS, or Dask not installed."""
    if scheduler is None:
        yield LocalExecutor(jobs)
        return
    check_address(scheduler, source)
    try:
        from distributed import Client
    except ImportError:
        raise ClusterError(f"{source}: running on a Dask cluster needs dask and distributed: {INSTALL}") from None
    if scheduler == LOCAL:
        with local_cluster(cores()) as cluster, Client(cluster) as client:
            yield DaskExecutor(client, LOCAL)
        return
    if scheduler.startswith("tls://"):
        check_tls(source)
    try:
        client = Client(scheduler, timeout=CONNECT_SECONDS)
    except (OSError, TimeoutError) as error:
        raise ClusterError(
            f"{source}: no Dask scheduler answered at {scheduler} within {CONNECT_SECONDS} s ({error.__class__.__name__}): "
            "check the address and that `dask scheduler` runs there and its port is open (docs/cluster.md)"
        ) from None
    with client:
        check_workers(client, scheduler, source)
        yield DaskExecutor(client, scheduler)


def check_tls(source: str = OPTION) -> None:
    """Refuse a ``tls://`` scheduler when Dask's configuration gives this machine no TLS context
    (a CA file, and a client certificate and key): Dask would fail with a TypeError."""
    from distributed.security import Security

    if Security().get_connection_args("client").get("ssl_context") is None:
        raise ClusterError(
            f"{source}: a tls:// scheduler needs Dask's TLS settings here: distributed.comm.tls.ca-file, "
            "distributed.comm.tls.client.cert and .key (e.g. the variables DASK_DISTRIBUTED__COMM__TLS__CA_FILE, "
            "DASK_DISTRIBUTED__COMM__TLS__CLIENT__CERT and DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY; docs/cluster.md)"
        )


def check_workers(client, scheduler: str, source: str = OPTION) -> None:
    """Refuse a cluster with no worker after WORKER_SECONDS, or whose workers cannot import
    linkstress or run another version of it (ClusterError naming the worker and ``source``). A
    worker that cannot unpickle a task dies of it: a nanny restarts it to die again, and without
    one the task would wait forever; another version would not give this machine's numbers."""
    import pydoc

    from linkstress import __version__

    try:
        client.wait_for_workers(1, timeout=WORKER_SECONDS)
    except TimeoutError:
        raise ClusterError(
            f"{source}: the scheduler at {scheduler} has no worker after {WORKER_SECONDS} s: start some with "
            f"`dask worker {scheduler}` (docs/cluster.md)"
        ) from None
    # pydoc.locate imports linkstress on each worker and hands back its version: a function of the
    # standard library, which every worker can unpickle.
    found = client.run(pydoc.locate, "linkstress.__version__", on_error="return")
    for worker, version in sorted(found.items()):
        if version != __version__:
            runs = f"runs linkstress {version}" if isinstance(version, str) else "cannot import linkstress"
            raise ClusterError(
                f"{source}: worker {worker} of {scheduler} {runs}, this machine {__version__}: install the same "
                f"version in every worker's environment ({INSTALL}, or the same checkout)"
            )


@contextmanager
def local_cluster(workers: int) -> Iterator[object]:
    """A distributed.LocalCluster of ``workers`` processes of one thread each (linkstress's own
    threads too: ``WORKER_THREADS``), with glibc's own malloc thresholds (``MALLOC_DEFAULTS``) and
    its HTTP server on a free port (two clusters at once must not fight for Dask's 8787), closed on
    leaving the context."""
    import dask
    from distributed import LocalCluster

    with dask.config.set(MALLOC_DEFAULTS), LocalCluster(
        n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0", env=WORKER_THREADS
    ) as cluster:
        yield cluster
