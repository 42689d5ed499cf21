"""Loads: upsetting law, springs, tables, bad input."""

import numpy as np
import pytest

from mechsynth.dynamics.inertia import LinkInertia
from mechsynth.dynamics.loads import Gravity, TabulatedLoad, TorsionSpring, upsetting_force
from mechsynth.machines.nail_header.model import NailHeader


def test_upsetting_force_paper_003():
    # F_e0 = 850 (1 + 0.3 * 3 / 60) pi 9 / 4 and c1 l_e^4 with l_e = 3 mm at s_B = 0 (paper 003)
    f0 = 850 * (1 + 0.3 / 3 * 3 / 20) * np.pi * 9 / 4
    assert upsetting_force(0.0) == pytest.approx(f0 + 571 * 3**4, rel=1e-12)
    assert upsetting_force(0.003) == 0.0 and upsetting_force(0.01) == 0.0
    assert upsetting_force(0.002) == pytest.approx(f0 + 571.0, rel=1e-12)
    assert 52300 < upsetting_force(0.0) < 52400  # "about 52.3 kN" (seeds notes)


def test_spring_moment_and_sense():
    nh = NailHeader()
    m = nh.motion(np.array([0.0, -np.pi]), speed=nh.omega)
    sp = TorsionSpring("ejector", "ejector", 1.75, 4.125, nh.phi50, sense=-1)
    mom = sp.moment(m)
    assert mom[0] == pytest.approx(1.75)
    twist = m.links["ejector"].angle[1] - nh.phi50
    assert mom[1] == pytest.approx(1.75 + 4.125 * twist)
    assert sp.contributions(m, {})[0].tz[1] == pytest.approx(-mom[1])


def test_table_periodic_interpolation(tmp_path):
    p = tmp_path / "card.csv"
    p.write_text("angle,force\n0,0\n90,10\n180,0\n270,-10\n")
    t = TabulatedLoad.from_csv(p, "angle", "force", period=360.0)
    np.testing.assert_allclose(t([45.0, 315.0, 360.0, 405.0]), [5.0, -5.0, 0.0, 5.0])


def test_table_errors(tmp_path):
    with pytest.raises(ValueError, match="'angle' must be strictly increasing"):
        TabulatedLoad([0, 2, 1], [0, 1, 2], x_field="angle")
    with pytest.raises(ValueError, match="more than the period"):
        TabulatedLoad([0, 400], [0, 1], period=360.0)
    t = TabulatedLoad([0, 1], [0, 1], x_field="stroke")
    with pytest.raises(ValueError, match="'stroke' covers"):
        t([2.0])
    with pytest.raises(ValueError, match="force must be finite"):
        TabulatedLoad([0, 1], [0, np.nan], y_field="force")
    p = tmp_path / "bad.csv"
    p.write_text("a,b\n0,1\n")
    with pytest.raises(ValueError, match="no column 'force'"):
        TabulatedLoad.from_csv(p, "a", "force")


def test_bad_masses_named():
    with pytest.raises(ValueError, match="m3 must not be negative"):
        NailHeader(m3=-1.0)
    with pytest.raises(ValueError, match="j_s1 must be finite"):
        NailHeader(j_s1=np.nan)
    with pytest.raises(ValueError, match="mass of rod"):
        LinkInertia("rod", "A", -2.0)
    with pytest.raises(ValueError, match="gravity g"):
        Gravity(g=-9.8)
    with pytest.raises(ValueError, match="spring stiffness"):
        TorsionSpring("e", "e", 1.0, -1.0, 0.0)
