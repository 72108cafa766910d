"""Errors of linkage definitions that no input angle can fix."""

from __future__ import annotations

from linkstress.errors import InputError


class LinkageError(InputError):
    """A loop or machine that is ill-defined: a zero length, an unknown branch, a drive cycle."""
