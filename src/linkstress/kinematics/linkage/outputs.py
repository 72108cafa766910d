"""A linkage's link motions at the sweep's samples, written a block of path positions at a time.

Every moving link gets its angle, angular velocity and acceleration (P,) and its origin's (its
joint 0's) position, velocity and acceleration (P, 2). Links whose joints 0 share a pin share those
three arrays (the point is one), an origin pinned to the ground is a constant (read-only views of
one value each, as the ground's are), and the input crank turns as the input does (its angle
plus the drawn offset, the input's speed and acceleration): nothing is written twice. Rows where
the mechanism cannot close hold finite filler (0).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.blocks import empty_arrays
from linkstress.kinematics.linkage.graph import Joint, LinkageGraph
from linkstress.kinematics.linkage.placing import Block, crank_offset
from linkstress.kinematics.motion import InputMotion
from linkstress.kinematics.results import LinkMotion, fixed_link

FloatArray = NDArray[np.float64]


def pin_keys(graph: LinkageGraph) -> dict[Joint, object]:
    """Every joint's point key: its pin's index in ``graph.all_pins``, or the joint itself when no
    pin holds it (the joints of a pin are at one point)."""
    keys: dict[Joint, object] = {Joint(name, k): Joint(name, k) for name, joints in graph.links.items()
                                 for k in range(len(joints))}
    for k, pin in enumerate(graph.all_pins):
        for joint in pin:
            keys[joint] = k
    return keys


class Outputs:
    """The arrays of every link's motion over ``n`` samples."""

    def __init__(self, graph: LinkageGraph, pin_of: dict[Joint, object], n: int) -> None:
        self.graph, self.n = graph, n
        self.crank = None if graph.input.is_stroke else graph.input.link
        moving = graph.moving
        self.origin_of: dict[str, object] = {}
        self.fixed: dict[object, FloatArray] = {}
        self.joint_of: dict[object, Joint] = {}
        solving = [name for group in graph.groups for name in group.links + group.riders]
        for name in solving:  # an origin shared by several links is written with the first one solved
            key = pin_of[Joint(name, 0)]
            self.origin_of[name] = key
            ground = [j for j in graph.all_pins[key] if j.link == graph.ground] if isinstance(key, int) else []
            if ground:
                self.fixed[key] = graph.drawn(ground[0])
            else:
                self.joint_of.setdefault(key, Joint(name, 0))
        self.writes = {name: [key for key, joint in self.joint_of.items() if joint.link == name] for name in moving}
        self.turning = tuple(name for name in moving if name != self.crank)
        vectors, pairs = empty_arrays(n, 3 * len(self.turning), 3 * len(self.joint_of))
        self.angles = {name: vectors[3 * k:3 * k + 3] for k, name in enumerate(self.turning)}
        self.points = {key: pairs[3 * k:3 * k + 3] for k, key in enumerate(self.joint_of)}

    def write(self, block: Block, links, samples: slice, local, scale=None) -> None:
        """The motions of ``links`` (and the origins written with them) on ``block`` at its path
        positions ``local`` (a slice or indices into the block), as the samples ``samples``.
        ``scale``: the input's speed and acceleration at those samples, when the block's rates are
        per unit input (chain rule: q. = q' x., q.. = q'' x.^2 + q' x..)."""
        for name in links:
            if name in self.angles:
                angle, w, al = self.angles[name]
                track = block.track(name)
                _put(angle, samples, track.angle, local)
                _put(w, samples, track.w, local)
                _put(al, samples, track.al, local)
                if scale is not None:
                    _chain(w[samples], al[samples], *scale)
            for key in self.writes.get(name, ()):
                p, v, a = self.points[key]
                point = block.joint(self.joint_of[key])
                for k, (x, x1, x2) in enumerate(((point.x, point.x1, point.x2), (point.y, point.y1, point.y2))):
                    _put(p[:, k], samples, x, local)
                    _put(v[:, k], samples, x1, local)
                    _put(a[:, k], samples, x2, local)
                    if scale is not None:
                        _chain(v[samples, k], a[samples, k], *scale)

    def fill(self, samples: slice, bad: NDArray[np.bool_]) -> None:
        """Finite filler (0) at the samples ``samples`` where ``bad``."""
        if bad.any():
            rows = np.arange(samples.start, samples.stop)[bad]
            for arrays in (*self.angles.values(), *self.points.values()):
                for array in arrays:
                    array[rows] = 0.0

    def motions(self, motion: InputMotion, feasible: NDArray[np.bool_]) -> dict[str, LinkMotion]:
        """Every link's motion (the ground's: at rest), the input crank's from ``motion`` where
        ``feasible``."""
        g, n = self.graph, self.n
        links = {g.ground: fixed_link(g.frames[g.ground], g.drawn_angles[g.ground], g.links[g.ground][0], n)}
        angles = dict(self.angles)
        if self.crank is not None:
            offset = crank_offset(g)
            turn = (motion.angle + offset if offset else motion.angle, motion.speed, motion.acceleration)
            if not feasible.all():
                turn = tuple(np.where(feasible, value, 0.0) for value in turn)
            angles[self.crank] = turn
        for name in g.moving:
            key = self.origin_of[name]
            if key in self.fixed:
                zero2 = np.broadcast_to(0.0, (n, 2))
                origin = (np.broadcast_to(self.fixed[key], (n, 2)), zero2, zero2)
            else:
                origin = self.points[key]
            links[name] = LinkMotion(g.frames[name], *angles[name], *origin)
        return {name: links[name] for name in g.links}


def _put(out: FloatArray, samples: slice, value, local) -> None:
    out[samples] = value if np.ndim(value) == 0 else value[local]


def _chain(first: FloatArray, second: FloatArray, speed: FloatArray, acceleration: FloatArray) -> None:
    """In place: (q', q'') per unit input -> (q', q'') per unit time."""
    second *= speed * speed
    second += first * acceleration
    first *= speed
