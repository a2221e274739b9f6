"""The tracks that ship with railexu, installed as ``railexu.tracks``.

See src/railexu/inputs/catalog.py: ``railexu run NAME`` finds them by name from any folder.
"""
