"""The bad-input table (not a test module): broken jobs, each refused with ONE line
``FILE: key = value: what is expected``, exit status 2 and nothing written. The job it starts from,
the scene fragments and the helpers that write a case's files and check its lines are in
tests/bad_job_kit.py.

Run by tests/unit/test_job_errors.py on one rank (``pice run`` and ``pice check`` in-process) and by
tests/parallel/test_job_errors_two_ranks.py under ``mpiexec -n 2`` (the same cases, the same line
and exit status from both). Every test folder imports this as ``bad_jobs`` (tests/conftest.py puts
tests/ on sys.path).

Every case takes a small valid job (``BASE``), breaks one thing and names what its error line must
contain. The rules come from

* the schema in pice/job/ (types, bounds, unknown keys, rules between keys; the job file's encoding),
  checked before anything is allocated or written ("validation" cases, marked ``nojit``: they never
  reach a numba kernel);
* set-up, before the run file is created ("setup" cases): the memory the sheet needs
  (pice/memory.py), the stable time step (pice/physics/timestep.py), the output schedule
  (pice/io/output.py), the bond calibration (pice/physics/bond.py), the walls (pice/physics/walls.py),
  the load/fix regions, the hulls against the ice and each other and the mooring layout solve
  (pice/platform/build.py).

Classes of input the table covers (issue 13 added the last six): unknown keys, wrong types,
non-physical values, rules between keys, missing files, invalid TOML, several problems at once;
solves at set-up that cannot converge; jobs larger than memory; outputs beyond the run; geometry
inside geometry; anything above the water that the physics assumes is below it; encodings.
"""

from __future__ import annotations

import re

from bad_job_kit import BASE, BODY, BUOY, FLOES, MOORING, NO_ICE, NUMBER_S, PLANE, SHIP, WATER, WAVES, add, case, sub

