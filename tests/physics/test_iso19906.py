"""ISO 19906 global ice loads: crushing (Eq. 15 of Zhu & Ji 2022), the yardstick of the reference scene's ice
load, and level ice bending on a cone (A.8.2.4.4.2 Croasdale, A.8.2.4.4.3 Ralston; docs/iso19906.md)."""

import math

import pytest

from pice.physics.iso19906 import cone_load, crushing_load, ralston_cone_load


def test_the_papers_number():
    """Section 4.2 of ../shared/seeds/000_...: 40.1 (M)N for D = 50 m, h = 1 m (rounded to 0.1 MN)."""
    assert crushing_load(thickness=1.0, diameter=50.0) == pytest.approx(40.1e6, abs=0.05e6)


def test_thickness_exponent():
    """F_h grows as h^(1 + n - m): with n = -0.3 above 1 m, doubling h multiplies F_h by 2^0.86."""
    ratio = crushing_load(thickness=2.0, diameter=50.0) / crushing_load(thickness=1.0, diameter=50.0)
    assert ratio == pytest.approx(2.0 ** (1.0 - 0.3 + 0.16), rel=1e-12)
    with pytest.raises(ValueError, match="must be > 0"):
        crushing_load(thickness=0.0, diameter=50.0)


# --- sloping structures: ISO 19906 A.8.2.4.4.2 (Croasdale) and A.8.2.4.4.3 (Ralston) -------------------------
# The IceFloe worked example: OpenFAST modules/icefloe/test/GLA_Proto_flex_ISO.inp (DNV KEMA 2014, a 5 m
# cone at 60 deg) and its log GLA_proto_flex_ISO.log, which prints every term. That log was made with
# g = 9.81 (IceFloe's source now has 9.80665: with it every term moves by ~3e-4).
ICEFLOE_ISO = dict(diameter=5.0, angle_deg=60.0, thickness=1.0, flexural_strength=7.0e5, youngs_modulus=8.0e9,
                   poissons_ratio=0.3, ice_density=916.2, water_density=999.8, friction=0.15, ice_friction=0.05,
                   rubble_height=3.0, rubble_porosity=0.3, rubble_angle_deg=40.0, rubble_friction_angle_deg=45.0,
                   rubble_cohesion=0.0, gravity=9.81)
CONE_60 = dict(diameter=50.0, angle_deg=60.0, flexural_strength=0.5e6, youngs_modulus=5.0e9)  # the DEM's cone


def test_croasdale_reproduces_the_icefloe_example():
    """Every term of GLA_proto_flex_ISO.log to half a unit of its last printed digit (4-6 digits)."""
    c = cone_load(**ICEFLOE_ISO)
    assert c.rubble_push == pytest.approx(2242.0, abs=0.5)          # "Hp = 2242 Newtons"
    assert c.rubble_lift == pytest.approx(2.09678e5, abs=0.5)       # "Hl = 2.09678E+05"
    assert c.block_turn == pytest.approx(42609.0, abs=0.5)          # "Ht = 42609"
    assert c.ride_up == pytest.approx(4.08262e5, abs=0.5)           # "Hr = 4.08262E+05"
    assert c.breaking == pytest.approx(1.84414e6, abs=5.0)          # "Hb = 1.84414E+06"
    assert c.horizontal == pytest.approx(2.65997e6, abs=5.0)        # "Maximum static load ... 2.65997E+06"


def test_ralston_reproduces_the_icefloe_example():
    """GLA_proto_flex_IEC.log (IceFloe's Ralston per IEC 61400-3): 3.74475E+06 N, to half its last digit."""
    r = ralston_cone_load(diameter=5.0, top_diameter=1.5, angle_deg=60.0, thickness=1.0, flexural_strength=7.0e5,
                          ride_up_thickness=2.5, ice_density=916.2, water_density=999.8, friction=0.15,
                          gravity=9.81)
    assert r.horizontal == pytest.approx(3.74475e6, abs=5.0)
    assert r.horizontal == pytest.approx(r.breaking + r.ride_up, rel=1e-15)


