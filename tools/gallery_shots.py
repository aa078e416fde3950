"""How tools/gallery.py shows each catalogue mechanism: pose, camera, colours, caption text."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Shot:
    """How one mechanism is shown.

    Attributes:
        text: what the bodies are (by colour) and what moves, for the caption.
        inputs: the input vector shown (``mech.input_names``) [rad, m]; None: home.
        view: direction from the scene centre to the camera; None: the viewer's default.
        colors: the body colours (:data:`rcm_pin.viz.palette.COLOR_MODES`).
        browser: render with Chromium (False: matplotlib, which draws rods for a URDF
            without visual geometry where Meshcat draws nothing).
    """

    text: str
    inputs: tuple[float, ...] | None = None
    view: tuple[float, float, float] | None = None
    colors: str = "auto"
    browser: bool = True


_RCM = (
    "Grey: the base, fixed to the world; blue: the platform, turned by q1 about x; orange: "
    "the initial, intermediate and output links, whose {drive} (mimic joints) keep the "
    "output axis through A for every q1, q2; silver: the holder and working organ, sliding "
    "along that axis (q3) and turning about it (q4){wrist}."
)
_WRIST = ", and the wrist and tool (q5, q6)"
#: The RCM mechanisms from the front, a little from above: the parallelogram in view.
_RCM_VIEW = (0.2, -1.0, 0.35)
#: Every catalogue mechanism's shot (--check fails for a mechanism without one).
SHOTS: dict[str, Shot] = {
    "rcm_bevel": Shot(
        _RCM.format(drive="gold bevel gears", wrist=_WRIST),
        (0.3, -0.4, 0.09, 0.5, 0.6, 0.2),
        _RCM_VIEW,
    ),
    "rcm_bevel_4dof": Shot(
        _RCM.format(drive="gold bevel gears", wrist=""), (0.3, -0.4, 0.09, 0.5), _RCM_VIEW
    ),
    "rcm_belt": Shot(
        _RCM.format(drive="gold belts and pulleys", wrist=_WRIST),
        (0.3, -0.4, 0.09, 0.5, 0.6, 0.2),
        _RCM_VIEW,
    ),
    "rcm_two_mass": Shot(
        "A massless schematic: grey bearing blocks of q1 on the base; the blue cross shaft "
        "turns q1 about x and carries q2 about y, both through A; on the orange output axis "
        "the point mass m_d (a sphere) at a fixed distance from A, and the gold point mass m "
        "at the tool centre, sliding along it (q3).",
        (0.3, -0.4, 0.09),
    ),
    "planar_3rrr": Shot(
        "Seen from above its plane. Three legs from the base pivots A1, A2, A3 (driven): "
        "proximal links (blue, teal, brown) and distal links (orange, gold, sky blue) hold "
        "the purple platform at C1, C2, C3; the platform moves in the plane "
        "(x, y and its angle)."
    ),
    "five_bar": Shot(
        "Seen from above its plane. Two chains from the base pivots A1, A2 (driven): the "
        "proximal links (blue, purple) and the distal links (orange, teal) meet at the "
        "output point P (the arrows), a planar point closure; the elbows B1, B2 can be "
        "driven instead near a singularity."
    ),
    "four_bar": Shot(
        "Seen from above its plane. Crank O1-A (orange, driven), coupler A-B (orange) and "
        "rocker O2-B (blue, the output, its angle psi) on the grey base (the frame line "
        "O1-O2); the red sphere is the cut pair B where coupler and rocker are joined."
    ),
    "eye_4dof": Shot(
        "Each body its own colour (the URDF's greys replaced). The pitch four-bar (crank O1, "
        "coupler, rocker with the eye cradle) tilts both eyes; the yaw crank O3 turns them "
        "through the slotted link 5, slider 7, link 8 and finger; the lid arm turns about "
        "the pitch axis; roll turns the camera block of eye 2 (the output frame). Red "
        "spheres: the cut pairs of the loops.",
        colors="bodies",
    ),
    "spherical_3rrr": Shot(
        "Every joint axis passes through the centre O (the thin rods along x, y, z meet "
        "there): three legs of a proximal arc (blue, teal, brown, turned by the base pairs "
        "u1, u2, u3) and a distal arc (orange, gold, sky blue) hold the purple platform, a "
        "sphere at O that can only turn about O (the arrows: its orientation).",
        view=(1.0, 0.75, 0.8),
    ),
    "translational_3ppapa": Shot(
        "Three legs, one per axis: a grey slider driven along x, y or z (P1, P2, P3, the "
        "rings with double arrows), then two hinged parallelograms (orange cranks, blue "
        "couplers; one crank per parallelogram a coordinate, the other a mimic), then the "
        "green platform, which only translates."
    ),
    "translational_3ppapa_loops": Shot(
        "The same mechanism with each parallelogram closed as a 4R loop (over-constrained) "
        "instead of crank + mimic: grey sliders (driven P1, P2, P3), orange cranks, blue "
        "couplers, green platform (translation only); red spheres: the cut pairs."
    ),
    "panda": Shot(
        "Each body its own colour (the meshes' own materials replaced): grey base, then "
        "links 1 to 7, the hand (sky blue) and the two fingers, the eighth coordinate "
        "(one finger joint; the other mimics it).",
        colors="bodies",
    ),
    "ur5": Shot(
        "Each body its own colour (the meshes' own materials replaced): grey base, "
        "shoulder, upper arm, forearm and three wrist links, each turned by the joint "
        "before it (q1 to q6).",
        colors="bodies",
    ),
}
