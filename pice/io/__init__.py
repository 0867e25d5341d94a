"""Input/output: the HDF5 run file (and, later, checkpoints, XDMF and VTK export)."""
