"""Newton-Euler joint forces and driving torques, and the section stresses along every link."""
