"""pice: MPI-parallel discrete-element solver for sea ice acting on moored floating structures.

Units are SI throughout (m, s, kg, N, Pa, rad) unless a docstring says otherwise.
"""

__version__ = "0.1.0"
