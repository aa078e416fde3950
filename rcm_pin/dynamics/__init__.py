"""Dynamics: tree dynamics on mimic models checked against the no-mimic projection
(:mod:`.tree`) and the constrained dynamics of closed mechanisms (:mod:`.constrained`)."""
