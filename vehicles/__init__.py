"""The vehicles that ship with railexu, installed as ``railexu.vehicles``.

See railexu/catalog.py: ``railexu run NAME`` finds them by name from any folder.
"""
