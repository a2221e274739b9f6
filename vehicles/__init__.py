"""The vehicles that ship with railexu (installed as ``railexu.vehicles``; see railexu/catalog.py)."""