CASES = [
    # --- unknown keys (pydantic extra="forbid"): the message lists the allowed keys
    case("unknown_top_level_key", add("", 'colour = "blue"'),
         "colour = 'blue': unknown key; expected one of: run, gravity, water, ice, floes, waves, keel, bond, contact, walls"),
    case("study_file_as_job", '[study]\njob = "a.toml"\n\n[study.vary]\n"run.dt" = [1.0e-3, 2.0e-3]\n',
         "[study] (job = 'a.toml'): a study file, not a job; run it with: pice study "),
    case("unknown_key_in_section", add("ice", "thicknes = 2.0"),
         "ice.thicknes = 2.0: unknown key; expected one of: density, thickness, element_diameter, length"),
    case("unknown_key_in_wall", BASE + PLANE + "normal = [0.0, 0.0, 1.0]\ncolor = 3\n",
         "walls[0].color = 3: unknown key; expected one of: name, type, point, normal, vertices, file"),
    # --- wrong types: TOML has real numbers and booleans, so "1.0", 1 for true and 2.5 for a count are refused
    case("string_for_number", sub("thickness = 1.0", 'thickness = "1.0"'),
         "ice.thickness = '1.0': must be a number (m)"),
    case("word_for_number", sub("length = 4.0", 'length = "long"'),
         "ice.length = 'long': must be a number (m)"),
    case("number_for_bool", add("bond", "breakable = 1"),
         "bond.breakable = 1: must be true or false"),
    case("bool_for_number", sub("width = 3.0", "width = true"),
         "ice.width = true: must be a number (m)"),
    case("float_for_int", sub("snapshots = 1", "snapshots = 2.5"),
         "run.snapshots = 2.5: must be a whole number"),
    case("nan_quantity", sub("thickness = 1.0", "thickness = nan"),
         "ice.thickness = nan: must be a finite number (m)"),
    case("array_of_tables_for_table", BASE.replace("[ice]", "[[ice]]"),
         "ice = [{...}]: must be a table: write [ice], not [[ice]]"),
    case("missing_ice_section", BASE[:BASE.index("[ice]")] + BASE[BASE.index("[bond]"):],
         "ice = (absent): missing: a scene needs ice: give [ice]", "or [floes] (broken ice)"),
    # --- non-positive physical quantities (bounds in pice/job/schema.py, unit printed)
    case("thickness_negative", sub("thickness = 1.0", "thickness = -1.0"),
         "ice.thickness = -1.0: must be > 0 m"),
    case("density_zero", sub("density = 920.0", "density = 0.0"),
         "ice.density = 0.0: must be > 0 kg/m^3"),
    case("element_diameter_negative", sub("element_diameter = 1.0", "element_diameter = -0.5"),
         "ice.element_diameter = -0.5: must be > 0 m"),
    case("duration_zero", sub("duration = 0.01", "duration = 0.0"),
         "run.duration = 0.0: must be > 0 s"),
    case("water_density_negative", BASE + "\n[water]\ndensity = -1025.0\n",
         "water.density = -1025.0: must be > 0 kg/m^3"),
    case("gravity_negative", add("", "gravity = -9.81"),
         "gravity = -9.81: must be >= 0 m/s^2"),
    # --- ratios out of range
    case("poissons_ratio_0_6", sub("poissons_ratio = 0.3", "poissons_ratio = 0.6"),
         "ice.poissons_ratio = 0.6: must be < 0.5"),
    case("restitution_1_5", sub("restitution = 0.3", "restitution = 1.5"),
         "contact.restitution = 1.5: must be <= 1"),
    case("dt_safety_2", add("run", "dt_safety = 2"),
         "run.dt_safety = 2: must be <= 1"),
    # --- geometry of the HCP sheet (pice/scenes/level_ice.py needs one element across each dimension)
    case("thickness_below_element_diameter", sub("thickness = 1.0", "thickness = 0.5"),
         "ice.thickness = 0.5: must be >= ice.element_diameter = 1.0 m"),
    case("length_below_element_diameter", sub("length = 4.0", "length = 0.5"),
         "ice.length = 0.5: must be >= ice.element_diameter = 1.0 m"),
    # --- bond stiffness and strength (pice/physics/bond.py; Eqs. 6-7 of Zhu & Ji 2022)
    case("stiffness_missing", sub("youngs_modulus = 1.0e9", ""),
         "bond.normal_stiffness = (absent): missing: give bond.normal_stiffness [N/m] or ice.youngs_modulus [Pa]"),
    case("stiffness_given_twice", add("bond", "normal_stiffness = 1.0e8"),
         "bond.normal_stiffness = 100000000.0: give either bond.normal_stiffness [N/m] or ice.youngs_modulus",
         "not both"),
    case("strength_missing", sub("flexural_strength = 0.5e6", ""),
         "bond.normal_strength = (absent): missing: give bond.normal_strength [Pa] or ice.flexural_strength [Pa]"),
    case("eq7_negative_friction",
         sub("compressive_strength = 2.0e6", "compressive_strength = 6e5",
             sub("flexural_strength = 0.5e6", "flexural_strength = 5e5")),
         "ice.compressive_strength = 600000.0: must be >= ", "x ice.flexural_strength = 1.087e+06 Pa",
         "Eq. 7 gives a negative bond friction", "bond.friction"),
    case("poissons_ratio_0_4_single_layer", sub("poissons_ratio = 0.3", "poissons_ratio = 0.4"),
         "ice.poissons_ratio = 0.4: ", "single layer", "<= 1/3", setup=True),
    case("ice_denser_than_water", BASE + "\n[water]\ndensity = 900.0\n",
         "ice.density = 920.0: must be < water.density = 900.0 kg/m^3"),
    # --- time step (pice/physics/timestep.py)
    case("dt_word", add("run", 'dt = "fast"'),
         "run.dt = 'fast': must be 'auto' or a number (s)"),
    case("dt_negative", add("run", "dt = -1.0"),
         "run.dt = -1.0: must be 'auto' or > 0 s"),
    case("dt_above_stability_limit", sub("duration = 0.01", "duration = 3.0", add("run", "dt = 1.0")),
         "run.dt = 1.0: above the stability limit ", re.compile(r"stability limit " + NUMBER_S),
         re.compile(r"use dt <= " + NUMBER_S), setup=True),
    case("dt_not_below_duration", add("run", "dt = 0.01"),
         "run.dt = 0.01: must be < run.duration = 0.01 s"),
    # --- walls (pice/job/schema.py WallSpec; pice/physics/walls.py reads mesh files)
    case("plane_wall_without_normal", BASE + PLANE,
         "walls[0].normal = (absent): missing: a plane wall needs normal = [nx, ny, nz]"),
    case("plane_wall_zero_normal", BASE + PLANE + "normal = [0.0, 0.0, 0.0]\n",
         "walls[0].normal = [0.0, 0.0, 0.0]: must be a non-zero vector"),
    case("wall_type_unknown", BASE + '[[walls]]\ntype = "sphere"\n',
         "walls[0].type = 'sphere': must be one of 'plane', 'triangle' or 'mesh'"),
    case("triangle_two_vertices", BASE + '[[walls]]\ntype = "triangle"\nvertices = [[0, 0, 0], [1, 0, 0]]\n',
         "walls[0].vertices = [[0, 0, 0], [1, 0, 0]]: must have 3 entries, not 2"),
    case("triangle_degenerate",
         BASE + '[[walls]]\ntype = "triangle"\nvertices = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]\n',
         "walls[0].vertices = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]: degenerate triangle (zero area)"),
    case("mesh_wall_file_missing", BASE + '[[walls]]\ntype = "mesh"\nfile = "no_such_wall.stl"\n',
         "walls[0].file = 'no_such_wall.stl': file not found", "relative to the job file's folder"),
    case("mesh_wall_file_unreadable", BASE + '[[walls]]\ntype = "mesh"\nfile = "garbage.stl"\n',
         "walls[0].file = 'garbage.stl': cannot read the mesh (", "meshio-readable triangle mesh",
         files={"garbage.stl": b"\x00garbage\xff not an stl at all\n" * 5}, setup=True),
    case("mesh_wall_file_unreadable_vtk", BASE + '[[walls]]\ntype = "mesh"\nfile = "garbage.vtk"\n',
         "walls[0].file = 'garbage.vtk': cannot read the mesh (", "meshio-readable triangle mesh",
         files={"garbage.vtk": b"not a vtk file\n"}, setup=True),  # meshio prints and calls sys.exit(1) here
    case("mesh_wall_file_without_triangles", BASE + '[[walls]]\ntype = "mesh"\nfile = "empty.stl"\n',
         "walls[0].file = 'empty.stl': no triangles read from it", "meshio-readable triangle mesh",
         files={"empty.stl": b"\x00\xffthis is not an STL\xfe\x00" * 8}, setup=True),  # read as 0 facets
    # --- loads and fixes (pice/simulation.py selects elements by their initial centres)
    case("load_region_selects_nothing",
         BASE + "[[loads]]\nforce = [1.0e3, 0.0, 0.0]\n[loads.region]\nxmin = 100.0\n",
         "loads[0].region = {xmin = 100.0}: selects no element", "x 0.5 .. 3.5", setup=True),
    case("fix_velocity_word", BASE + '[[fixes]]\nvelocity = [0.0, "fixed", "free"]\n[fixes.region]\nxmax = 1.0\n',
         "fixes[0].velocity[1] = 'fixed': must be a number (m/s) or 'free'"),
    # --- bodies and moorings (pice/job/platform.py; set-up in pice/platform/)
    case("body_without_water", BASE + BODY, "bodies[0] = 'barge': a floating body needs a [water] table"),
    case("box_hull_without_size", BASE + WATER + BODY.replace('hull = {type = "box", size = [10.0, 8.0, 4.0]}',
                                                             'hull = {type = "box"}'),
         "bodies[0].hull.size = (absent): missing: a box hull needs size = [length, width, height] (m)"),
    case("mesh_hull_file_not_found", BASE + WATER + BODY.replace('{type = "box", size = [10.0, 8.0, 4.0]}',
                                                                '{type = "mesh", file = "ship.stl"}'),
         "bodies[0].hull.file = 'ship.stl': file not found"),
    case("prescribed_without_velocity", BASE + WATER + BODY + 'motion = "prescribed"\n',
         "bodies[0].velocity = (absent): missing: prescribed motion needs velocity = [[t, vx, vy, vz, wx, wy, wz]"),
    case("mooring_names_unknown_body", BASE + WATER + BODY + MOORING.replace('body = "barge"', 'body = "ship"'),
         "moorings[0].body = 'ship': must name one of the [[bodies]]: barge"),
    case("mooring_headings_count", BASE + WATER + BODY + MOORING.replace("headings = [0.0]", "headings = [0.0, 90.0]"),
         "moorings[0].headings = [0.0, 90.0]: must have one heading per fairlead (1), not 2"),
    case("mooring_without_depth", BASE + "[water]\n" + BODY + MOORING,
         "moorings[0] = 'barge': mooring lines need water.depth [m] (the seabed) in [water]"),
    case("anchor_below_seabed", BASE + WATER + BODY + MOORING.replace("anchor_depth = 48.0", "anchor_depth = 60.0"),
         "moorings[0].anchor_depth = 60.0: puts an anchor below the seabed at -50 m (water.depth = 50 m)"),
    case("hull_overlaps_ice", BASE + WATER + BODY.replace("position = [12.0, 1.5, 0.0]", "position = [8.9, 1.5, 0.0]"),
         "bodies[0] (barge): its hull overlaps", "ice element(s) at t = 0; move the body", setup=True),
    case("pretension_below_slack", BASE + WATER + BODY + MOORING.replace("pretension = 5.0e3", "pretension = 10.0"),
         "moorings[0].pretension = 10: a fairlead tension of 10 N is below the slackest static state",
         setup=True),
    # --- the moored buoy of seed 004 (issue 16): a "buoy" hull, a steel shell's mass, "afloat"
    case("buoy_cone_closes_before_keel", BASE + WATER + BUOY.replace("d_max = 9.0", "d_max = 4.0"),
         "bodies[0].hull.d_max = 4.0: the lower cone at alpha = 45 deg",
         "closes before the keel", "widen the buoy (d_max > 4 m) or steepen the cone (alpha > 45 deg)"),
    case("buoy_keel_above_widest", BASE + WATER + BUOY.replace("height = 3.0}", "height = 3.0, keel = 2.6}"),
         "bodies[0].hull.keel = 2.6: the keel cylinder (2.6 m high) must end below the widest section at 2.5 m"),
    case("buoy_without_alpha", BASE + WATER + BUOY.replace(" alpha = 45.0,", ""),
         "bodies[0].hull.alpha = (absent): missing: a buoy hull needs the downward-sloping hull angle [deg]"),
    case("buoy_alpha_vertical", BASE + WATER + BUOY.replace("alpha = 45.0", "alpha = 90.0"),
         "bodies[0].hull.alpha = 90.0: must be < 90 deg"),
    case("buoy_key_on_a_box", BASE + WATER + BODY.replace("size = [10.0, 8.0, 4.0]}", "size = [10.0, 8.0, 4.0], d_max = 9.0}"),
         "bodies[0].hull.d_max = 9.0: only for type = \"buoy\"; drop it (this hull is 'box')"),
    case("fairleads_and_inset", BASE + WATER + BODY + MOORING.replace("headings = [0.0]\n",
                                                                      "headings = [0.0]\nfairlead_inset = 0.5\n"),
         "moorings[0].fairleads", "give either fairleads", "or fairlead_inset", "not both or neither"),
    case("fairlead_inset_on_a_box", BASE + WATER + BODY + MOORING.replace("fairleads = [[17.0, 1.5, -2.0]]\n",
                                                                          "fairlead_inset = 0.5\n"),
         "moorings[0].fairlead_inset = 0.5: puts the fairleads on the keel of a hull of revolution",
         "give fairleads = [[x, y, z], ...] (m) instead"),
    case("anchor_on_the_seabed_two_depths", BASE + WATER + BODY + MOORING.replace(
         "fairleads = [[17.0, 1.5, -2.0]]\nheadings = [0.0]\n", "fairleads = [[17.0, 1.5, -2.0], [7.0, 1.5, -1.0]]\n"
         "headings = [0.0, 180.0]\n").replace("anchor_depth = 48.0", 'anchor_depth = "seabed"'),
         "moorings[0].anchor_depth = \"seabed\": needs every fairlead at one depth above the seabed",
         "give anchor_depth in m", setup=True),
    # --- the ridge keel of seed 002 (issue 15): rubble blocks under a cover (pice/job/keel.py)
    case("keel_without_water", NO_ICE + "[keel]\nwidth = 17.3\nlength = 30.0\n",
         "water = (absent): missing: a [keel]'s blocks rise against its cover by their buoyancy: give [water]"),
    case("keel_with_floes", NO_ICE + WATER + FLOES + "[keel]\nwidth = 17.3\nlength = 30.0\n",
         "floes.area = [0.0, 0.0, 100.0, 50.0]: a [keel] scene's rigid pieces are its blocks: drop [floes]"),
    case("keel_file_missing", NO_ICE + WATER + "[keel]\nwidth = 17.3\nlength = 30.0\n",
         "keel.file = ", "x.keel.h5': not found; generate it: pice keel ", setup=True),
    case("keel_too_narrow", NO_ICE + WATER + "[keel]\nwidth = 12.0\nlength = 30.0\n",
         "keel.width = 12.0: the sides at pile_angle = 30 deg meet above the keel's depth 5 m",
         "give width >= 17.23 m (a triangle)"),
    case("keel_two_dashpots", NO_ICE + WATER + "[keel]\nwidth = 17.3\nlength = 30.0\n"
         "contact = {damping = 1.75e4, damping_ratio = 0.3}\n",
         "keel.contact.damping_ratio = 0.3: damping is given too", "remove one"),
    case("keel_step_fraction_unstable", NO_ICE + WATER + "[keel]\nwidth = 17.3\nlength = 30.0\nstep_fraction = 0.4\n",
         "keel.step_fraction = 0.4: above 0.3, the largest step measured free of the blocks' corner instability",
         "give at most 0.3"),
    case("keel_lock_without_settle_friction", NO_ICE + WATER + "[keel]\nwidth = 17.3\nlength = 30.0\n"
         "lock_speed = 0.02\n",
         "keel.lock_speed = 0.02: it ends the settling friction, and settle_friction is not given",
         "give settle_friction (e.g. 0.0) or drop lock_speed"),
    case("keel_half_model_off_the_centreline", NO_ICE + WATER + "[keel]\nwidth = 17.3\nlength = 30.0\ny0 = 5.0\n"
         + SHIP.replace("stem_angle = 29.7}", "stem_angle = 29.7, half = true}"),
         "keel.y0 = 5.0: a half ship's model (hull.half = true) has its symmetry plane at the centreline y = 0",
         "give y0 = 0"),
    case("keel_end_after_peak_without_a_ship", NO_ICE + WATER + "[keel]\nwidth = 17.3\nlength = 30.0\n"
         "end_after_peak = 0.5\n",
         "keel.end_after_peak = 0.5: ends a ship's run once its resistance is past the peak, and the job has no "
         "[[bodies]]", "give the ship, or drop end_after_peak"),
    case("keel_end_after_peak_not_a_fraction", NO_ICE + WATER + "[keel]\nwidth = 17.3\nlength = 30.0\n"
         "end_after_peak = 1.5\n" + SHIP, "keel.end_after_peak = 1.5: must be < 1"),
    case("keel_lock_below_rest", NO_ICE + WATER + "[keel]\nwidth = 17.3\nlength = 30.0\n"
         "settle_friction = 0.0\nlock_speed = 0.001\n",
         "keel.lock_speed = 0.001: the friction would return only once the blocks are at rest",
         "give lock_speed > settle_speed"),
    # --- the ship of seed 002 (issue 15): a "ship" hull from Table 1's main dimensions (pice/platform/ship.py)
    case("ship_midbody_longer_than_length", BASE + WATER + SHIP.replace("midbody = 67.5", "midbody = 160.0"),
         "bodies[0].hull.midbody = 160.0: must be < length = 150 m"),
    case("ship_bow_does_not_fit", BASE + WATER + SHIP.replace("waterline_angle = 25.2", "waterline_angle = 5.0"),
         "bodies[0].hull.waterline_angle = 5.0: the bow at 5 deg is 126.9 m long on the waterline",
         "raise it above 7.663 deg or shorten the midbody"),
    case("ship_stem_vertical", BASE + WATER + SHIP.replace("stem_angle = 29.7", "stem_angle = 90.0"),
         "bodies[0].hull.stem_angle = 90.0: must be < 90 deg"),
    case("ship_stem_rakes_past_the_midbody", BASE + WATER + SHIP.replace("stem_angle = 29.7", "stem_angle = 5.0"),
         "bodies[0].hull.stem_angle = 5.0: the stem at 5 deg rakes 108.6 m over the draft", "raise it above 8.011 deg"),
    case("ship_without_breadth", BASE + WATER + SHIP.replace(" breadth = 22.2,", ""),
         "bodies[0].hull.breadth = (absent): missing: a ship hull needs the breadth [m]"),
    case("ship_deck_below_the_draft", BASE + WATER + SHIP.replace("stem_angle = 29.7}", "stem_angle = 29.7, depth = 8.0}"),
         "bodies[0].hull.depth = 8.0: must be > draft = 9.5 m (keel to deck)"),
    case("ship_key_on_a_box", BASE + WATER + BODY.replace("size = [10.0, 8.0, 4.0]}", "size = [10.0, 8.0, 4.0], half = true}"),
         "bodies[0].hull.half = true: only for type = \"ship\"; drop it (this hull is 'box')"),
    case("ship_with_a_shell_mass", BASE + WATER + SHIP.replace("mass = 2.1e7", 'mass = "shell"\nshell_thickness = 0.02'),
         "bodies[0].mass = 'shell': \"shell\" is not for a ship hull", "give the mass in kg"),
    case("shell_thickness_negative", BASE + WATER + BUOY.replace("0.0619", "-0.0619"),
         "bodies[0].shell_thickness = -0.0619: must be > 0 m"),
    case("shell_without_thickness", BASE + WATER + BUOY.replace("shell_thickness = 0.0619\n", ""),
         "bodies[0].shell_thickness = (absent): missing: mass = \"shell\" needs the shell's thickness t [m]"),
    case("inertia_missing", BASE + WATER + BODY.replace("inertia = [1.0e7, 2.0e7, 3.0e7]\n", ""),
         "bodies[0].inertia = (absent): missing: give [roll, pitch, yaw] moments (kg m^2)", "or mass = \"shell\""),
    case("afloat_with_balance_mass", BASE + WATER + BODY.replace("position = [12.0, 1.5, 0.0]", 'position = "afloat"'),
         "bodies[0].position = 'afloat': \"afloat\" floats the body at its mass", "give the mass"),
    case("buoy_too_heavy_to_float", BASE + WATER + BUOY.replace("0.0619", "0.5"),
         "bodies[0].position = \"afloat\": the hull cannot float: wholly under water it displaces",
         "lighten it (shell_thickness)", setup=True),
    # --- solves at set-up that cannot converge (the catenary of pice/platform/catenary.py is bounded
    # and ends in one line naming the key; lines it cannot hold are refused before it runs; issue 13:
    # ea = 1.0 raised OverflowError, ea = 1e-300 spun for minutes, pretension = 1e300 said "raise the
    # pretension"). With pretension_below_slack above (the layout solve has no root) and, in
    # tests/unit/test_job_errors.py, DEM lines that cannot settle within their relaxation budget.
    case("segment_ea_too_soft", BASE + WATER + BODY + MOORING.replace("ea = 1.0e8", "ea = 1.0"),
         "moorings[0].segments[0].ea = 1.0: must be >= 1000 N, a tenth of the line's wet weight (1e+04 N)",
         "more than ten-fold"),
    case("segment_ea_1e-300", BASE + WATER + BODY + MOORING.replace("ea = 1.0e8", "ea = 1e-300"),
         "moorings[0].segments[0].ea = 1e-300: must be >= 1000 N"),
    case("pretension_beyond_the_line", BASE + WATER + BODY + MOORING.replace("pretension = 5.0e3", "pretension = 1e300"),
         "moorings[0].pretension = 1e+300: must be < 1e+08 N, the axial stiffness moorings[0].segments[0].ea",
         "stretched to twice its length"),
    # --- jobs larger than memory (pice/memory.py: refused before the sheet is allocated; issue 13:
    # ice.length = 1e7 raised MemoryError). 1.2e10 elements: more than any machine has.
    case("sheet_larger_than_memory", sub("length = 4.0", "length = 1.0e7", sub("width = 3.0", "width = 1.0e3")),
         "ice.length = 1e+07: the sheet of 1.154e+10 elements needs", "TiB of particle arrays on each rank at set-up",
         re.compile(r"more than the [\d.,]+ [KMGT]iB available on this machine"), "shorten the sheet", setup=True),
    # --- outputs beyond the run (pice/io/output.py; issue 13: run.snapshots = 1e9 spent minutes)
    case("snapshots_beyond_the_run", sub("snapshots = 1", "snapshots = 1000000000"),
         "run.snapshots = 1000000000: more snapshots than the run has steps",
         re.compile(r"is \d+ steps, so at most \d+ snapshots"), "refused, not clamped", setup=True),
    # --- geometry inside geometry (pice/platform/build.py; issue 13: a hull around the sheet ran with no load)
    case("hull_contains_ice", BASE + WATER + BODY.replace("position = [12.0, 1.5, 0.0]", "position = [2.0, 1.5, 0.0]"),
         "bodies[0] (barge): its hull contains 11 ice element(s) at t = 0 (their centres lie inside it)",
         "move the body", setup=True),
    case("hulls_overlap", BASE + WATER + BODY + BODY.replace('"barge"', '"tug"').replace("[12.0, 1.5", "[18.0, 1.5"),
         "bodies[1] (tug): its hull overlaps that of bodies[0] (barge) at t = 0", "move one of them", setup=True),
    # --- above the water what the physics assumes below it (a line's wet weight)
    case("fairlead_above_water", BASE + WATER + BODY + MOORING.replace("[[17.0, 1.5, -2.0]]", "[[17.0, 1.5, 2.0]]"),
         "moorings[0].fairleads[0] = [17.0, 1.5, 2.0]: is above the water (z > water.level = 0 m)",
         "put the fairlead at or below the water level"),
    # --- encodings (pice/job/load.py; issue 13: a Latin-1 byte read as U+FFFD)
    case("job_not_utf8", BASE.encode().replace(b'name = "tiny"', b'name = "tin\xe9"'),
         "not UTF-8 text: byte offset 17 (line 2, column 12) holds 0xe9", "save the job file as UTF-8"),
    case("job_in_utf16", BASE.encode("utf-16"),
         "not UTF-8 text: byte offset 0 (line 1, column 1) holds 0xff", "the file is UTF-16"),
    # --- the file itself
    case("invalid_toml", sub("width = 3.0", "width = 3.0.0"),
         "not valid TOML: ", re.compile(r"line \d+")),
    case("job_file_not_found", None, "file not found: give the path of a TOML job file"),
    # --- scenes without level ice (issue 14): floes, waves
    case("floes_without_water", NO_ICE + FLOES, "water = (absent): missing: [floes] and [waves] need [water]"),
    case("walls_without_ice", NO_ICE + WATER + FLOES + PLANE + "normal = [0.0, 0.0, 1.0]\n", "walls = (absent): [[walls]] hold level-ice elements",
         "floes.sides"),
    case("floe_area_inverted", NO_ICE + WATER + FLOES.replace("[0.0, 0.0, 100.0, 50.0]", "[100.0, 0.0, 0.0, 50.0]"),
         "floes.area = [100.0, 0.0, 0.0, 50.0]", "x1 > x0"),
    case("waves_regular_with_period_kind", NO_ICE + WATER + FLOES + WAVES + 'period_kind = "mean"\n',
         "a regular wave has one period"),
    case("waves_on_level_ice_alone", BASE + WATER + WAVES, "waves = (absent): nothing in this scene feels waves",
         "drop [waves]"),
    case("waves_on_breakable_floes", sub("length = 4.0", "", sub("width = 3.0", "")) + WATER + FLOES
         + "breakable = true\n" + WAVES, "waves = (absent): breakable floes are level-ice elements",
         "drop floes.breakable"),
    # --- breakable floes: the floe field built of [ice] elements (pice/scenes/bonded_floes.py)
    case("breakable_floes_without_ice", NO_ICE + WATER + FLOES + "breakable = true\n",
         "ice = (absent): missing: breakable floes (floes.breakable = true) are built of [ice] elements"),
    case("breakable_floes_with_rigid_keys", BASE + WATER + FLOES + "breakable = true\nthickness = [1.0, 1.2]\n",
         "floes.thickness = [1.0, 1.2]: a key of rigid floes (given: thickness)", "drop them"),
    case("breakable_floes_with_sheet_keys", BASE + WATER + FLOES + "breakable = true\n",
         lines=[["ice.length = 4.0: the floe field places breakable floes", "drop ice.length"],
                ["ice.width = 3.0: the floe field places breakable floes", "drop ice.width"]]),
    case("breakable_floes_confined", sub("length = 4.0", "", sub("width = 3.0", "")) + WATER + FLOES
         + 'breakable = true\nsides = "confined"\n', "floes.sides = 'confined'", "give two planes",
         "point = [0, 0, 0] normal = [0, 1, 0] and point = [0, 50, 0] normal = [0, -1, 0]"),
    case("breakable_floes_too_small", sub("length = 4.0", "", sub("width = 3.0", "")) + WATER
         + FLOES.replace("concentration = 0.5", "concentration = 0.5\nsize = [2.0, 2.5]") + "breakable = true\n",
         "floes: ", "hold no element of diameter 1 m", "use smaller elements", setup=True),
    # --- genuinely several problems: one line each
    case("two_bad_values", sub("density = 920.0", "density = -3.0", sub("thickness = 1.0", "thickness = -1.0")),
         lines=[["ice.density = -3.0: must be > 0 kg/m^3"], ["ice.thickness = -1.0: must be > 0 m"]]),
    case("two_missing_rules", sub("flexural_strength = 0.5e6", "", sub("youngs_modulus = 1.0e9", "")),
         lines=[["bond.normal_stiffness = (absent): missing"], ["bond.normal_strength = (absent): missing"]]),
]
