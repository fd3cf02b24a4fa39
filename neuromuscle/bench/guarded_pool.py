"""A process pool in which no task can hang: each task has a wall-time limit, and a worker past it is killed and
replaced (``concurrent.futures`` can only stop waiting for such a task, not end it).

Workers start by ``spawn`` (as in ``neuromuscle.fit.evaluate``), each one a fresh interpreter with its own
NEURON, whose stdout is its stderr.  A task is ``fn(item, emit)``: ``emit(message)`` sends a picklable message to
the parent at once, so what a task reported before it was killed is kept.
"""

from __future__ import annotations

import multiprocessing
import os
import time
import traceback
from collections import deque
from dataclasses import dataclass, field
from multiprocessing.connection import Connection, wait
from typing import Any, Callable, Iterable, Iterator

Task = Callable[[Any, Callable[[Any], None]], None]


#: How long (s) a new worker may take to start (spawn, imports) beyond a task's own timeout before it is killed.
STARTUP_S = 60.0


@dataclass
class Outcome:
    """How one task ended: ``status`` "done", "error" (it raised: ``error`` holds the traceback), "timeout" (killed
    after ``timeout_s``) or "died" (the worker process ended, ``error`` says how); ``messages`` are what it
    emitted, in order; ``wall_s`` its wall time (s)."""

    index: int
    status: str
    messages: list[Any] = field(default_factory=list)
    error: str | None = None
    wall_s: float = 0.0


def _serve(conn: Connection, fn: Task) -> None:
    """Worker loop: run each (index, item) received, until None.  What the task prints (NEURON's own messages
    too) goes to stderr: the parent's stdout stays its own."""
    os.dup2(2, 1)
    while True:
        task = conn.recv()
        if task is None:
            return
        index, item = task
        conn.send(("begun", index, None))
        try:
            fn(item, lambda message, index=index: conn.send(("message", index, message)))
            conn.send(("done", index, None))
        except Exception:  # reported to the parent, which records it; the worker serves on
            conn.send(("error", index, traceback.format_exc(limit=8)))


class _Worker:
    def __init__(self, ctx: Any, fn: Task) -> None:
        self.conn, child = ctx.Pipe()
        self.proc = ctx.Process(target=_serve, args=(child, fn), daemon=True)
        self.proc.start()
        child.close()
        self.outcome: Outcome | None = None
        self.started = self.deadline = self.timeout_s = 0.0

    def give(self, index: int, item: Any, timeout_s: float) -> None:
        self.outcome = Outcome(index, "running")
        self.started = time.monotonic()
        self.deadline = self.started + timeout_s + STARTUP_S  # until the worker begins it
        self.timeout_s = timeout_s
        self.conn.send((index, item))

    def finish(self, status: str, error: str | None = None) -> Outcome:
        out, self.outcome = self.outcome, None
        assert out is not None
        out.status, out.error, out.wall_s = status, error, time.monotonic() - self.started
        return out

    def receive(self) -> Outcome | None:
        """Read one message; the task's Outcome when it ended (or the worker died), else None."""
        try:
            kind, _, payload = self.conn.recv()
        except EOFError:
            self.proc.join(5)
            return self.finish("died", f"worker process ended (exit code {self.proc.exitcode})")
        if kind == "begun":  # the task's clock starts now: a worker's start-up is not the task's time
            self.started = time.monotonic()
            self.deadline = self.started + self.timeout_s
            return None
        if kind == "message":
            assert self.outcome is not None
            self.outcome.messages.append(payload)
            return None
        return self.finish(kind, payload)

    def kill(self) -> None:
        self.proc.kill()
        self.proc.join()
        self.conn.close()


def guarded_map(fn: Task, items: Iterable[Any], workers: int, timeout_s: float,
                mp_context: str = "spawn") -> Iterator[Outcome]:
    """Run ``fn(item, emit)`` for every item in ``workers`` processes, each task limited to ``timeout_s`` (s) of
    wall time from when its worker begins it (a worker's start-up does not count; a worker that has not begun it
    ``timeout_s`` + :data:`STARTUP_S` after it was handed over is killed); yields each task's Outcome as it ends
    (completion order; ``Outcome.index`` is the item's position).
    ``fn`` must be importable (a module-level function)."""
    ctx = multiprocessing.get_context(mp_context)
    pending = deque(enumerate(items))
    pool = [_Worker(ctx, fn) for _ in range(min(max(1, workers), len(pending)))]
    try:
        while pending or any(w.outcome for w in pool):
            for w in pool:
                if w.outcome is None and pending:
                    w.give(*pending.popleft(), timeout_s)
            busy = [w for w in pool if w.outcome]
            ready = wait([w.conn for w in busy], max(0.0, min(w.deadline for w in busy) - time.monotonic()))
            for w in busy:
                ended = w.receive() if w.conn in ready else None
                if ended is None and time.monotonic() > w.deadline:
                    ended = w.finish("timeout", f"killed after {timeout_s:g} s")
                if ended is not None:
                    yield ended
                    if ended.status in ("timeout", "died"):
                        w.kill()
                        pool[pool.index(w)] = _Worker(ctx, fn)
    finally:
        for w in pool:
            if w.proc.is_alive():
                try:
                    w.conn.send(None)
                except OSError:
                    pass
                w.proc.join(5)
            if w.proc.is_alive():
                w.kill()
