"""One module per ``linkstress`` subcommand, each with ``register(subparsers)``."""

from __future__ import annotations

import argparse


class HelpFormatter(argparse.HelpFormatter):
    """argparse's formatter, filling each line of a description or epilog on its own and keeping an
    indented line as written: prose fills the terminal, an example's command line stays whole."""

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        fill = super()._fill_text
        lines = text.splitlines()
        return "\n".join(indent + line if line.startswith(" ") else fill(line, width, indent) for line in lines)


def examples(*lines: str, heading: str = "example:") -> str:
    """An epilog of ``heading`` then ``lines``, each a shell command line run from the root of a source
    checkout (the shipped cases are under validation/cases)."""
    return "\n".join([heading, *(f"  {line}" for line in lines)])
