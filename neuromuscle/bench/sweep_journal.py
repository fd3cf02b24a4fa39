"""The sweep's journal (JSON lines, schema ``neuromuscle.sweep-journal/1``): the settings on the first line, then
one line per finished draw with its run records and comparisons, appended as each draw ends.  A sweep given an
existing journal of the same settings takes the draws it holds and runs only the others, so a long sweep that
was stopped resumes where it was; a journal of other settings is refused.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ..errors import InputError

JOURNAL_SCHEMA = "neuromuscle.sweep-journal/1"


def open_journal(path: str | Path, settings: dict[str, Any]) -> dict[int, dict[str, Any]]:
    """The finished draws of the journal at ``path`` ({draw: {"runs", "comparisons"}}), starting the file when it
    is absent; InputError when it was written with other settings.  A last line cut short is dropped.  The
    number of draws is not a setting that matters here (draw i is the same in a sweep of any size), so a
    journal of a larger sweep gives a smaller one its first draws, and a smaller one's journal resumes a larger."""
    p = Path(path)
    header = {"schema": JOURNAL_SCHEMA, "settings": settings}
    if not p.exists() or not p.read_text().strip():
        p.write_text(json.dumps(header) + "\n")
        return {}
    lines = p.read_text().splitlines()
    first = json.loads(lines[0])

    def same(h: dict[str, Any]) -> dict[str, Any]:
        return {**h, "settings": {k: v for k, v in h.get("settings", {}).items() if k != "n_draws"}}

    if same(first) != same(json.loads(json.dumps(header))):
        raise InputError(f"sweep journal {p}: written for other settings ({first.get('settings')}); give another "
                         "file or delete it")
    done: dict[int, dict[str, Any]] = {}
    for line in lines[1:]:
        try:
            entry = json.loads(line)
        except json.JSONDecodeError:  # the sweep was stopped while writing it: the draw runs again
            continue
        done[int(entry["draw"])] = entry
    p.write_text("\n".join([lines[0], *(json.dumps(e) for e in done.values())]) + "\n")
    return done


def append_draw(path: str | Path, draw: int, runs: list[dict[str, Any]], comparisons: list[dict[str, Any]]) -> None:
    """Append one finished draw to the journal."""
    with open(path, "a") as f:
        f.write(json.dumps({"draw": draw, "runs": runs, "comparisons": comparisons}) + "\n")
