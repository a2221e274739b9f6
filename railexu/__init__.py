"""railexu: railway vehicle dynamics on the Exudyn multibody engine.

The package is organised along the physics:

- :mod:`railexu.profiles` -- wheel and rail profiles (S1002, 60E1, cones, SIMPACK files);
- :mod:`railexu.contact` -- wheel-rail contact: geometry, Hertz, creep forces, the compiled kernel;
- :mod:`railexu.cli` -- the ``railexu`` command, a thin shell over the public functions.

All quantities inside the code are SI (m, kg, s, N, rad).
"""

__version__ = "0.1.0"
