"""Layer 4, the track: files, alignment, irregularities and the track's own dynamics.

:mod:`~railexu.track.track` (:class:`Track`, :func:`load_track`) with its schema
(:mod:`~railexu.track.schema`); the horizontal alignment (:mod:`~railexu.track.alignment`); the
track irregularities, synthetic and measured (:mod:`railexu.track.irregularities`); the rigid or
elastic track (:mod:`~railexu.track.elastic`). ``docs/track-format.md`` documents the file.
"""
