"""What the LAAS-style fixtures of tests/data/laas are (shared by the API and CLI tests)."""

from __future__ import annotations

from pathlib import Path

from rcm_pin.model.output_choice import HOW, candidate_frames

DATA = Path(__file__).parent / "data" / "laas"

#: name -> drives, closure kinds, coordinates, assembly modes at least found from home.
FIXTURES = {
    "five_bar": {"drives": ("mot1", "mot2"), "kinds": ("3d",), "nq": 4, "min_modes": 2},
    "delta": {
        "drives": ("mot1", "mot2", "mot3"),
        "kinds": ("3d", "3d"),
        "nq": 9,
        "min_modes": 2,
    },
    "leg_6d": {"drives": ("motor_hip", "motor_knee"), "kinds": ("6d",), "nq": 5, "min_modes": 2},
}
#: name -> output frame to give, and the default coordinates it gets.
OUTPUT = {
    "five_bar": ("effector", ("x", "y")),
    "delta": ("effector", ("x", "y", "z")),  # singular at the symmetric home: see SIMULATE
    "leg_6d": ("foot", ("x", "z")),
}


def no_output_message(mech, what: str) -> str:
    """The exact message of :func:`rcm_pin.model.output_choice.require_output`."""
    return (
        f"{what} of {mech.name} needs an output frame and its sidecar names none; valid: "
        f"{HOW} with FRAME one of {', '.join(candidate_frames(mech))}"
    )


#: name -> output options of a regular task for ``simulate`` (the 3-RRS "delta" moves in
#: heave, roll and pitch; x, y and yaw are its parasitic motions, stationary at home).
SIMULATE = {
    "five_bar": ["--output-frame", "effector"],
    "delta": ["--output-frame", "effector", "--output-coords", "z rx ry"],
    "leg_6d": ["--output-frame", "foot"],
}