def test_breaking_term_is_a_beam_on_an_elastic_foundation():
    """H_B / xi per metre (2D) is the end load breaking a semi-infinite beam on a Winkler foundation.

    Hetenyi (1946): M(x) = (V / beta) exp(-beta x) sin(beta x) peaks at beta x = pi/4; beta^4 = k / (4 EI),
    k = rho_w g, EI = E h^3 / 12; breaking at 6 M / h^2 = sigma_f gives V = sigma_f h^2 beta / (6 m_max) =
    3^(1/4) / (6 m_max) sigma_f (rho_w g h^5 / E)^(1/4) = 0.6804 (...): the standard's 0.68, within 1e-3.
    """
    for angle, mu in ((45.0, 0.0), (60.0, 0.15)):
        c = cone_load(diameter=1.0, angle_deg=angle, thickness=0.8, flexural_strength=0.6e6, youngs_modulus=4e9,
                      rubble_height=0.0, friction=mu, three_d=False, block_turning=False)
        a = math.radians(angle)
        xi = (math.sin(a) + mu * math.cos(a)) / (math.cos(a) - mu * math.sin(a))
        beta = (1035.0 * 9.81 / (4.0 * 4e9 * 0.8 ** 3 / 12.0)) ** 0.25
        v = 0.6e6 * 0.8 ** 2 * beta / (6.0 * math.exp(-math.pi / 4) * math.sin(math.pi / 4))
        assert c.breaking / xi == pytest.approx(v, rel=1e-3)
        assert c.vertical == pytest.approx(c.horizontal / xi, rel=1e-12)


def test_no_rubble_leaves_breaking_and_turning():
    """h_r = 0: H_P = H_R = H_L = 0 (all carry h_r); F_H = (H_B + H_T) amplified; the ride-up grows with h_r."""
    c = cone_load(thickness=1.0, rubble_height=0.0, **CONE_60)
    assert (c.rubble_push, c.ride_up, c.rubble_lift) == (0.0, 0.0, 0.0)
    assert c.horizontal == pytest.approx((c.breaking + c.block_turn) * c.amplification, rel=1e-12)
    rides = [cone_load(thickness=1.0, rubble_height=hr, **CONE_60) for hr in (0.5, 1.0, 2.0, 4.0)]
    for lower, upper in zip(rides, rides[1:]):
        assert upper.ride_up > lower.ride_up and upper.rubble_push > lower.rubble_push
        assert upper.rubble_lift > lower.rubble_lift and upper.horizontal > lower.horizontal
        assert upper.breaking == c.breaking and upper.block_turn == c.block_turn
    assert cone_load(thickness=1.0, rubble_height=0.0, block_turning=False, **CONE_60).block_turn == 0.0


def test_load_grows_with_angle_and_the_cone_is_wider_than_its_waterline():
    """xi = (sin a + mu cos a)/(cos a - mu sin a) rises with a, and H_B with it; F_H too from 45 deg on (below,
    H_T = 1.5 w h^2 rho_i g cos a / (sin a - mu cos a) grows as the slope flattens). The 3D crack
    (w + pi^2 L_c / 4) raises H_B over the 2D width w."""
    loads = [cone_load(thickness=1.0, rubble_height=1.0, rubble_angle_deg=20.0, angle_deg=a,
                       **{k: v for k, v in CONE_60.items() if k != "angle_deg"}) for a in (30, 45, 55, 60, 65, 70)]
    assert all(b.breaking > a.breaking for a, b in zip(loads, loads[1:]))
    assert all(b.horizontal > a.horizontal for a, b in zip(loads[1:], loads[2:]))
    assert loads[0].block_turn > loads[1].block_turn
    two_d = cone_load(thickness=1.0, rubble_height=0.0, three_d=False, **CONE_60)
    three_d = cone_load(thickness=1.0, rubble_height=0.0, **CONE_60)
    l_c = (5e9 / (12 * 1035 * 9.81 * (1 - 0.09))) ** 0.25
    assert three_d.breaking / two_d.breaking == pytest.approx((50 + math.pi ** 2 * l_c / 4) / 50, rel=1e-12)


def test_downward_breaking_takes_the_buoyancy():
    """A downward-breaking cone: same H_B (the same water foundation); the ride-down terms with
    (rho_w - rho_i) g in place of rho_i g, so H_T scales by (1035 - 920) / 920 exactly."""
    up = cone_load(thickness=1.0, rubble_height=2.0, **CONE_60)
    down = cone_load(thickness=1.0, rubble_height=2.0, downward=True, **CONE_60)
    assert down.breaking == up.breaking
    assert down.block_turn == pytest.approx(up.block_turn * 115.0 / 920.0, rel=1e-12)
    assert down.ride_up < up.ride_up and down.horizontal < up.horizontal


