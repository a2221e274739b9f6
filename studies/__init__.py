"""The studies that ship with railexu, installed as ``railexu.studies``.

See railexu/catalog.py: ``railexu run NAME`` finds them by name from any folder.
"""
