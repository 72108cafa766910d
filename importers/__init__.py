"""Sketch importers: DXF and Inventor iLogic CSV sketches become link outlines with joints.

``read_sketch(path, units=None, tolerance=None)`` returns a :class:`Sketch` whose ``links`` are
:class:`ImportedLink` objects (outline and joints in metres, sketch frame); ``ImportedLink.profile``
makes a :class:`linkstress.geometry.profile.LinkProfile` of a given thickness and material.
``unit_warnings(sketch, links)`` says when its links or pin holes are of a size no mechanism has, and
which unit would make them ordinary.
"""

from linkstress.importers.sketch import HOLE_RULE, POINT_RULE, ImportedLink, Sketch, SketchRefused, read_sketch
from linkstress.importers.plausibility import unit_warnings

__all__ = ["HOLE_RULE", "POINT_RULE", "ImportedLink", "Sketch", "SketchRefused", "read_sketch", "unit_warnings"]
