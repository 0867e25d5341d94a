"""The virtual lab's small pieces (pice/lab): specimen sizes, rows, the loading program, the specimens'
held lines. No time stepping here; tests/physics/test_lab.py runs the experiments."""

import math

import numpy as np
import pytest
from scenes import job_from_text

from pice.lab.loading import RAMP_PERIODS, Program
from pice.lab.specimens import ROW, Size, cantilever, parse_size, rows_for, three_point_beam

SHEET = """
[ice]
thickness = 1.0
element_diameter = 1.0
element_volume = "cell"
youngs_modulus = 5.0e9
poissons_ratio = 0.3
flexural_strength = 0.5e6
compressive_strength = 2.5e6
"""


@pytest.mark.parametrize("text, size", [("20h", Size(20.0, "h")), ("12d", Size(12.0, "d")), ("15", Size(15.0)),
                                        ("15m", Size(15.0)), (" 2.5e1 m ", Size(25.0)), (".5h", Size(0.5, "h"))])
def test_parse_size(text, size):
    assert parse_size(text) == size


@pytest.mark.parametrize("text", ["", "-3", "0h", "3 km", "h", "1e"])
def test_parse_size_refuses(text):
    with pytest.raises(ValueError, match="positive length"):
        parse_size(text)


def test_size_in_metres():
    assert Size(20.0, "h").metres(thickness=1.5, element_size=0.5) == 30.0
    assert Size(12.0, "d").metres(thickness=1.5, element_size=0.5) == 6.0
    assert Size(7.0).metres(thickness=1.5, element_size=0.5) == 7.0


def test_default_width_is_the_same_at_the_three_element_sizes():
    """5.2 h for h = 1 m: 12, 6 and 3 rows of sqrt(3)/2 d, b = 5.196 m at d = 0.5, 1, 2 m."""
    assert [rows_for(5.2, d) for d in (0.5, 1.0, 2.0)] == [12, 6, 3]
    assert all(math.isclose(n * ROW * d, 3 * math.sqrt(3)) for n, d in ((12, 0.5), (6, 1.0), (3, 2.0)))


def test_program_is_smooth_then_constant_then_proportional():
    prog = Program.for_specimen(reference=0.01, period=0.2, periods=5.0)
    assert prog.ramp == pytest.approx(RAMP_PERIODS * 0.2) and prog.tau == pytest.approx(1.0)
    assert prog.velocity(0.0, 0.0) == 0.0
    assert prog.velocity(0.5 * prog.ramp, 0.0) == pytest.approx(0.5 * prog.speed)
    assert prog.velocity(prog.ramp, 0.005) == pytest.approx(prog.speed)
    # continuous at the reference displacement, then v = delta / tau
    assert prog.velocity(2.0, 0.01) == pytest.approx(prog.speed)
    assert prog.velocity(3.0, 0.04) == pytest.approx(0.04)


def test_beam_lines_are_straight_and_span_is_physical():
    """Supports and load are even-row elements on one line each; the span is 20 m at d = 1 and 2 m."""
    job = job_from_text(SHEET)
    for d, n_rows in ((1.0, 6), (2.0, 3)):
        s = three_point_beam(job, d=d, span=20.0, width=5.2)
        assert s.length == 20.0 and s.rows == n_rows
        load = s.x0[s.sets["load"]]
        assert np.allclose(load[:, 0], s.lines["load"]) and len(load) == (n_rows + 1) // 2
        sup = s.x0[s.sets["supports"], 0]
        assert set(np.round(sup, 9)) == {s.lines["support_left"], s.lines["support_right"]}
        p = s.sim.p
        assert p.fix_mask[s.sets["load"], 2].all() and not p.fix_mask[s.sets["load"], :2].any()
        assert p.fix_mask[:, 2].sum() == len(s.sets["load"]) + len(s.sets["supports"])


def test_cantilever_root_is_clamped_up_to_the_face():
    job = job_from_text(SHEET)
    s = cantilever(job, d=1.0, length=10.0, width=5.2, root=2.0)
    face, x0 = s.lines["clamp_face"], s.x0
    root = s.sets["root"]
    assert x0[root, 0].max() == pytest.approx(face)          # odd rows held to the face
    free = np.setdiff1d(np.arange(len(x0)), root)
    assert x0[free, 0].min() == pytest.approx(face + 0.5)     # even rows' first free element
    assert s.length == pytest.approx(10.5) and s.held_rotation == ("root",)
    assert s.sim.p.fix_mask[root].all()
