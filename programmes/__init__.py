"""The EN 14363 acceptance programmes that ship with railexu, installed as ``railexu.programmes``.

See src/railexu/inputs/catalog.py (kind ``programme``) and docs/acceptance.md.
"""
