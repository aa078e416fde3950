"""``rcm-pin reproduce``: every paper result the project reproduces, in one report.

The building blocks are in :mod:`.framework`, the explicit list of sections in
:mod:`.sections`, the writer (:func:`rcm_pin.report.writer.write_report`) in :mod:`.writer`.
"""

from rcm_pin.report.framework import Comparison, Section, comparison_table

__all__ = ["Comparison", "Section", "comparison_table"]
