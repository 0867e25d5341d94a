"""Pure numba kernels: arrays and scalars in, arrays out. No MPI, no I/O.

``JIT`` holds the flags every kernel is compiled with; set ``NUMBA_DISABLE_JIT=1`` to run them as
plain Python (slow, but with Python tracebacks and coverage).
"""

JIT = dict(cache=True, fastmath=False, error_model="numpy")

# The bond kernel's flags: JIT with fused multiply-adds allowed (LLVM's "contract", and no other
# fast-math liberty: no reassociation, NaNs and infinities kept for the health check). 43.7 -> 40.0 ns
# a bond (benchmarks/memory_bandwidth.py, docs/performance.md). The results change in the last bits,
# identically on every rank: each bond is still computed once per end in one canonical order.
JIT_FMA = dict(JIT, fastmath={"contract"})
