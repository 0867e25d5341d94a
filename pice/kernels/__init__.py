"""Pure numba kernels: arrays and scalars in, arrays out. No MPI, no I/O.

``JIT`` holds the flags every kernel is compiled with; set ``NUMBA_DISABLE_JIT=1`` to run them as
plain Python (slow, but with Python tracebacks and coverage).
"""

JIT = dict(cache=True, fastmath=False, error_model="numpy")
