"""The report of pice bench: the lines it prints and the JSON file it writes."""

from __future__ import annotations

import json
import pathlib

from ..timers import PARTS

#: load average [processes] above which the machine was not quiet before the measurement
QUIET_LOAD = 0.5


def default_json_path(result: dict) -> pathlib.Path:
    """runs/bench_<commit7>[-dirty]_<ranks>ranks.json: one file per commit and rank count."""
    code = result["code"]
    commit = (code["commit"] or "nogit")[:7] + ("-dirty" if code.get("dirty") else "")
    return pathlib.Path("runs") / f"bench_{commit}_{result['ranks']}ranks.json"


def write_json(result: dict, path) -> pathlib.Path:
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(result, indent=2) + "\n")
    return path


def _split_lines(split: dict | None) -> list[str]:
    if not split:
        return []
    lines = [f"  split of one step (timed window; mean over {split['ranks']} rank(s), max in brackets): "
             f"{split['ms_per_step']:.3f} ms/step, {split['sum_over_outside']:.1%} of the window's wall time"]
    for name in PARTS:
        part = split["parts"][name]
        if part["max_ms_per_step"] > 0.0005:  # parts the scene does not have stay at zero: not printed
            lines.append(f"    {name:<12} {part['ms_per_step']:9.3f} ms {part['percent']:6.1f} %   "
                         f"({part['max_ms_per_step']:.3f})")
    waits = [(r, w) for r, w in enumerate(split.get("ghost_wait_ms") or []) if w]
    if waits:
        lines.append("  ghost update wait per step [ms] (median / 90th percentile / largest): "
                     + ", ".join(f"rank {r} {w['median']:.3f} / {w['p90']:.3f} / {w['max']:.2f}" for r, w in waits))
    return lines


def report_lines(result: dict) -> list[str]:
    """The printed report: the setting, the sheet's throughput, the full scene's cost, their splits."""
    m, sw, code = result["machine"], result["software"], result["code"]
    commit = (code["commit"] or "no git")[:12] + (" (dirty: tracked files differ)" if code.get("dirty") else "")
    cores = f"{m['physical_cores']} core(s), " if m["physical_cores"] else ""
    mem = f"{m['memory_gib']:.1f} GiB" if m["memory_gib"] else "memory unknown"
    lines = [f"pice bench: {result['ranks']} rank(s), commit {commit}",
             f"  machine       {m['cpu_model']}, {cores}{m['usable_cpus']} usable CPU(s), {mem}",
             f"  software      python {sw['python']}, numpy {sw['numpy']}, numba {sw['numba']}, mpi4py "
             f"{sw['mpi4py']}, MPI {sw['mpi_library'] or '(one rank: not initialised)'}"]
    load = m["load_average_before"]
    if load and load[0] > QUIET_LOAD:
        lines.append(f"  warning       load average {load[0]:.2f} before the measurement: the machine was "
                     "not quiet, so these figures are not comparable (docs/performance.md, Measuring)")
    if result["ranks"] > (m["usable_cpus"] or 1):
        lines.append(f"  warning       {result['ranks']} ranks on {m['usable_cpus']} CPU(s): oversubscribed")
    s = result.get("sheet")
    if s:
        lines += [f"sheet           {s['elements']:,} elements, {s['bonds_broken_before_timing']} bonds broken, "
                  f"dt {s['dt']:.4g} s, {s['steps']} steps after {s['warmup_steps']}",
                  f"  throughput    {s['particle_steps_per_second']:.4g} particle-steps/s "
                  f"({s['particle_steps_per_second_per_rank']:.4g} per rank), {s['ms_per_step']:.3f} ms/step"]
        if s.get("median_block_ms_per_step"):
            lines.append(f"  median block  {s['median_block_ms_per_step']:.3f} ms/step "
                         f"({s['median_block_particle_steps_per_second']:.4g} particle-steps/s): the median over "
                         f"blocks of {s['block_steps']} steps, the rare long pauses of a shared machine left out")
        lines += _split_lines(s["split"])
    f = result.get("full")
    if f:
        lines += [f"full scene      {f['job']}: {f['elements']:,} elements, {f['bodies']} body(ies), "
                  f"{f['mooring_lines']} line(s), dt {f['dt']:.4g} s ({f['dt_safety']:.3g} x the limit), "
                  f"{f['steps']} steps from t = {f['window_start_time_s']:.3g} s"
                  + (f" (restarted from {result['settings']['restart']})" if result["settings"].get("restart") else ""),
                  f"  cost          {f['wall_s_per_simulated_s']:.4g} s of wall time per simulated second, "
                  f"{f['ms_per_step']:.3f} ms/step, {f['particle_steps_per_second']:.4g} particle-steps/s",
                  f"  projected     {f['projected_hours']:.3g} h for its {f['duration_s']:g} s on "
                  f"{result['ranks']} rank(s) (this window's cost throughout)"]
        lines += _split_lines(f["split"])
    return lines
