"""Layer 4, how the vehicle is run: the run settings (speed, distance, initial offset, step,
solver; :mod:`~railexu.operation.run_settings`), prescribed speed profiles
(:mod:`~railexu.operation.speed_profile`) and traction and brake demands
(:mod:`~railexu.operation.traction`).
"""
