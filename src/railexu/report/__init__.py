"""Figures and files: everything railexu writes for people to read (the top layer below the CLI).

- :mod:`.figures`: saving (PNG, SVG) and common helpers
- :mod:`.run_figures`, :mod:`.contact_figures`, :mod:`.study_figures`: the figures of each job
- :mod:`.run_files`, :mod:`.contact_files`, :mod:`.stability_files`: the output folders
"""
