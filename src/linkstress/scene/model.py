"""What a scene file says, checked and in SI units: links, materials, machine, motion, loads, analysis.

Member frames: a link's motion, its explicit centre of mass and the points where forces act are
given in its member frame ``frame_joints`` (i, j): origin at joint i, +x toward joint j (a slider's
frame is (k, k): origin at its joint, +x along the slider line, its sketch drawn with that line
along the sketch's +x; in a linkage, along the line as drawn, at ``frame_angle``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.linkage.graph import LinkageGraph
from linkstress.kinematics.machine import Machine
from linkstress.kinematics.motion import InputMotion
from linkstress.materials import Material
from linkstress.geometry.profile import LinkProfile


@dataclass(frozen=True)
class MassData:
    """mass [kg], inertia [kg m^2] about the centre of mass, center_of_mass (2,) [m] in the member frame."""

    mass: float
    inertia: float
    center_of_mass: NDArray[np.float64]


@dataclass(frozen=True)
class SceneLink:
    """A link of the scene.

    joints (n, 2) [m] as drawn (a ground's are where the ground frame puts them); ``frame_joints`` its
    member frame; ``profile`` when it comes from a sketch; ``explicit_mass`` when the scene gives
    mass, inertia and centre of mass (these take precedence over the profile's); ``members`` as the
    scene names them.
    """

    name: str
    joints: NDArray[np.float64]
    frame_joints: tuple[int, int]
    thickness: float | None = None
    material: Material | None = None
    profile: LinkProfile | None = None
    explicit_mass: MassData | None = None
    sketch: Path | None = None
    layer: str | None = None
    members: tuple[tuple[int, int], ...] | None = None
    """The link's arms as joint pairs (``linkstress.geometry.members``); None: the tree that joins its joints."""
    frame_angle: float = 0.0
    """A one-joint frame's +x as drawn [rad]: a linkage block's slider line (0 elsewhere)."""

    def to_member(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Drawn points (..., 2) [m] into the member frame."""
        i, j = self.frame_joints
        origin = self.joints[i]
        if i == j:
            if self.frame_angle == 0.0:
                return np.asarray(points, float) - origin
            c, s = np.cos(self.frame_angle), np.sin(self.frame_angle)
        else:
            dx, dy = self.joints[j] - origin
            length = np.hypot(dx, dy)
            c, s = dx / length, dy / length
        p = np.asarray(points, float) - origin
        return np.stack([p[..., 0] * c + p[..., 1] * s, -p[..., 0] * s + p[..., 1] * c], axis=-1)

    @property
    def center_of_mass(self) -> NDArray[np.float64] | None:
        """Centre of mass (2,) [m] in the member frame: explicit, else the profile's centroid, else None."""
        if self.explicit_mass is not None:
            return self.explicit_mass.center_of_mass
        if self.profile is not None:
            return self.to_member(self.profile.center_of_mass)
        return None

    @property
    def mass_data(self) -> MassData | None:
        """Mass properties: explicit, else from the profile and its material's density, else None."""
        if self.explicit_mass is not None:
            return self.explicit_mass
        if self.profile is not None and self.material is not None:
            return MassData(self.profile.mass, self.profile.mass_moment_of_inertia, self.center_of_mass)
        return None


@dataclass(frozen=True)
class CoupleLoad:
    """A known couple ``value`` [N m], counter-clockwise, on ``link`` at its joint ``at_joint``."""

    link: str
    value: float
    at_joint: int


@dataclass(frozen=True)
class PointLoad:
    """A known force ``force`` (2,) [N], ground frame, on ``link`` at ``at`` (2,) [m], member frame."""

    link: str
    at: NDArray[np.float64]
    force: NDArray[np.float64]


@dataclass(frozen=True)
class Loads:
    """gravity (2,) [m/s^2]; couples and point forces; ``friction[mechanism]``: Coulomb coefficient
    of that slider-crank's slider on its line."""

    gravity: NDArray[np.float64]
    couples: tuple[CoupleLoad, ...] = ()
    forces: tuple[PointLoad, ...] = ()
    friction: Mapping[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class Analysis:
    """What to compute when the scene has an [analysis] table (absent: everything the data allows).

    stations: number of section stations per link (None: the engine's default); validate: links to
    check by FEA; mesh_size [m] (None: the engine's default); element_order 1 or 2;
    body_load_near_holes: the body-load term on sections near holes too (default: nominal values there);
    peaks: FEA peak stresses over the sweep by superposition of unit loads, and fatigue, for every
    stressed link; fatigue_criterion: the criterion of ``fatigue_safety_factor`` ("goodman",
    "gerber" or "asme-elliptic"); accuracy: the governing stress within this fraction, which picks
    each link's stress model (``linkstress.model_choice``; None: its default, 0.05).
    """

    kinematics: bool = False
    forces: bool = False
    stresses: bool = False
    stations: int | None = None
    validate: tuple[str, ...] = ()
    mesh_size: float | None = None
    element_order: int = 2
    body_load_near_holes: bool = False
    peaks: bool = False
    fatigue_criterion: str = "goodman"
    accuracy: float | None = None


@dataclass(frozen=True)
class Scene:
    """A whole scene, checked. ``actuator``: the link carrying the unknown driving torque;
    ``title`` and ``notes``: what reports say about the case (the title defaults to the file's stem);
    ``warnings``: values that are valid but implausible (a unit slip, most likely), one line each,
    which every report shows and the JSON lists under ``warnings``."""

    path: Path
    units: str | None
    materials: Mapping[str, Material]
    links: Mapping[str, SceneLink]
    machine: Machine | LinkageGraph
    motion: InputMotion
    actuator: str
    loads: Loads
    analysis: Analysis | None
    title: str = ""
    notes: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()

    @property
    def linkage(self) -> LinkageGraph | None:
        """The scene's ``type = "linkage"`` mechanism, or None for loops."""
        return self.machine if isinstance(self.machine, LinkageGraph) else None

    @property
    def moving_links(self) -> tuple[str, ...]:
        """Names of the links that move (every role but ground; every link of a linkage but its
        ground), in solving order."""
        if self.linkage is not None:
            return tuple(name for group in self.linkage.groups for name in group.links + group.riders)
        names: list[str] = []
        for loop in self.machine.loops:
            for role, r in loop.roles.items():
                if role != "ground" and r.link not in names:
                    names.append(r.link)
        return tuple(names)
