"""The finite-element check's own error: a link that cannot be meshed or solved.

It is an :class:`~linkstress.errors.InputError` (the CLI exits 2 on it), and it names the link, so
that a command checking several links can catch it per link, report the reason and go on.
"""

from __future__ import annotations

from linkstress.errors import InputError


class FEAError(InputError):
    """A link too thin for the mesh size, a loaded joint without a hole, a gmsh or solver failure."""
