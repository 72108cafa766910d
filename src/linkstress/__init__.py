"""linkstress: planar linkages from CAD sketches to checked section stresses.

SI units throughout (m, kg, s, N, Pa, rad); angles counter-clockwise from the ground frame's +x.
"""

from linkstress.errors import GeometryError, InputError, LinkstressError, SceneError, SketchError
from linkstress.materials import Material
from linkstress.geometry.profile import LinkProfile

__version__ = "0.1.0"

__all__ = [
    "GeometryError",
    "InputError",
    "LinkProfile",
    "LinkstressError",
    "Material",
    "SceneError",
    "SketchError",
    "__version__",
]
