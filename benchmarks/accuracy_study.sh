#!/usr/bin/env bash
# The runs behind docs/accuracy.md and docs/reference_scene.md, on N ranks (default 2), in sequence.
#   bash benchmarks/accuracy_study.sh [ranks] [stage ...]
#   stages: dt element mooring full element15 coarse200 column thickness
# Each stage is a `pice study` of the reference scene (the coarse job unless it says "full"); its
# table, study.csv/json and study.png land in runs/accuracy_<stage>/.
set -euo pipefail
cd "$(dirname "$0")/.."
N="${1:-2}"; shift || true
SMALL=jobs/zhu_ji_2022_semisub_small.toml
VENV="${PICE_VENV:-.venv}"
run() { local name=$1; shift; echo "== $name"
        "$VENV/bin/mpiexec" -n "$N" "$VENV/bin/pice" study "$@" --out "runs/accuracy_$name" 2>&1 \
          | grep -v "INFO" | tee "runs/accuracy_$name.log"; }
COARSE=(--vary ice.element_diameter=2.0 --vary "moorings[0].element_length=20.0")
for stage in ${@:-dt element full mooring thickness}; do
  case $stage in
    # the time step from the paper's 1e-5 s to 0.95 of the stability limit (1.17e-3 s), over the first impact
    dt)        run dt "$SMALL" --vary run.duration=3.0 --vary run.dt=1e-5,1.17e-4,2.925e-4,5.85e-4,1.11e-3 ;;
    # element size 1.0, 1.5, 2.0 m (dt = 0.5 x each one's limit), same window
    element)   run element "$SMALL" --vary run.duration=3.0 --vary ice.element_diameter=1.0,1.5,2.0 ;;
    # mooring element length, 10 s: the platform's first excursion
    mooring)   run mooring "$SMALL" --vary run.duration=10.0 --vary "moorings[0].element_length=5.0,10.0,20.0,40.0" ;;
    # the full-size sheet (92,000 elements of 1 m) over its first 30 s (~1 h 30 min on 2 shared cores)
    full)      run full jobs/zhu_ji_2022_semisub.toml --vary run.duration=30.0 ;;
    # the same 30 s with 1.5 m elements (the far-field spring per element in proportion to d)
    element15) run element15 jobs/zhu_ji_2022_semisub.toml --vary run.duration=30.0 --vary ice.element_diameter=1.5 \
                 --vary ice.push.stiffness=1.5e6 --vary "moorings[0].element_length=15.0" ;;
    # the full-size sheet and duration (200 s) with 2 m elements: the whole run, coarse
    coarse200) run coarse200 jobs/zhu_ji_2022_semisub.toml "${COARSE[@]}" --vary ice.push.stiffness=2.0e6 ;;
    # one column's ISO 19906 width for the hull's crushing pressure (16.68 m instead of 64.6 m), coarse, 30 s
    column)    run column jobs/zhu_ji_2022_semisub.toml "${COARSE[@]}" --vary ice.push.stiffness=2.0e6 \
                 --vary run.duration=30.0 --vary "bodies[0].crushing_width=16.68" ;;
    # the thickness sweep of section 4.3 on the coarse full-size scene, the first 30 s of each
    # (h = 1.0 is the first 30 s of coarse200); the far-field spring per element in proportion to h
    thickness) for h in 1.2 1.4 1.6; do
                 run "thickness_h$h" "jobs/zhu_ji_2022_semisub_h$h.toml" "${COARSE[@]}" --vary run.duration=30.0 \
                   --vary "ice.push.stiffness=$(python3 -c "print(2.0e6 * $h)")"
               done ;;
    *) echo "unknown stage $stage (dt element mooring full element15 coarse200 column thickness)"; exit 2 ;;
  esac
done
