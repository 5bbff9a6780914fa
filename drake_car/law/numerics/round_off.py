"""Round-off as the reports print it: a value that is zero by construction but comes out of a
computation on numbers of size ``scale`` as a few thousand ulps of them (a car file's spring
offset 1.4e-17 m, its spring inclination 1.7e-15 deg) prints as 0. Files keep full precision."""

# relative to the numbers it is computed from: 4500 ulps of double precision (2.2e-16), far
# above what a chain of geometry leaves and far below any value a designer enters
ROUND_OFF = 1e-12


def cleaned(value, scale=1.0):
    """``value``, or 0.0 where it is round-off of numbers of size ``scale``."""
    return 0.0 if abs(value) < ROUND_OFF * scale else value
