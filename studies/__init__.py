"""The studies that ship with railexu (installed as ``railexu.studies``; see railexu/catalog.py)."""
