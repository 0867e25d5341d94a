"""Input/output, one module per file kind or job:

    errors.py      OutputError (exit status 4) and RunFileError (5), below every other module here
    run_file.py    the HDF5 run file's writer (RunFile): attributes, series, snapshots, events
    mpio.py        which write mode a parallel run uses, and the collective writes of the mpio mode
    output.py      a run's output while it runs (RunOutput): what each rank writes, and when it fails
    run_reader.py  the one reader of a run file (open_run): for export, plots, studies, summaries
    xdmf.py        the XDMF file beside a run file, so ParaView opens the run directly
    vtk_export.py  `pice export --vtk`: a .vtu per snapshot and block, and a .pvd collection
    checkpoint.py  checkpoints: the whole state of a run, written atomically, read on any rank count
    restore.py     a simulation continued from a checkpoint
    mesh.py        the one reader of triangle-mesh files (walls and hulls)
    toml_text.py   TOML text of a job dict (the variants of `pice study`)
"""
