"""Benchmarks: speed against error, throughput, stability, start-up, and the original program's strip sums
as the baseline. Scripts that print figures (``python -m linkstress.validation.bench.<name>``) and the
suite behind ``linkstress bench``. The top of the import graph: nothing else imports from here.
"""
