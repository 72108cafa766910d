"""One exception family for the whole tool.

Every error a user can cause is an :class:`InputError`; the CLI turns it into one message and exit
code 2. Each message names the culprit (file, DXF handle, CSV line, scene key, joint, crank angle)
and says what to do.
"""

from __future__ import annotations


class LinkstressError(Exception):
    """Base of every error raised on purpose by linkstress."""


class InputError(LinkstressError, ValueError):
    """Bad input from the user: exit code 2 at the command line."""


class GeometryError(InputError):
    """A link outline, hole, joint or thickness that cannot make a link profile."""


class SketchError(InputError):
    """A DXF or CSV sketch that cannot be read or turned into closed outlines."""


class SceneError(InputError):
    """A scene file key that is missing, misspelt or out of range."""
