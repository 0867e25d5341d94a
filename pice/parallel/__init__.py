"""Everything MPI: the communicator, decomposition, halo exchange, migration, load balance.

This is the only package that imports mpi4py, and it does so only when the process was started by
an MPI launcher (so a serial `pice run` never initialises MPI).
"""
