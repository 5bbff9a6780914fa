"""The rigs: the car's parts alone on a test bench, run by the one runner
(``sim.simulation``).

``friction``: a block on a belt, one friction pair (the FRD law against closed forms).
``strut``: the car's own front strut on the side-load friction rig; ``at_rest``: the car's
strut load at rest and the rig's side load that reproduces it.
"""