def test_ralston_ride_up_without_friction_is_the_weight_on_the_front_half_times_tan_alpha():
    """mu = 0: ice of thickness h_r on the front half of the frustum, weight per unit azimuth
    rho_i g h_r (R^2 - R_T^2) / (2 cos a), each part needing tan(a) cos(beta) of it horizontally:
    integral over beta in (-pi/2, pi/2) = rho_i g h_r (D^2 - D_T^2) tan a / (4 cos a) (our derivation)."""
    a = math.radians(55.0)
    r = ralston_cone_load(diameter=20.0, top_diameter=8.0, angle_deg=55.0, thickness=1.2, flexural_strength=0.5e6,
                          ride_up_thickness=0.6, friction=0.0)
    assert r.ride_up == pytest.approx(920 * 9.81 * 0.6 * (20.0 ** 2 - 8.0 ** 2) * math.tan(a) / (4 * math.cos(a)),
                                      rel=1e-12)
    none = ralston_cone_load(diameter=20.0, top_diameter=20.0, angle_deg=55.0, thickness=1.2,
                             flexural_strength=0.5e6, ride_up_thickness=0.6)
    assert none.ride_up == 0.0 and none.horizontal == none.breaking
    assert none.breaking > r.breaking  # friction: tan(a) / (1 - mu g_R) > tan(a)


def test_thickness_trend_of_the_60_degree_cone():
    """The reference the DEM cone runs (60 deg, 50 m waterline, sigma_f 0.5 MPa, E 5 GPa, no rubble) are set
    beside, h = 0.6-1.6 m. Pinned (rel 1e-4) so it cannot drift: F_H [MN] of this module, checked through the
    IceFloe example above. The trend follows from the formula: H_B ~ h^(5/4) (w + pi^2 L_c / 4) with
    L_c ~ h^(3/4), so its log-slope lies in (1.25, 2); the amplification (~ h^(1/4)) and H_T (~ h^2) add to
    F_H's. From 1.0 to 1.6 m F_H rises 2.2-fold, Eq. 15's crushing load 1.5-fold."""
    pinned = {0.6: 1.5258, 0.8: 2.4080, 1.0: 3.4587, 1.2: 4.6745, 1.4: 6.0531, 1.6: 7.5929}
    loads = {h: cone_load(thickness=h, rubble_height=0.0, **CONE_60) for h in pinned}
    for h, f_h in pinned.items():
        assert loads[h].horizontal / 1e6 == pytest.approx(f_h, rel=1e-4)
    hs = sorted(pinned)
    for h0, h1 in zip(hs, hs[1:]):
        slope_b = math.log(loads[h1].breaking / loads[h0].breaking) / math.log(h1 / h0)
        slope_h = math.log(loads[h1].horizontal / loads[h0].horizontal) / math.log(h1 / h0)
        assert 1.25 < slope_b < 2.0 and slope_b < slope_h < 2.0
    assert loads[1.6].horizontal / loads[1.0].horizontal == pytest.approx(2.195, abs=0.001)
    crush = crushing_load(thickness=1.6, diameter=50.0) / crushing_load(thickness=1.0, diameter=50.0)
    assert crush == pytest.approx(1.498, abs=0.001)


def test_cone_inputs_out_of_range_say_so():
    with pytest.raises(ValueError, match="rubble_angle_deg"):
        cone_load(thickness=1.0, rubble_height=1.0, rubble_angle_deg=60.0, **CONE_60)
    with pytest.raises(ValueError, match="cannot slide up"):
        cone_load(thickness=1.0, rubble_height=0.0, friction=0.7, **CONE_60)
    with pytest.raises(ValueError, match="must be > 0"):
        cone_load(thickness=0.0, rubble_height=0.0, **CONE_60)
    with pytest.raises(ValueError, match="top_diameter"):
        ralston_cone_load(diameter=10.0, top_diameter=12.0, angle_deg=60.0, thickness=1.0, flexural_strength=5e5,
                          ride_up_thickness=0.0)


def test_the_table_command(capsys):
    """``python -m pice.physics.iso19906``: one row per thickness; Eq. 15 gives 40.11 MN at 1 m."""
    from pice.physics.iso19906 import main

    assert main([]) == 0
    rows = [line.split() for line in capsys.readouterr().out.splitlines() if line[:6].strip()[:1].isdigit()]
    assert [row[0] for row in rows] == ["1.00", "1.20", "1.40", "1.60"]
    assert rows[0][1] == "40.11" and rows[0][3] == "3.46"
