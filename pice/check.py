"""``pice check JOB``: a job validated and built, a short probe timed, and what the run holds and costs
printed (the elements, bonds, step, floes or keel blocks, bodies and lines, the wall time)."""

from __future__ import annotations

import math
import pathlib
import time

TWO_RANK_EFFICIENCY = 0.8  # mpi/scaling.py on this project's 2-core machine (README, Speed)


def check_job(source) -> int:
    """`pice check JOB`: validate the job, build it, time a short probe, and print what it holds and
    what it will cost; 0 when valid (an invalid job raises its JobError before anything is printed)."""
    from .job import load_job
    from .simulation import Simulation

    job = load_job(source)
    if job.keel is not None and job.bodies:
        from .io.keel_file import keel_path

        if not keel_path(job, pathlib.Path(source).parent).exists():
            return _check_keel_to_generate(job, source)
    sim = Simulation(job, base_dir=pathlib.Path(source).parent)
    d = sim.describe()
    sim.advance(3)  # compile and warm up
    probe = max(10, min(200, int(2e6 // max(d["elements"], 1))))
    t0 = time.perf_counter()
    sim.advance(probe)
    per_step = (time.perf_counter() - t0) / probe
    wall_per_s = per_step * d["steps_per_second"]
    mb = d["memory_bytes"] / 2**20
    print(f"{source}: valid")
    print(f"  elements          {d['elements']:,} in {d['layers']} layer(s), modelled thickness "
          f"{d['thickness_modelled']:.3g} m")
    print(f"  bonds             {d['bonds']:,}")
    print(f"  memory (particles) {mb:,.1f} MiB")
    print(f"  stable time step  {d['dt_stable']:.4g} s ({d['dt_governed_by']})")
    limit = f"({d['dt_safety']:.2g} x the limit)" if math.isfinite(d["dt_stable"]) else "(as given)"
    print(f"  chosen time step  {d['dt']:.4g} s {limit}")
    print(f"  steps per sim. s  {d['steps_per_second']:,.0f}")
    if "bond_kn" in d:
        print(f"  bond springs      k_n {d['bond_kn']:.4g} N/m, k_s {d['bond_ks']:.4g} N/m, "
              f"k_bend {d['bond_kb']:.4g} N m/rad, k_twist {d['bond_kt']:.4g} N m/rad")
        print(f"  bond strength     normal {d['normal_strength']:.4g} Pa, shear {d['shear_strength']:.4g} Pa, "
              f"friction {d['bond_friction']:.3g}")
    if "floes" in d:
        lo, hi = d["floe_mass_range"]
        if "floe_concentration" in d:
            print(f"  floes             {d['floes']:,} of {lo / 1e3:,.0f}-{hi / 1e3:,.0f} t, concentration "
                  f"{d['floe_concentration']:.1%} of floes.area")
        else:
            print(f"  keel blocks       {d['floes']:,} of {lo:,.0f}-{hi:,.0f} kg")
    if "bodies" in d:
        masses = ", ".join(f"{m / 1e3:,.1f} t" for m in d["body_mass"])
        print(f"  bodies            {d['bodies']} ({masses})")
        sub = f", {d['mooring_substeps']} line sub-step(s) per step" if d["mooring_substeps"] else " (quasi-static)"
        print(f"  mooring lines     {d['mooring_lines']} with {d['mooring_nodes']:,} DEM nodes{sub}")
    if job.keel is not None and job.keel.end_after_peak is not None and sim.hulls:
        from .platform.build import initial_poses
        from .postproc.resistance import PeakWatch

        watch = PeakWatch.from_job(job, sim.hulls[0], initial_poses(job)[0])
        print(f"  run's end         once R is past its peak (keel.end_after_peak): the stem past the keel, after "
              f"{watch.beyond:.4g} m, and the 6 m average of R below {watch.drop:g} of its peak; at most "
              f"run.duration")
    print(f"  wall time / sim. s {wall_per_s:,.1f} s on this machine, 1 rank (probe of {probe} steps: "
          + (f"{d['floes'] / per_step:,.3g} floe-steps/s" if d.get("floes") else
             f"{d['elements'] / per_step:,.3g} particle-steps/s") + f"); the {job.run.duration:g} s job: "
          f"~{wall_per_s * job.run.duration:,.0f} s")
    eff = TWO_RANK_EFFICIENCY
    print(f"  on 2 ranks        ~{wall_per_s * job.run.duration / (2 * eff):,.0f} s for the job (at the {eff:.0%} "
          "two-rank efficiency mpi/scaling.py measures; more ranks: see README, Speed)")
    return 0


def _check_keel_to_generate(job, source) -> int:
    """`pice check` of a ship run whose keel file is not made yet: what its generation will settle."""
    from .physics.keel import generation_facts

    if job.keel.trim_from is not None:
        from .io.keel_file import read_trim_source

        folder = pathlib.Path(source).parent
        if not (folder / job.keel.trim_from).exists():
            print(f"{source}: valid; its keel is trimmed from {folder / job.keel.trim_from}, not generated yet: "
                  f"pice keel on that keel's job first (its cost: pice check on it), then pice keel {source}")
            return 0
        wider = read_trim_source(job, folder)  # JobError: generated from another keel, or narrower
        print(f"{source}: valid; its keel file is not made yet (pice keel {source}: trimmed from "
              f"{wider['path']}, {wider['width']:g} m wide, {len(wider['x']):,} blocks, in seconds)")
        return 0
    g = generation_facts(job)
    lo, hi = g["mass_range"]
    print(f"{source}: valid; its keel file is not generated yet (pice keel {source})")
    print(f"  keel blocks       {g['released']:,} released, of {lo:,.0f}-{hi:,.0f} kg "
          "(the trim keeps those in the keel)")
    print(f"  settling step     {g['dt']:.4g} s ({1.0 / g['dt']:,.0f} steps per sim. s), up to keel.settle_time = "
          f"{g['settle_time']:g} s")
    print(f"  cost              ~{g['hours']:.2g} h on 2 ranks here, from a measured generation (the 80 m Gong "
          "keel's) in proportion to the blocks and the steps (docs/ridge_keel.md)")
    return 0
