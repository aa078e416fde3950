"""Mechanism families: the only place that knows a mechanism by its kind.

Each family module (a subpackage where it needs more than ~300 lines) holds the closed
forms of its papers with their misprints written down, its named configurations, and the
hooks of :class:`rcm_pin.model.family.Family` that generic code asks for. Each module
exposes ``FAMILY``; the catalogue (:mod:`rcm_pin.catalog.table`) imports the modules
explicitly, and its entries are the one list of families.
"""
