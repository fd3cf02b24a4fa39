"""Which trials calibrate the model and which are held out to judge the candidate causes.

Automatic split (``automatic_split``): trials are grouped by protocol (the file's ``protocol`` attribute) and, within
a protocol, ordered by length, stimulus count, shortest inter-stimulus interval and id; alternate trials of each
group go to calibration and to the held-out set (first, third, ... calibrate), so every protocol with two trials or
more appears on both sides, and with three or more the held-out ones lie between calibration ones (a candidate is
judged where it interpolates).  A protocol with a single trial calibrates: its cause is then judged on the held-out
trials where its fitted extension acts (:mod:`.selection`).  ``given_split`` takes the held-out ids of ``--split``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..errors import InputError
from ..measured import MeasuredData, Trial


@dataclass(frozen=True)
class Split:
    """Trial ids used to calibrate (baseline and extension fits) and held out (judging only); how it was made."""

    calibration: tuple[str, ...]
    heldout: tuple[str, ...]
    method: str

    def to_json(self) -> dict:
        return {"calibration": list(self.calibration), "heldout": list(self.heldout), "method": self.method}


def _order_key(t: Trial) -> tuple:
    x = t.length_const if t.length is None else float(np.mean(t.length))
    stim = np.sort(np.asarray(t.stimulus_times_s, dtype=float))
    isi = float(np.diff(stim).min()) if stim.size > 1 else np.inf
    return (float(x) if x is not None else 0.0, int(stim.size), isi, t.trial_id)


def automatic_split(data: MeasuredData) -> Split:
    """By protocol, alternating (module docstring)."""
    groups: dict[str, list[Trial]] = {}
    for t in data.trials.values():
        groups.setdefault(t.protocol, []).append(t)
    cal, held = [], []
    for proto in groups:
        for i, t in enumerate(sorted(groups[proto], key=_order_key)):
            (cal if i % 2 == 0 else held).append(t.trial_id)
    return Split(tuple(cal), tuple(held), "by protocol: alternate trials of each protocol (ordered by length, "
                                          "stimulus count, shortest interval, id) calibrate and are held out; "
                                          "single trials calibrate")


def parse_split(text: str) -> list[str]:
    """``--split`` text: comma-separated held-out trial ids, optionally prefixed ``heldout=``."""
    body = text.split("=", 1)[1] if text.strip().startswith("heldout=") else text
    ids = [s.strip() for s in body.split(",") if s.strip()]
    if not ids:
        raise InputError(f"--split {text!r}: give the held-out trial ids, comma-separated")
    return ids


def given_split(data: MeasuredData, heldout: Sequence[str]) -> Split:
    """The held-out ids given (every other trial calibrates); InputError naming unknown ids."""
    unknown = [i for i in heldout if i not in data.trials]
    if unknown:
        raise InputError(f"--split names trial(s) {unknown} that are not in {data.path or 'the data'} "
                         f"(trials: {', '.join(data.trials)})")
    held = tuple(dict.fromkeys(heldout))
    cal = tuple(t for t in data.trials if t not in held)
    if not cal:
        raise InputError("--split holds out every trial: nothing is left to calibrate the model")
    return Split(cal, held, "given (--split)")
