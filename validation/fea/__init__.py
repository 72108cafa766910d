"""The plane-stress finite-element engine: mesh, element forms, loads, stress recovery, convergence,
VTU output, unit load cases, and the closed-form solutions it is verified against.

Imports nothing from the rest of ``linkstress.validation``: the comparison and the benchmarks build
on it, never the reverse.
"""
