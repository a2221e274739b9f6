"""The tracks that ship with railexu (installed as ``railexu.tracks``; see railexu/catalog.py)."""
