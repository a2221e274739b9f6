"""The studies that ship with railexu, installed as ``railexu.studies``.

See src/railexu/inputs/catalog.py: ``railexu run NAME`` finds them by name from any folder.
"""
