"""Members of generated links: whatever the outline, members and their sections come out finite,
with both sides of every cut in equilibrium, or the link is refused with a GeometryError (exit 2 at
the command line), never another exception. (Of the 60 generated links, 17 have several members,
4 a curved one, and most have cuts whose line crosses other material, split along the section.)"""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import Point, Polygon

from linkstress.dynamics.section_stress import section_stresses
from linkstress.errors import GeometryError
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.geometry.members import link_members
from linkstress.geometry.profile import LinkProfile

CASES = 60


def generated_link(seed: int) -> LinkProfile:
    """A star-shaped plate (8 to 40 vertices, radius 20-100 mm) with 2 to 4 joints inside it, some in
    4 mm pin holes."""
    rng = np.random.default_rng(seed)
    count = int(rng.integers(8, 41))
    angles = np.sort(rng.uniform(0, 2 * np.pi, count))
    radii = rng.uniform(0.02, 0.1, count)
    shell = Polygon(np.column_stack([radii * np.cos(angles), radii * np.sin(angles)]))
    shell = shell if shell.is_valid else shell.buffer(0)
    if shell.geom_type != "Polygon":
        shell = max(shell.geoms, key=lambda g: g.area)
    joints, holes = [], []
    for _ in range(200):
        if len(joints) == int(rng.integers(2, 5)):
            break
        p = Point(rng.uniform(*shell.bounds[::2]), rng.uniform(*shell.bounds[1::2]))
        if shell.buffer(-0.004).contains(p) and all(p.distance(Point(q)) > 0.01 for q in joints):
            joints.append((p.x, p.y))
            if rng.random() < 0.5:
                holes.append(p.buffer(0.002, quad_segs=8))
    outline = shell
    for hole in holes:
        outline = outline.difference(hole)
    return LinkProfile(outline, np.array(joints if len(joints) >= 2 else [(0.0, 0.0), (1e-3, 0.0)]), 0.005, STRUCTURAL_STEEL)


@pytest.mark.parametrize("seed", range(CASES))
def test_members_of_any_link_are_finite_or_refused(seed):
    try:
        link = generated_link(seed)
        members = link_members(link, (0, 1))
        joints = len(link.joints)
        rng = np.random.default_rng(seed)
        pins = rng.normal(size=(2, joints, 2)) * 100
        couples = np.zeros((2, joints))
        zero = np.zeros(2)
        loads = LinkLoadCase((0, 1), pins, couples, zero + 3.0, zero + 20.0, np.ones((2, 2)), np.zeros((2, 2)))
        # joint 0 (the load frame's origin) takes what balances the rest, inertia included
        force, moment = loads.residual(link)
        pins[:, 0] -= force
        couples[:, 0] -= moment
        for member in members:
            stress = section_stresses(link, loads, member.stations(31), member=member)
            assert np.isfinite(stress.von_mises).all() and np.isfinite(stress.forces.moment).all()
            assert stress.forces.mismatch.max() < 1e-9  # both sides of every cut agree
    except GeometryError as error:
        assert str(error)
