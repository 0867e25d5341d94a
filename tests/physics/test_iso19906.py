"""ISO 19906 crushing load (Eq. 15 of Zhu & Ji 2022), the yardstick of the reference scene's ice load."""

import pytest

from pice.physics.iso19906 import crushing_load


def test_the_papers_number():
    """Section 4.2 of ../shared/seeds/000_...: 40.1 (M)N for D = 50 m, h = 1 m (rounded to 0.1 MN)."""
    assert crushing_load(thickness=1.0, diameter=50.0) == pytest.approx(40.1e6, abs=0.05e6)


def test_thickness_exponent():
    """F_h grows as h^(1 + n - m): with n = -0.3 above 1 m, doubling h multiplies F_h by 2^0.86."""
    ratio = crushing_load(thickness=2.0, diameter=50.0) / crushing_load(thickness=1.0, diameter=50.0)
    assert ratio == pytest.approx(2.0 ** (1.0 - 0.3 + 0.16), rel=1e-12)
    with pytest.raises(ValueError, match="must be > 0"):
        crushing_load(thickness=0.0, diameter=50.0)
