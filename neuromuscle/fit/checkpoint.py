"""The record of a running fit: counters, best point, progress lines and the checkpoint file.

The checkpoint (JSON, schema ``neuromuscle.fit-checkpoint/1``, written atomically after every iteration) holds
the free names and their search-space references, the current best parameters and cost, the history (one entry
per iteration) and counters.  ``fit(..., checkpoint=path, resume=True)`` starts from the best parameters in it
and continues its history.
"""

from __future__ import annotations

import json
import math
import os
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from .problem import FitProblem

CHECKPOINT_SCHEMA = "neuromuscle.fit-checkpoint/1"


def write_json_atomic(path: Path, doc: dict) -> None:
    """Write ``doc`` as JSON to ``path`` through a temporary file and a rename (never half a file)."""
    tmp = path.with_name(path.name + f".tmp{os.getpid()}")
    tmp.write_text(json.dumps(doc, indent=1) + "\n")
    os.replace(tmp, path)


def read_checkpoint(path: str | os.PathLike, problem: FitProblem) -> dict[str, Any]:
    """Read a fit checkpoint and check it belongs to ``problem`` (same free parameters)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"checkpoint {p}: file not found (cannot resume)")
    try:
        doc = json.loads(p.read_text())
    except json.JSONDecodeError as exc:
        raise InputError(f"checkpoint {p}: not valid JSON ({exc})") from None
    if not isinstance(doc, dict) or doc.get("schema") != CHECKPOINT_SCHEMA:
        raise InputError(f"checkpoint {p}: schema is not {CHECKPOINT_SCHEMA!r}")
    if doc.get("free") != problem.free:
        raise InputError(f"checkpoint {p}: fits {doc.get('free')}, the problem fits {problem.free}")
    if doc.get("objective") != problem.objective:
        raise InputError(f"checkpoint {p}: objective {doc.get('objective')!r}, the problem uses "
                         f"{problem.objective!r}")
    return doc


class Tracker:
    """Counts simulations and iterations, keeps the best point, prints progress and writes the checkpoint;
    ``previous``: a checkpoint read by :func:`read_checkpoint` whose history and counters continue."""

    def __init__(self, problem: FitProblem, method: str, checkpoint: Path | None, progress: bool,
                 previous: dict | None) -> None:
        self.problem, self.method, self.checkpoint, self.progress = problem, method, checkpoint, progress
        self.t_start = time.perf_counter()
        self.history: list[dict] = list(previous["history"]) if previous else []
        self.n_sim = int(previous["n_simulations"]) if previous else 0
        self.n_iter = int(previous["n_iterations"]) if previous else 0
        self.best_z: np.ndarray | None = None
        self.best_cost = math.inf

    def evaluated(self, zs: Sequence[np.ndarray], rs: Sequence[np.ndarray]) -> None:
        """Count the candidates zs with residuals rs and keep the best."""
        self.n_sim += len(zs) * len(self.problem.trials)
        for z, r in zip(zs, rs):
            c = float(r @ r)
            if np.isfinite(c) and c < self.best_cost:
                self.best_cost, self.best_z = c, np.array(z, dtype=float)

    def iteration(self, z: np.ndarray, cost: float) -> None:
        """One iteration ended at z with ``cost``: history, progress line, checkpoint."""
        self.n_iter += 1
        values = self.problem.to_values(z)
        entry = {"iteration": self.n_iter, "cost": cost, "parameters": values, "n_simulations": self.n_sim,
                 "elapsed_s": round(time.perf_counter() - self.t_start, 3)}
        self.history.append(entry)
        if self.progress:
            shown = " ".join(f"{k}={v:.6g}" for k, v in values.items())
            print(f"[fit {self.method}] iter {self.n_iter:3d}  cost {cost:.6g}  {shown}  ({self.n_sim} sims, "
                  f"{entry['elapsed_s']:.1f} s)", file=sys.stderr, flush=True)
        self.write()

    def write(self, final: bool = False) -> None:
        """Write the checkpoint (if a path was given and a point was evaluated)."""
        if self.checkpoint is None or self.best_z is None:
            return
        pr = self.problem
        doc = {"schema": CHECKPOINT_SCHEMA, "method": self.method, "objective": pr.objective, "free": pr.free,
               "bounds": pr.bounds, "frozen": pr.frozen, "search_space": pr.reference(),
               "best": pr.to_values(self.best_z), "best_cost": self.best_cost,
               "n_simulations": self.n_sim, "n_iterations": self.n_iter, "finished": final,
               "parameters": pr.parameters(self.best_z).to_json(), "history": self.history}
        write_json_atomic(self.checkpoint, doc)
