"""The floating structure: 6-DOF bodies, their hulls and mooring lines, and the rank-0 platform that
steps them (DESIGN.md, the step, item 5).

    rigid_body.py            RigidBody (6 DOF, quaternion attitude, Eqs. 9 and 11) and its rotation kernels
    hull_buoyancy.py         submerged volume and centre of buoyancy of hull mesh and braces (Eqs. 12-14)
    hull_contact.py          ice-hull contact kernel, run by every rank on its own ice
    hulls.py                 hull geometry: box, sloped block, the semi-submersible of Zhu & Ji 2022
    mooring_lines.py         DEM mooring lines (nodes and bonds, Morison drag, seabed), their
    mooring_line_kernels.py    numba kernels beside them
    catenary.py              quasi-static elastic catenary of a multi-segment line; the layout solve
    quasi_static.py          lines whose pull follows the catenary (no line dynamics)
    layout.py                where the anchors go: spread moorings from the pretension
    platform.py              Platform: rank 0's bodies and lines, stepped together
    build.py                 from the job: hulls on every rank, the Platform on rank 0, set-up checks
    output.py                what rank 0 records: series and snapshot entries, peaks, describe()

Numba kernels live beside their Python owner; each is a pure function of arrays and scalars (no
MPI, no I/O). MPI stays in pice/parallel (coupling.py reduces the loads and broadcasts the poses).
"""
