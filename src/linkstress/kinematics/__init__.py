"""Kinematics of planar loops and machines: positions, velocities and accelerations over whole sweeps.

- ``fourbar.FourBar`` / ``solve_fourbar`` and ``slider_crank.SliderCrank`` / ``solve_slider_crank``:
  one loop, closed form, one call for a whole sweep of crank angles.
- ``machine.Machine``: loops chained by a power graph; ``solve.solve_machine`` sweeps it (and a
  ``linkage.LinkageGraph``: any one-DOF linkage of pins and sliders, ``linkage.solve_linkage``).
- ``linkage_class``: Grashof class, Barker type, toggles, limit positions, feasible input ranges.
- ``crossings``: steps of a sweep that pass a loop's toggle or change point (``Crossing``).
- ``blocks``: a loop's sweep solved a block of positions at a time, the blocks on every core.
- ``motion.InputMotion``: the main crank's angles, speeds and accelerations; ``expression`` parses
  functions of time safely.
"""

from linkstress.kinematics.errors import LinkageError
from linkstress.kinematics.fourbar import FourBar, solve_fourbar
from linkstress.kinematics.machine import Drive, Loop, Machine, Role
from linkstress.kinematics.motion import InputMotion, angle_motion, timed_motion
from linkstress.kinematics.results import Crossing, JointMotion, LinkMotion, LoopMotion, MachineMotion
from linkstress.kinematics.slider_crank import SliderCrank, solve_slider_crank
from linkstress.kinematics.solve import solve_machine

__all__ = [
    "Crossing",
    "Drive",
    "FourBar",
    "InputMotion",
    "JointMotion",
    "LinkMotion",
    "LinkageError",
    "Loop",
    "LoopMotion",
    "Machine",
    "MachineMotion",
    "Role",
    "SliderCrank",
    "angle_motion",
    "solve_fourbar",
    "solve_machine",
    "solve_slider_crank",
    "timed_motion",
]
