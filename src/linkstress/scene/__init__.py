"""Scene files (TOML): links, materials, mechanisms, motion, loads and what to compute.

``load_scene(path) -> Scene`` reads and checks a whole scene; the schema is documented in
``reader`` (top level), ``links``, ``mechanisms``, ``motion`` and ``loads`` (with [analysis]).
"""

from linkstress.scene.model import Analysis, CoupleLoad, Loads, MassData, PointLoad, Scene, SceneLink
from linkstress.scene.reader import load_scene

__all__ = ["Analysis", "CoupleLoad", "Loads", "MassData", "PointLoad", "Scene", "SceneLink", "load_scene"]
