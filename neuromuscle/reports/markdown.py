"""Markdown helpers for the reports: numbers, intervals, tables and lists, formatted one way."""

from __future__ import annotations

from typing import Any, Iterable, Sequence


def sig(x: float | None, digits: int = 3) -> str:
    """``x`` to ``digits`` significant digits; "n/a" for None (a number the report does not have)."""
    return "n/a" if x is None else f"{x:.{digits}g}"


def fixed(x: float, decimals: int = 2) -> str:
    """``x`` with ``decimals`` digits after the point."""
    return f"{x:.{decimals}f}"


def in_ms(seconds: float) -> str:
    """A duration given in s, written in whole ms."""
    return f"{1e3 * seconds:.0f}"


def interval(lower: float | None, upper: float | None, digits: int = 6) -> str:
    """A closed interval, "[lower, upper]"."""
    return f"[{sig(lower, digits)}, {sig(upper, digits)}]"


def value_range(value: float | None, lower: float | None, upper: float | None, digits: int = 3,
                range_digits: int = 2) -> str:
    """A value with its range in parentheses, "v (lower-upper)"."""
    return f"{sig(value, digits)} ({sig(lower, range_digits)}-{sig(upper, range_digits)})"


def table(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> list[str]:
    """The lines of a Markdown table; cells are written with ``str``."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return lines


def bullets(items: Iterable[str]) -> list[str]:
    """The lines of a Markdown list."""
    return [f"- {item}" for item in items]


def link(path: str) -> str:
    """A Markdown link whose text is its target (a file of the report)."""
    return f"[{path}]({path})"
