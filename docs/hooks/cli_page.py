"""MkDocs hook: the command-line reference is generated from the argparse parsers of ``neuromuscle.cli``.

A page holding the line ``<!-- cli-reference -->`` gets, in its place, one section per command and subcommand with
its ``--help`` text, so the page cannot drift from the parsers.
"""

from __future__ import annotations

import argparse
import os

MARKER = "<!-- cli-reference -->"
WIDTH = "110"


def _subcommands(parser: argparse.ArgumentParser) -> list[tuple[str, argparse.ArgumentParser]]:
    actions = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return [(name, p) for a in actions for name, p in a.choices.items()]


def command_sections(parser: argparse.ArgumentParser, prefix: str = "neuromuscle", level: int = 2) -> list[str]:
    """Markdown sections (heading and ``--help`` text) of every subcommand of ``parser``, depth first."""
    out = []
    for name, sub in _subcommands(parser):
        command = f"{prefix} {name}"
        out += [f"{'#' * level} `{command}`", "", "```text", sub.format_help().rstrip(), "```", ""]
        out += command_sections(sub, command, level + 1)
    return out


def cli_reference() -> str:
    """The generated part of the command-line page."""
    from neuromuscle.cli import build_parser

    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = WIDTH  # argparse wraps the help text at the terminal's width
    try:
        parser = build_parser()
        lines = ["```text", parser.format_help().rstrip(), "```", "", *command_sections(parser)]
    finally:
        if old is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = old
    return "\n".join(lines)


def on_page_markdown(markdown: str, page, config, files) -> str:  # noqa: ARG001 (the MkDocs hook signature)
    if MARKER not in markdown:
        return markdown
    return markdown.replace(MARKER, cli_reference())
