"""The fork server's preload that kills it with its run (PR_SET_PDEATHSIG), nothing else.

Imported by a process pool's fork server only: it asks the kernel for SIGKILL when its
parent (the run) dies (:func:`rcm_pin.processes.parent_death_signal`).

The fork server outlives its parent otherwise: each worker it forks holds the write end of
the pipe whose end-of-file tells it the run is gone, so workers and fork server would keep
each other alive. Importing this module anywhere else would tie that process to its parent:
:func:`rcm_pin.processes.process_pool` lists it in the fork server's preload, nothing else
imports it.
"""

from __future__ import annotations

from rcm_pin.processes import parent_death_signal

parent_death_signal()
