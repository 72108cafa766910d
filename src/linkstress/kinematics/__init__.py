"""Kinematics of planar loops and machines: positions, velocities and accelerations over whole sweeps."""
