#!/usr/bin/env bash
# The test command (documented in README.md):   bash mpi/run_tests.sh [extra pytest args]
#
# Stages (all run; the script fails at the end if any stage failed):
#   1. serial   : pytest -m "not mpi"            (+ extra args, e.g. -m slow)
#   2. nojit    : NUMBA_DISABLE_JIT=1 pytest -m nojit
#   3. mpi      : mpiexec -n 2 pytest -m mpi     (under `timeout 1200`)
# Pytest exit code 5 ("no tests collected") counts as success for stages 2 and 3.
set -uo pipefail            # no -e: we want to run every stage

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
bash "$ROOT/mpi/setup_env.sh" || { echo "run_tests.sh: environment setup failed" >&2; exit 1; }

VENV="${PICE_VENV:-.venv}"
[[ "$VENV" = /* ]] || VENV="$ROOT/$VENV"
PY="$VENV/bin/python"
PYTEST=(-q -p no:cacheprovider)

failed=()
# run_stage NAME ALLOW_NO_TESTS(0|1) CMD...
run_stage() {
    local name="$1" allow5="$2"; shift 2
    echo
    echo "==================== stage: $name ===================="
    echo "+ $(printf "%q " "$@")"
    "$@"
    local rc=$?
    if [[ $rc -eq 5 && $allow5 -eq 1 ]]; then
        echo "---- stage $name: no tests collected (ok)"
    elif [[ $rc -eq 124 ]]; then
        echo "---- stage $name: TIMED OUT" ; failed+=("$name(timeout)")
    elif [[ $rc -ne 0 ]]; then
        echo "---- stage $name: FAILED (exit $rc)" ; failed+=("$name(exit $rc)")
    else
        echo "---- stage $name: passed"
    fi
}

run_stage serial 0 "$PY" -m pytest -m "not mpi" "${PYTEST[@]}" tests "$@"
run_stage nojit  1 env NUMBA_DISABLE_JIT=1 "$PY" -m pytest -m nojit "${PYTEST[@]}" tests
run_stage mpi    1 timeout -k 30 1200 "$VENV/bin/mpiexec" -n 2 "$PY" -m pytest -m mpi "${PYTEST[@]}" tests

echo
if [[ ${#failed[@]} -gt 0 ]]; then
    echo "run_tests.sh: FAILED stages: ${failed[*]}"
    exit 1
fi
echo "run_tests.sh: all stages passed"
