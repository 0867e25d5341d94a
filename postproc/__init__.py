"""Post-processing of pice run files: figures (``plots``) and off-screen pyvista renders (``render``).

Run as ``pice plot RUN.h5``. Installed with pice (see pyproject.toml) so it imports from any folder;
matplotlib and pyvista are imported only when a figure or render is made.
"""
