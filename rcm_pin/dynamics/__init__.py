"""Dynamics: tree dynamics on mimic models checked against the no-mimic projection
(:mod:`.tree`) and the constrained dynamics of closed mechanisms (:mod:`.constrained`).; linear
vibrations (:mod:`.vibrations`). The re-exports below are the public API of the layer
(``docs/api.md``), imported on first access; the closed-mechanism forward and inverse
dynamics are ``constrained_forward_dynamics`` / ``constrained_inverse_dynamics``."""

from __future__ import annotations

from typing import TYPE_CHECKING

from rcm_pin.lazy import lazy_exports

if TYPE_CHECKING:
    from rcm_pin.dynamics.constrained import (
        acceleration_for_output,
        output_drift,
        velocity_for_output,
        world_closure,
    )
    from rcm_pin.dynamics.constrained import (
        forward_dynamics as constrained_forward_dynamics,
    )
    from rcm_pin.dynamics.constrained import (
        inverse_dynamics as constrained_inverse_dynamics,
    )
    from rcm_pin.dynamics.tree import (
        coriolis_matrix,
        forward_dynamics,
        gravity,
        inverse_dynamics,
        kinetic_energy,
        mass_matrix,
        nonlinear_effects,
        potential_energy,
        total_energy,
        with_gravity,
    )
    from rcm_pin.dynamics.vibrations import (
        Vibrations,
        linearised_frequencies,
        natural_frequencies,
        spring_dynamics,
    )

#: public name -> submodule (or ``submodule:attribute`` where the name differs)
_LAZY = {
    "Vibrations": "vibrations",
    "acceleration_for_output": "constrained",
    "constrained_forward_dynamics": "constrained:forward_dynamics",
    "constrained_inverse_dynamics": "constrained:inverse_dynamics",
    "coriolis_matrix": "tree",
    "forward_dynamics": "tree",
    "gravity": "tree",
    "inverse_dynamics": "tree",
    "kinetic_energy": "tree",
    "linearised_frequencies": "vibrations",
    "mass_matrix": "tree",
    "natural_frequencies": "vibrations",
    "nonlinear_effects": "tree",
    "output_drift": "constrained",
    "potential_energy": "tree",
    "spring_dynamics": "vibrations",
    "total_energy": "tree",
    "velocity_for_output": "constrained",
    "with_gravity": "tree",
    "world_closure": "constrained",
}

__getattr__, __dir__ = lazy_exports(__name__, _LAZY)

__all__ = [
    "Vibrations",
    "acceleration_for_output",
    "constrained_forward_dynamics",
    "constrained_inverse_dynamics",
    "coriolis_matrix",
    "forward_dynamics",
    "gravity",
    "inverse_dynamics",
    "kinetic_energy",
    "linearised_frequencies",
    "mass_matrix",
    "natural_frequencies",
    "nonlinear_effects",
    "output_drift",
    "potential_energy",
    "spring_dynamics",
    "total_energy",
    "velocity_for_output",
    "with_gravity",
    "world_closure",
]
