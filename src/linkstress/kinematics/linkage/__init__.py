"""Any one-DOF planar linkage of pins and sliders: its joint graph, Assur groups and kinematics.

- ``graph``: the links, pins, sliders, ground and input, with the checks (Gruebler, connected,
  joints named once, the drawn pose closes).
- ``groups``: the joint graph split into the input and groups solvable in order.
- ``dyads``: closed-form RRR, RRP and RPR positions with their velocities and accelerations, on
  points whose x and y are kept apart (``tracks``); ``placing`` puts those groups on a block of the
  path, ``blockwork`` runs them in turn on a block, keeping only what later groups read.
- ``triads``: Newton on a group's constraints (``constraints``), continued along the path;
  ``rates``: its velocities and accelerations from the constraint Jacobian, exact.
- ``sweep``: the whole sweep in blocks on every core, following the drawn assembly, with its flags
  (``flags``) and the link motions it writes (``outputs``): ``solve_linkage``.
"""

from linkstress.kinematics.linkage.graph import Input, Joint, LinkageGraph, Slider, parse_joint
from linkstress.kinematics.linkage.groups import Group, decompose
from linkstress.kinematics.linkage.sweep import LinkageMotion, solve_linkage

__all__ = [
    "Group", "Input", "Joint", "LinkageGraph", "LinkageMotion", "Slider", "decompose", "parse_joint", "solve_linkage",
]
