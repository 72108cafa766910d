"""Sketch importers: DXF and Inventor iLogic CSV sketches become link outlines with joints.

``read_sketch(path, units=None, tolerance=None)`` returns a :class:`Sketch` whose ``links`` are
:class:`ImportedLink` objects (outline and joints in metres, sketch frame); ``ImportedLink.profile``
makes a :class:`linkstress.geometry.profile.LinkProfile` of a given thickness and material.
"""

from linkstress.importers.sketch import HOLE_RULE, POINT_RULE, ImportedLink, Sketch, read_sketch

__all__ = ["HOLE_RULE", "POINT_RULE", "ImportedLink", "Sketch", "read_sketch"]
