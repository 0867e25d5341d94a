"""Post-processing of pice run files: figures (``plots``) and off-screen pyvista renders (``render``).

Run as ``pice plot RUN.h5``. Both read the run file through pice/io/run_reader.py; matplotlib and
pyvista are imported only when a figure or render is made.
"""
