#!/usr/bin/env bash
# Create (or reuse) the pice virtual environment and check that MPI works.
#
#   bash mpi/setup_env.sh            # venv at <repo>/.venv
#   PICE_VENV=/tmp/v bash mpi/setup_env.sh
#
# The venv gets `pip install -e ".[mpich,test]"`; the MPICH wheel from PyPI
# puts `mpiexec` into $VENV/bin. The install is skipped when the stamp file in
# the venv matches the current pyproject.toml (sha256), so reruns are fast.
set -euo pipefail
export PIP_DISABLE_PIP_VERSION_CHECK=1

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="${PICE_VENV:-.venv}"
[[ "$VENV" = /* ]] || VENV="$ROOT/$VENV"          # relative -> repo root
PYTHON="${PYTHON:-python3}"
EXTRAS="mpich,test"
STAMP="$VENV/.pice-setup-stamp"

die() { echo "setup_env.sh: ERROR: $*" >&2; exit 1; }

# 1. venv
if [[ ! -x "$VENV/bin/python" ]]; then
    command -v "$PYTHON" >/dev/null || die "'$PYTHON' not found (set PYTHON=/path/to/python3.10+)"
    echo "setup_env.sh: creating venv at $VENV"
    "$PYTHON" -m venv "$VENV" || die "'$PYTHON -m venv' failed (install python3-venv?)"
fi
"$VENV/bin/python" -c 'import sys' 2>/dev/null \
    || die "venv python at $VENV/bin/python is broken; remove $VENV and rerun"

# 2. install, unless the stamp says pyproject.toml is unchanged
want="$(sha256sum "$ROOT/pyproject.toml" | cut -d' ' -f1) extras=$EXTRAS"
if [[ -f "$STAMP" && "$(cat "$STAMP")" == "$want" ]]; then
    echo "setup_env.sh: venv up to date (pyproject.toml unchanged)"
else
    echo "setup_env.sh: installing pice[$EXTRAS] (editable) into $VENV ..."
    rm -f "$STAMP"
    "$VENV/bin/python" -m pip install -q --upgrade pip || die "pip upgrade failed"
    (cd "$ROOT" && "$VENV/bin/python" -m pip install -q -e ".[$EXTRAS]") \
        || die "pip install -e \".[$EXTRAS]\" failed (see pip output above)"
    echo "$want" > "$STAMP"
fi

# 3. smoke test: mpiexec from the venv must start 2 ranks of mpi4py
[[ -x "$VENV/bin/mpiexec" ]] || die "no mpiexec in $VENV/bin (is the 'mpich' wheel installed?)"
"$VENV/bin/python" -c 'import mpi4py' 2>/dev/null || die "mpi4py is not importable in $VENV"
out="$(timeout 120 "$VENV/bin/mpiexec" -n 2 "$VENV/bin/python" -c \
    'from mpi4py import MPI; c = MPI.COMM_WORLD; print(f"rank {c.rank} of {c.size}", flush=True)' 2>&1)" \
    || die "'mpiexec -n 2 python -c \"from mpi4py import MPI\"' failed: $(echo "$out" | tail -n 3 | tr '\n' ' ')"
grep -q "rank 0 of 2" <<<"$out" && grep -q "rank 1 of 2" <<<"$out" \
    || die "mpiexec -n 2 did not start 2 MPI ranks (got: $(echo "$out" | tr '\n' ' '))"

echo "setup_env.sh: OK - mpiexec -n 2 works; venv: $VENV"
echo "setup_env.sh: activate with: source $VENV/bin/activate"
