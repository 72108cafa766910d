"""The check of linkstress's beam stresses against plane-stress finite elements.

Three layers, imports flowing downward only:

- ``linkstress.validation.bench``: benchmarks and the ``linkstress bench`` suite (top);
- this package's own modules: the comparison of beam and FEA stresses (``compare``,
  ``validate_scene``), FEA peaks by superposition (``peaks``, ``peaks_scene``) and their reports;
- ``linkstress.validation.fea``: the finite-element engine itself (bottom).
"""
