#!/usr/bin/env bash
# A second environment with PARALLEL HDF5, for the mpio writer and its tests.
#
#   bash mpi/setup_parallel_hdf5.sh                  # venv at <repo>/.venv-phdf5
#   PICE_PHDF5_VENV=/tmp/v bash mpi/setup_parallel_hdf5.sh
#   <venv>/bin/mpiexec -n 2 <venv>/bin/python -m pytest -m io tests
#
# Steps (each skipped when already done):
#   1. Debian packages mpich, libhdf5-mpich-dev, pkg-config (apt-get; needs root, as CI is);
#   2. a venv; numpy/numba and the build tools;
#   3. mpi4py built from source against the system MPICH (MPICC=/usr/bin/mpicc.mpich);
#   4. h5py built from source against Debian's MPICH HDF5 (HDF5_MPI=ON, CC=mpicc, HDF5_DIR=...);
#   5. `pip install -e ".[test]"` WITHOUT the mpich extra: the system MPICH must be the MPI loaded;
#   6. checks: h5py.get_config().mpi, mpi4py reports the system MPICH, and a 2-rank mpio write
#      with the system mpiexec.
# A wrapper <venv>/bin/mpiexec that runs the system mpiexec.mpich is made, so the venv looks like the
# main one to scripts and tests. Takes ~5 minutes from nothing (h5py's compile dominates); a rerun
# with an unchanged pyproject.toml and this script unchanged only repeats the checks.
set -euo pipefail
export PIP_DISABLE_PIP_VERSION_CHECK=1

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="${PICE_PHDF5_VENV:-.venv-phdf5}"
[[ "$VENV" = /* ]] || VENV="$ROOT/$VENV"
PYTHON="${PYTHON:-python3}"
STAMP="$VENV/.pice-phdf5-stamp"
PKGS=(mpich libhdf5-mpich-dev pkg-config)

die() { echo "setup_parallel_hdf5.sh: ERROR: $*" >&2; exit 1; }
say() { echo "setup_parallel_hdf5.sh: $*"; }
t_start=$SECONDS

# 1. Debian packages
missing=()
for p in "${PKGS[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${#missing[@]} -gt 0 ]]; then
    [[ $(id -u) -eq 0 ]] || die "missing Debian packages: ${missing[*]}; run as root or: sudo apt-get install -y ${missing[*]}"
    say "apt-get install ${missing[*]} ..."
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q >/dev/null || die "apt-get update failed"
    apt-get install -y -q --no-install-recommends "${PKGS[@]}" >/dev/null \
        || die "apt-get install ${PKGS[*]} failed"
else
    say "Debian packages present: ${PKGS[*]}"
fi

# system MPICH tools (not the PyPI mpich wheel of the main venv, whatever PATH says)
MPICC="$(command -v mpicc.mpich || true)"; [[ -n "$MPICC" ]] || MPICC=/usr/bin/mpicc.mpich
MPIEXEC="$(command -v mpiexec.mpich || true)"; [[ -n "$MPIEXEC" ]] || MPIEXEC=/usr/bin/mpiexec.mpich
[[ -x "$MPICC" ]] || die "no system mpicc.mpich (is Debian's mpich installed?)"
[[ -x "$MPIEXEC" ]] || die "no system mpiexec.mpich (is Debian's mpich installed?)"

# Debian's MPICH build of HDF5: <libdir>/hdf5/mpich holds include/ and lib/ (symlinks)
HDF5_DIR=""
for d in $(dpkg -L libhdf5-mpich-dev 2>/dev/null | grep -E '/hdf5/mpich$' || true) \
         "/usr/lib/$(gcc -print-multiarch 2>/dev/null || echo x86_64-linux-gnu)/hdf5/mpich"; do
    if [[ -f "$d/include/H5pubconf.h" && -e "$d/lib/libhdf5.so" ]]; then HDF5_DIR="$d"; break; fi
done
[[ -n "$HDF5_DIR" ]] || die "cannot find Debian's MPICH HDF5 prefix (expected <libdir>/hdf5/mpich with include/ and lib/)"
grep -q '#define H5_HAVE_PARALLEL 1' "$HDF5_DIR/include/H5pubconf.h" \
    || die "$HDF5_DIR is not a parallel HDF5 build (H5_HAVE_PARALLEL missing)"
say "system MPICH: $MPICC, $MPIEXEC; parallel HDF5: $HDF5_DIR"

# 2. venv
if [[ ! -x "$VENV/bin/python" ]]; then
    command -v "$PYTHON" >/dev/null || die "'$PYTHON' not found (set PYTHON=/path/to/python3.10+)"
    say "creating venv at $VENV"
    "$PYTHON" -m venv "$VENV" || die "'$PYTHON -m venv' failed"
fi
PY="$VENV/bin/python"
pip_() { "$PY" -m pip "$@"; }

want="$(cat "$ROOT/pyproject.toml" "${BASH_SOURCE[0]}" | sha256sum | cut -d' ' -f1) hdf5=$HDF5_DIR"
if [[ -f "$STAMP" && "$(cat "$STAMP")" == "$want" ]]; then
    say "venv up to date (pyproject.toml and this script unchanged); checking only"
else
    rm -f "$STAMP"
    pip_ install -q --upgrade pip || die "pip upgrade failed"
    # numba fixes the numpy range; h5py is compiled against that numpy (no build isolation)
    pip_ install -q --upgrade numpy numba "Cython>=3" pkgconfig "setuptools>=77" wheel \
        || die "pip install numpy numba Cython setuptools failed"
    pip_ uninstall -y -q mpich 2>/dev/null || true     # never the PyPI MPICH in this venv

    # 3. mpi4py against the system MPICH
    # already built against the system library? (the loaded libmpi lies outside the venv)
    if "$PY" -c 'import sys; from mpi4py import MPI; m = [l.split()[-1] for l in open("/proc/self/maps") if "libmpi" in l]; sys.exit(0 if m and all(x.startswith("/usr/lib/") for x in m) else 1)' 2>/dev/null; then
        say "mpi4py already built against $MPICC"
    else
        say "building mpi4py from source against $MPICC ..."
        t=$SECONDS
        PATH="$(dirname "$MPICC"):$PATH" MPICC="$MPICC" CC="$MPICC" \
            pip_ install -q --no-cache-dir --force-reinstall --no-deps --no-binary=mpi4py mpi4py \
            || die "building mpi4py against the system MPICH failed (see pip output above)"
        say "mpi4py built in $((SECONDS - t)) s"
    fi

    # 4. h5py against parallel HDF5
    if "$PY" -c 'import h5py, sys; sys.exit(0 if h5py.get_config().mpi else 1)' 2>/dev/null; then
        say "h5py with MPI already installed"
    else
        say "building h5py from source (HDF5_MPI=ON, HDF5_DIR=$HDF5_DIR; a few minutes) ..."
        t=$SECONDS
        PATH="$(dirname "$MPICC"):$PATH" HDF5_MPI=ON CC="$MPICC" HDF5_DIR="$HDF5_DIR" \
            pip_ install -q --no-cache-dir --force-reinstall --no-deps --no-build-isolation \
            --no-binary=h5py h5py \
            || die "building h5py against $HDF5_DIR failed (see pip output above)"
        say "h5py built in $((SECONDS - t)) s"
    fi

    # 5. pice itself, without the mpich extra (mpi4py and h5py above already satisfy it)
    (cd "$ROOT" && pip_ install -q -e ".[test]") || die "pip install -e \".[test]\" failed"
    pip_ uninstall -y -q mpich 2>/dev/null || true
    echo "$want" > "$STAMP"
fi
# a wrapper, not a symlink: hydra looks for its proxy beside the path it was started as
rm -f "$VENV/bin/mpiexec"
printf '#!/bin/sh\n# the system MPICH launcher (written by mpi/setup_parallel_hdf5.sh)\nexec %s "$@"\n' "$MPIEXEC" \
    > "$VENV/bin/mpiexec"
chmod +x "$VENV/bin/mpiexec"

# 6. checks
"$PY" -c 'import h5py; assert h5py.get_config().mpi, "h5py has no MPI"' \
    || die "h5py in $VENV was not built with MPI (remove $VENV and rerun)"
lib="$("$PY" -c 'from mpi4py import MPI; print(MPI.Get_library_version().splitlines()[0])')" \
    || die "mpi4py does not import in $VENV"
say "mpi4py: $lib"
"$PY" -c 'import importlib.util, sys; sys.exit(1 if importlib.util.find_spec("mpich") else 0)' \
    || die "the PyPI mpich wheel is installed in $VENV; the system MPICH must be the one loaded"
probe="$(mktemp -d "${TMPDIR:-/tmp}/pice-phdf5.XXXXXX")"
trap 'rm -rf "$probe"' EXIT
cat > "$probe/probe.py" <<'EOF'
import sys
import h5py
import numpy as np
from mpi4py import MPI

c = MPI.COMM_WORLD
with h5py.File(sys.argv[1], "w", driver="mpio", comm=c) as f:
    d = f.create_dataset("x", shape=(c.size, 4), dtype="f8")
    with d.collective:
        d[c.rank] = np.full(4, c.rank, dtype="f8")
c.Barrier()
if c.rank == 0:
    with h5py.File(sys.argv[1], "r") as f:
        x = f["x"][:]
    assert x.shape == (c.size, 4) and all((x[r] == r).all() for r in range(c.size)), x
    print(f"mpio write ok on {c.size} ranks", flush=True)
EOF
out="$(cd "$probe" && timeout 120 "$MPIEXEC" -n 2 "$PY" probe.py "$probe/probe.h5" 2>&1)" \
    || die "2-rank mpio write failed: $(echo "$out" | tail -n 5 | tr '\n' ' ')"
grep -q "mpio write ok on 2 ranks" <<<"$out" || die "2-rank mpio write gave: $(echo "$out" | tr '\n' ' ')"

say "OK - h5py with MPI, $lib, 2-rank mpio write ($((SECONDS - t_start)) s); venv: $VENV"
say "run the I/O tests with: $VENV/bin/mpiexec -n 2 $VENV/bin/python -m pytest -m io tests"
