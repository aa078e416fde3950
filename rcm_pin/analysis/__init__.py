"""Generic algorithms on any Mechanism (serial or closed); never a mechanism's name.

Position problems (:mod:`.position`, numeric routes :mod:`.closed_position`,
:mod:`.serial_ik`), kinematics (:mod:`.kinematics`, :mod:`.jacobians`), velocity
(:mod:`.velocity`, :mod:`.loop_velocity`), singularities (:mod:`.singularity`,
:mod:`.closed_singularity`, :mod:`.screws`, :mod:`.maps`, :mod:`.singularity_report`),
workspace (:mod:`.workspace`), accuracy (:mod:`.accuracy`), mobility (:mod:`.mobility`) and
the vectorised planar Newton (:mod:`.batch_planar`).
"""
