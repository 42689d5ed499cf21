"""The fast paths of one design's motion: they give what the general code gives."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.errors import MechanismError
from mechsynth.kinematics import ops
from mechsynth.kinematics.tracks import Jet, LinkTrack, Motion, PointJet, PointTrack, SliderTrack


def _arrays(m):
    out = [x for p in m.points.values() for x in vars(p).values()]
    out += [x for k in m.links.values() for x in vars(k).values()]
    out += [x for s in m.sliders.values() for x in vars(s).values()]
    return [*out, m.pressure_angle, m.transmission_angle]


def test_quick_constructors_fill_every_field():
    """``from_jet`` and ``Motion.of`` skip the frozen dataclasses' ``__init__``; the objects they
    build hold exactly the fields the ``__init__`` would set, and stay frozen."""
    x = np.linspace(0.0, 1.0, 5)
    p = PointTrack.from_jet(PointJet(x, x + 1, x + 2, x + 3, x + 4, x + 5), 1.0, 0.0)
    assert list(vars(p)) == [f.name for f in dataclasses.fields(PointTrack)]
    assert all(np.array_equal(v, x + k) for k, v in enumerate(vars(p).values()))
    for cls in (LinkTrack, SliderTrack):
        t = cls.from_jet(Jet(x, x + 1, x + 2), 1.0, 0.0)
        assert list(vars(t)) == [f.name for f in dataclasses.fields(cls)]
        with pytest.raises(dataclasses.FrozenInstanceError):
            t.omega = x
    m = ms.FourBar(1.0, 4.3, 3.0, 5.2).motion(ms.cycle(8))
    assert list(vars(m)) == [f.name for f in dataclasses.fields(Motion)]
    assert m.extra == {} and m.pressure_angles == {} and m.transmission_angles == {}
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.phi = None


@pytest.mark.parametrize(
    "mech", [ms.FourBar(1.0, 4.3, 3.0, 5.2), ms.SliderCrank(0.07, 0.24, 0.01)], ids=str
)
def test_motion_outputs_are_separate_arrays(mech):
    """No two outputs of a motion share memory: changing one in place leaves the others."""
    arrays = _arrays(mech.motion(ms.cycle(36)))
    for i, a in enumerate(arrays):
        assert a.shape == (36,)
        assert not any(np.shares_memory(a, b) for b in arrays[i + 1 :]), i


def test_remembered_cosines_follow_the_grid():
    phi = ms.cycle(16)
    c, s = ops.cos_sin(phi)
    np.testing.assert_array_equal(c, np.cos(phi))
    np.testing.assert_array_equal(s, np.sin(phi))
    phi[3] += 0.5  # edited in place: not mistaken for the grid remembered
    c, s = ops.cos_sin(phi)
    assert c[3] == np.cos(phi[3]) and s[3] == np.sin(phi[3])
    # the motion sees the edit too
    m = ms.SliderCrank(0.07, 0.24).motion(phi)
    assert m.points["A"].x[3] == pytest.approx(0.07 * np.cos(phi[3]), abs=1e-15)


def test_angle_checks_of_the_quick_path():
    """The finite test by a sum: huge finite angles pass (without a warning), NaN and inf do
    not."""
    sc = ms.SliderCrank(0.07, 0.24)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert sc.motion(np.array([1e300, 1e300, 0.5])).slider.position.shape == (3,)
    for bad in (np.nan, np.inf):
        with pytest.raises(MechanismError, match="crank angles must be finite"):
            sc.motion(np.array([0.1, bad]))


def test_transmission_angle_is_the_angle_between_the_links():
    fb = ms.FourBar(1.0, 4.3, 3.0, 5.2)
    m = fb.motion(ms.cycle(360))
    t1, t2 = m.links["coupler"].angle, m.links["rocker"].angle
    mu = m.raw_transmission_angle
    np.testing.assert_allclose(mu, np.arccos(np.cos(t1 - t2)), atol=1e-12)
    # directly from the link vectors A -> B and O2 -> B
    a, b = m.points["A"], m.points["B"]
    u = np.stack([b.x - a.x, b.y - a.y])
    v = np.stack([b.x - fb.ground, b.y])
    cos = np.sum(u * v, axis=0) / (fb.coupler * fb.rocker)
    np.testing.assert_allclose(np.cos(mu), cos, atol=1e-12)
    np.testing.assert_allclose(m.pressure_angle, np.abs(np.pi / 2 - mu), atol=0)
    # the design quantity is the raw angle folded into [0, 90] deg, obtuse angles counted as
    # their supplement; this four-bar's raw angle is obtuse over part of the cycle
    assert mu.max() > np.pi / 2 > mu.min()
    np.testing.assert_array_equal(m.transmission_angle, np.minimum(mu, np.pi - mu))
    assert m.transmission_angle.max() <= np.pi / 2
    assert m.transmission_angle.min() == pytest.approx(
        float(ms.objectives.min_transmission_angle().from_motion(fb, m)), abs=1e-12
    )


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), float("inf"), 1e101])
@pytest.mark.parametrize("name", ["crank", "coupler", "rocker", "ground"])
def test_one_four_bar_refuses_bad_lengths(name, bad):
    """The quick path of one numeric design checks what the general one does."""
    dims = {"crank": 1.0, "coupler": 4.3, "rocker": 3.0, "ground": 5.2, name: bad}
    with pytest.raises(MechanismError, match=name):
        ms.FourBar(**dims)


@pytest.mark.parametrize(
    "dims",
    [
        {"crank": float("nan"), "rod": 0.24},
        {"crank": 0.07, "rod": float("inf")},
        {"crank": 0.07, "rod": 0.24, "offset": float("nan")},
        {"crank": 0.07, "rod": 0.24, "offset": float("-inf")},
        {"crank": 0.07, "rod": 0.24, "offset": 0.2},
        {"crank": -0.07, "rod": 0.24},
    ],
)
def test_one_slider_crank_refuses_bad_dimensions(dims):
    with pytest.raises(MechanismError):
        ms.SliderCrank(**dims)


def test_one_four_bar_options_still_checked():
    with pytest.raises(MechanismError, match="branch"):
        ms.FourBar(1.0, 4.3, 3.0, 5.2, branch=["open"])
    with pytest.raises(MechanismError, match="full_turn"):
        ms.FourBar(1.0, 4.3, 3.0, 5.2, full_turn=1)
    with pytest.raises(MechanismError, match="full turn"):
        ms.FourBar(3.0, 4.3, 1.0, 5.2)
    assert ms.FourBar(3.0, 4.3, 1.0, 5.2, full_turn=False).crank == 3.0


@pytest.mark.parametrize(
    "mech", [ms.FourBar(1.0, 4.3, 3.0, 5.2), ms.SliderCrank(0.07, 0.24, 0.01)], ids=str
)
def test_constant_tracks_at_a_speed(mech):
    """The crank's and the frame pivots' tracks are made, not scaled: the crank turns at the
    speed and acceleration asked, the pivots stand still; the moving points scale."""
    phi = ms.cycle(24)
    m, ref = mech.motion(phi, speed=3.0, epsilon=2.0), mech.motion(phi)
    crank = m.links["crank"]
    np.testing.assert_array_equal(crank.angle, phi)
    assert np.all(crank.omega == 3.0) and np.all(crank.epsilon == 2.0)
    pivot = m.points["O" if "O" in m.points else "O1"]
    assert all(np.all(v == 0.0) for v in vars(pivot).values())
    b, b0 = m.points["B"], ref.points["B"]
    np.testing.assert_allclose(b.vx, 3.0 * b0.vx, rtol=1e-15)
    np.testing.assert_allclose(b.ax, 9.0 * b0.ax + 2.0 * b0.vx, rtol=1e-14, atol=1e-15)


def test_numeric_helpers_of_ops():
    x = np.arange(3.0)
    y = ops.plus(0.0, x)
    assert y is not x and np.array_equal(y, x)
    assert ops.plus(0, np.arange(3)).dtype.kind == "i"  # an integer array: the sum's type
    assert ops.plus(0.0, np.arange(3)).dtype == np.float64
    np.testing.assert_array_equal(ops.plus(1.5, x), x + 1.5)
    f = ops.full_like(x, 2.0)
    assert f.shape == (3,) and np.all(f == 2.0)
    np.testing.assert_array_equal(
        ops.full_like(x, np.array([[1.0], [2.0]])), [[1.0] * 3, [2.0] * 3]
    )
    rows = ops.zero_rows(x, 4)
    assert len(rows) == 4 and all(r.shape == (3,) and not r.any() for r in rows)
    rows[0][0] = 1.0
    assert not rows[1].any()
    assert ops.is_zero(0.0) and ops.is_zero(0) and not ops.is_zero(np.zeros(1))
    assert not ops.is_zero(1e-300) and not ops.is_zero(False)


def test_finite_test_of_ops():
    """One pass finds a NaN or an infinity anywhere; an entry whose square overflows gives
    False too (its callers then test entry by entry), a huge finite one passes those."""
    x = np.linspace(-3.0, 3.0, 12).reshape(3, 4)
    assert ops.finite(x) and ops.finite(x[:, ::2]) and ops.finite(np.zeros(0))
    for bad in (np.nan, np.inf, -np.inf, 1e200):
        y = x.copy()
        y[2, 1] = bad
        assert not ops.finite(y), bad
    big = np.ones((3, 5000))  # past the dot product's size: a sum
    assert ops.finite(big) and ops.finite(1e300 * big)
    for bad in (np.nan, np.inf, -np.inf):
        y = big.copy()
        y[1, 4321] = bad
        assert not ops.finite(y), bad
    # a dyad whose second analogs are past 1e154 but finite: no error, as without the quick test
    from mechsynth.kinematics.blocks import dyad_rrp

    y = np.array([0.5, -0.25])
    p = PointJet(0.0 * y, y, 0.0 * y, 0.0 * y, 0.0 * y, 1e200 + 0.0 * y)
    _, s, _ = dyad_rrp(p, 1.0, phi=np.array([0.1, 0.2]))
    assert np.all(np.isfinite(s.d2)) and np.min(np.abs(s.d2)) > 1e199


def test_one_design_batches_as_many():
    """A batch of one design (checked and sorted on numbers) gives what a batch of several
    gives for it, refuses what the batch refuses, and builds every field."""
    from mechsynth.kinematics import compiled

    phi = ms.cycle(24)
    for fn, dims in (
        (compiled.four_bar_batch, (1.0, 4.3, 3.0, 5.2)),
        (compiled.slider_crank_batch, (0.07, 0.24, 0.01)),
    ):
        for speed in (None, 3.0):
            one = fn(*dims, phi, speed=speed)
            two = fn(*(np.array([x, 1.1 * x]) for x in dims), phi, speed=speed)
            cls = type(one)
            assert list(vars(one)) == [f.name for f in dataclasses.fields(cls)]
            for f in compiled._FIELDS[cls]:
                np.testing.assert_array_equal(getattr(one, f)[0], getattr(two, f)[0])
            with pytest.raises(dataclasses.FrozenInstanceError):
                one.backend = "x"
    for bad in ((1.0, 1.0, 1.0, 5.2), (1.0, np.nan, 3.0, 5.2), (-1.0, 4.3, 3.0, 5.2)):
        with pytest.raises(MechanismError):
            compiled.four_bar_batch(*bad, phi)
    with pytest.raises(MechanismError):
        compiled.four_bar_batch(1.0, 1.0, 1.0, 5.2, phi, full_turn=False)  # cannot assemble
    r = compiled.four_bar_batch(2.0, 2.5, 1.0, 3.0, np.array([1.0]), full_turn=False)
    assert np.isfinite(r.rocker_epsilon).all()  # a crank that does not turn fully, assembled
    for bad in ((0.1, 0.1, 0.0), (0.1, 0.3, 0.25), (0.1, 0.3, np.inf), (0.0, 0.3, 0.0)):
        with pytest.raises(MechanismError):
            compiled.slider_crank_batch(*bad, phi)
    # the designs sent to the numpy model near a toggle: the same on numbers as on arrays
    for near, p, grid in (
        (compiled._slider_crank_near, (0.1, 0.1 + 1e-11, 0.0), ()),
        (compiled._slider_crank_near, (0.1, 0.3, 0.05), ()),
        (compiled._four_bar_near, (1.0, 3.0, 3.0, 5.0), (1.0, -1.0)),
        (compiled._four_bar_near, (1.0, 4.3, 3.0, 5.2), (1.0, -1.0)),
    ):
        names = ("crank", "b", "c", "d")[: len(p)]
        one = compiled._rows(near, {k: np.array([x]) for k, x in zip(names, p)}, *grid)
        two = compiled._rows(near, {k: np.array([x, x]) for k, x in zip(names, p)}, *grid)
        np.testing.assert_array_equal(np.concatenate([one, one + 1]), two)


def test_dyads_quiet_only_their_own_warnings():
    """The dyads' warning guard ignores 0/0 and x/0 inside them and nothing else: the caller's
    other error handling holds inside, a changed one is followed, and the caller's is back
    after the call, also after an error."""
    from mechsynth.kinematics import blocks

    probe = blocks._toggles_raise(np.geterr)
    with np.errstate(over="raise", divide="warn", invalid="warn"):
        inside = probe()
        assert inside["over"] == "raise"
        assert inside["divide"] == "ignore" and inside["invalid"] == "ignore"
        assert np.geterr()["divide"] == "warn" and np.geterr()["invalid"] == "warn"
    with np.errstate(over="ignore", under="raise"):
        inside = probe()
        assert inside["over"] == "ignore" and inside["under"] == "raise"
    before = np.geterr()

    def fails():
        raise MechanismError("inside")

    with pytest.raises(MechanismError, match="inside"):
        blocks._toggles_raise(fails)()
    assert np.geterr() == before
    # a four-bar that cannot be assembled at some angles: the error, no numpy warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(MechanismError, match="cannot be assembled"):
            ms.FourBar(3.0, 4.3, 1.0, 5.2, full_turn=False).motion(ms.cycle(36))
    assert np.geterr() == before
