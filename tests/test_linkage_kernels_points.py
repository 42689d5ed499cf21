"""Batches on the kernel of the points alone (``linkage_batch(..., outputs="points")``): every
point's track the model's to 1e-12 on random designs of a Watt II and a Stephenson III six-bar
on both code generators, views of the kernel's block; what such a batch does not compute is
absent, not zeros; its flags tell the designs the model cannot assemble as the full kernel's
do. And the one-design paths (``one_motion``, ``linkage_batch`` of one design) against the
model and against each other."""

import numpy as np
import pytest
import test_linkage_kernels
from test_linkage import FIELDS, six_link

import mechsynth as ms
from mechsynth.errors import MechanismError
from mechsynth.kinematics import linkage_kernels as lkk
from mechsynth.kinematics.compiled import BatchWorkspace

backend = test_linkage_kernels.backend  # the code generator's fixture, C and numba
PHI = ms.cycle(72)


@pytest.fixture(params=["c", pytest.param("numba", marks=pytest.mark.slow)])
def backend_c_first(request, monkeypatch):
    """As ``backend``, numba's runs among the slow tests: they compile the six-bars' kernels
    of every output too (some 10 s each with numba on an empty cache)."""
    monkeypatch.setenv(lkk.BACKEND_ENV, request.param)
    if lkk.kernel_backend() != request.param:
        pytest.skip(f"no {request.param} kernels on this machine")
    return request.param


def four_bar():
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.10, 0.0)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.10), ("D", 0.07))
    )


def watt_ii():
    """Two four-bars in series: a point K on the first rocker DB drives the dyad K-E-F."""
    lk = four_bar().attach("K", on="DB", along=0.05, left=0.02).ground_point("F", 0.16, 0.06)
    return lk.rrr("E", ("K", 0.08), ("F", 0.06))


def stephenson_iii():
    """A point C on the four-bar's coupler AB drives the dyad C-E-F."""
    lk = four_bar().attach("C", on=("A", "B"), along=0.05, left=0.03)
    return lk.ground_point("F", 0.06, 0.12).rrr("E", ("C", 0.07), ("F", 0.08))


SIX_BARS = {"Watt II": watt_ii, "Stephenson III": stephenson_iii}


def random_designs(lk, n, spread, seed):
    """``n`` designs of ``lk``: every length scaled by a factor in ``1 +- spread`` and every
    other parameter (ground coordinates, the attached points' offsets) moved by up to
    ``spread`` times the crank's length, as ``(n, 1)`` arrays; every fifth design's crank
    2.5 times as long (most of those cannot be assembled)."""
    rng = np.random.default_rng(seed)
    crank = lk.parameters["OA"]
    values = {}
    for k, v in lk.parameters.items():
        kind = lk.parameter_kinds[k]
        if kind == "length":
            values[k] = v * (1.0 + rng.uniform(-spread, spread, (n, 1)))
        elif kind != "angle":
            values[k] = v + spread * crank * rng.uniform(-1.0, 1.0, (n, 1))
    values["OA"][::5] *= 2.5
    return lk(**values)


def _rows_of(batch, i):
    """Design ``i`` of a batch of ``(n, 1)`` parameter arrays, as numbers."""
    return batch(**{k: float(np.ravel(v)[i]) for k, v in batch.parameters.items() if np.ndim(v)})


def _close(a, b, what, tol=1e-12):
    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    err = np.max(np.abs(a - b)) / max(1.0, float(np.max(np.abs(b))))
    assert err < tol, (what, err)


@pytest.mark.parametrize("name", list(SIX_BARS))
@pytest.mark.parametrize("speed", [None, ms.rpm(600)])
def test_a_batch_of_the_points_alone_is_the_models(name, speed, backend):
    """Random designs: those the points' kernel marks good have every point's track the
    model's to 1e-12 (positions, velocities, accelerations, the ground points' too, in the
    model's order), as views of the workspace's block; those it marks failed the model cannot
    assemble; the rest are few (toggles, round-off). Nothing else is in the motion."""
    lk = SIX_BARS[name]()
    batch = random_designs(lk, 40, 0.25, seed=31)
    ws = BatchWorkspace()
    got = lkk.linkage_batch(batch, PHI, speed, ws, outputs="points")
    assert got is not None
    motion, good, failed = got
    kernel = lkk.linkage_kernel(lk, outputs="points")
    assert kernel.backend == backend and kernel.kinds == "points"
    assert good.any() and failed.any() and not (good & failed).any()
    assert np.count_nonzero(~good & ~failed) <= 2
    block = ws.block(40, PHI.size, rows=kernel.outputs)
    assert list(motion.points) == list(lk.motion(PHI).points)
    ground = {k for k, t in lk.motion(PHI).points.items() if not np.any(t.vx) and not np.any(t.vy)}
    assert ground == {"O", "D", "F"}
    for key, track in motion.points.items():
        for f in FIELDS:
            v = getattr(track, f)
            assert v.shape == (40, PHI.size) and np.shares_memory(v, block), f
            # a ground point's rows are written once per design and read along the inputs
            assert v.flags.writeable == (key not in ground), (key, f)
    # what the kernel of the points does not compute is absent, not zeros
    assert motion.links == {} and motion.sliders == {} and motion.extra == {}
    assert motion.pressure_angles == {} and motion.raw_transmission_angles == {}
    assert motion.pressure_angle is None and motion.raw_transmission_angle is None
    assert motion.transmission_angle is None and motion.transmission_angles == {}
    ok = np.flatnonzero(good)
    model = _rows_of_batch(batch, ok).motion(PHI, speed=speed)
    for key, track in model.points.items():
        for f in FIELDS:
            _close(getattr(motion.points[key], f)[ok], getattr(track, f), (key, f))
    for i in np.flatnonzero(failed):
        with pytest.raises(MechanismError):
            _rows_of(batch, i).motion(PHI)
    if speed is not None:
        assert motion.omega == speed and not motion.is_analog
    else:
        assert motion.is_analog


def _rows_of_batch(batch, rows):
    """The designs ``rows`` of a batch of ``(n, 1)`` parameter arrays, as a batch."""
    return batch(**{k: np.asarray(v)[rows] for k, v in batch.parameters.items() if np.ndim(v)})


@pytest.mark.parametrize("name", list(SIX_BARS))
def test_the_points_kernels_flags_are_the_full_kernels(name, backend_c_first):
    """The kernel of the points reduces the groups' assembly margins into its flags without
    storing them: its smallest margins are the full kernel's, its finite flags agree where
    the full kernel's are finite, and its good and failed designs are the full kernel's."""
    lk = SIX_BARS[name]()
    batch = random_designs(lk, 60, 0.3, seed=7)
    full, points = lkk.linkage_kernel(lk), lkk.linkage_kernel(lk, outputs="points")
    assert points.outputs == 6 * len(lk.points)  # the margins are not rows of its block
    params = np.column_stack(
        [np.broadcast_to(np.ravel(batch.parameters[k]), (60,)) for k in full.names]
    )
    assert points.names == full.names
    _, f_full = full(params, PHI)
    _, f_points = points(params, PHI)
    finite = np.isfinite(f_full[:, 1])
    assert finite.all()
    np.testing.assert_allclose(f_points[:, 1], f_full[:, 1], rtol=1e-13, atol=1e-15)
    for out in ("all", "points"):
        m, good, failed = lkk.linkage_batch(batch, PHI, outputs=out)
        if out == "all":
            ref = good, failed
        else:
            np.testing.assert_array_equal(good, ref[0])
            np.testing.assert_array_equal(failed, ref[1])
    assert ref[0].any() and ref[1].any()


def test_a_batch_of_the_points_takes_its_own_kernel_and_refuses_another(backend_c_first):
    """``outputs`` chooses the kernel; a kernel given must be of the outputs asked for (either
    way round), and an unknown choice is refused by name."""
    lk = watt_ii()
    full, points = lkk.linkage_kernel(lk), lkk.linkage_kernel(lk, outputs="points")
    batch = lk(OA=np.array([[0.029], [0.03], [0.031]]))
    m, good, _ = lkk.linkage_batch(batch, PHI, kernel=points, outputs="points")
    assert good.all() and set(m.points) == set(lk.points)
    with pytest.raises(MechanismError, match="outputs='points'"):
        lkk.linkage_batch(batch, PHI, kernel=points)
    with pytest.raises(MechanismError, match="outputs='all'"):
        lkk.linkage_batch(batch, PHI, kernel=full, outputs="points")
    with pytest.raises(MechanismError, match="outputs must be"):
        lkk.linkage_batch(batch, PHI, outputs="angles")
    # one design of numbers, without a workspace: a block of the call's own
    one = lkk.linkage_batch(lk, PHI, ms.rpm(100), outputs="points")[0]
    again = lkk.linkage_batch(lk, PHI, ms.rpm(100), outputs="points")[0]
    assert one.points["E"].x.shape == (1, PHI.size)  # a batch of one: (n, m) tracks
    assert not np.shares_memory(one.points["E"].x, again.points["E"].x)
    ref = lk.motion(PHI, speed=ms.rpm(100))
    for f in FIELDS:
        _close(getattr(one.points["E"], f), getattr(ref.points["E"], f), f)


@pytest.mark.parametrize("name", list(SIX_BARS))
def test_one_design_through_each_path_is_the_models(name, backend_c_first):
    """One design: ``one_motion`` (what ``Linkage.motion(kernel=True)`` calls),
    ``linkage_batch`` with and without a workspace and the model give the same motion (the
    kernel paths the same numbers bit for bit); a speed given as a numpy number is taken, one
    per angle sends the design to the model (None); angles that are a strided view or
    read-only are read as they are."""
    from test_linkage_kernels import _same_motion

    lk = SIX_BARS[name]()
    kernel = lkk.linkage_kernel(lk)
    w = ms.rpm(450)
    model = lk.motion(PHI, speed=w, epsilon=2.0)
    one = lkk.one_motion(lk, PHI, w, 2.0, kernel)
    _same_motion(model, one)
    assert one.omega == w and one.epsilon == 2.0
    for path in (
        lkk.one_motion(lk, PHI, np.float64(w), np.float64(2.0), kernel),
        lkk.linkage_batch(lk, PHI, w, None, kernel)[0],
        lkk.linkage_batch(lk, PHI, w, BatchWorkspace(), kernel)[0],
    ):
        if path.epsilon == 0.0:  # linkage_batch has no angular acceleration
            _same_motion(lk.motion(PHI, speed=w), path)
            continue
        for key, track in one.points.items():
            for f in FIELDS:
                a = getattr(path.points[key], f)
                np.testing.assert_array_equal(a.reshape(PHI.shape), getattr(track, f))
    assert lkk.one_motion(lk, PHI, np.full(PHI.size, w), 0.0, kernel) is None
    frozen = PHI.copy()
    frozen.flags.writeable = False
    for grid in (frozen, np.repeat(PHI, 2)[::2]):
        again = lkk.one_motion(lk, grid, w, 2.0, kernel)
        _same_motion(one, again, tol=1e-15)
    # a design that cannot close: None (the model judges and raises)
    assert lkk.one_motion(lk(OA=0.2), PHI, w, 0.0, kernel) is None


def test_the_motion_of_one_design_has_tracks_and_dicts_of_its_own(backend):
    """Each call makes dicts of its own (and, over a block of its own, tracks of its own;
    over a workspace's block the frozen tracks of its rows are shared): changing one
    motion's dicts leaves the next call's whole."""
    lk = six_link()
    kernel = lkk.linkage_kernel(lk)
    ws = BatchWorkspace()
    for call in (
        lambda: lkk.one_motion(lk, PHI, 1.0, 0.0, kernel),
        lambda: lkk.linkage_batch(lk, PHI, None, ws, kernel)[0],
    ):
        m1 = call()
        m1.points.pop("B")
        m1.links.clear()
        m1.extra["assembly margins"].clear()
        m1.pressure_angles.clear()
        m2 = call()
        assert "B" in m2.points and m2.links and m2.extra["assembly margins"]
        assert m2.pressure_angles
        _close(m2.pressure_angle, m2.pressure_angles["N"], "pressure")


def test_the_rows_written_once_are_found_again_without_tracing(monkeypatch, backend):
    """A kernel of the points alone writes its ground points' rows in the first column alone
    and says so in its source: a kernel loaded from the structure's record (no trace) knows
    the same rows, and its batch is the traced kernel's bit for bit."""
    lk = watt_ii()
    kernel = lkk.linkage_kernel(lk, outputs="points")
    assert kernel.once and lkk._once_rows(kernel.source) == kernel.once
    assert lkk._once_rows(lkk.linkage_kernel(lk).source) == ()
    batch = lk(OA=np.array([[0.029], [0.031]]))
    m1, _, _ = lkk.linkage_batch(batch, PHI, ms.rpm(300), outputs="points")
    monkeypatch.setattr(lkk, "_KERNELS", {})
    monkeypatch.setattr(lkk, "_trace", lambda *a: pytest.fail("traced although recorded"))
    again = lkk.linkage_kernel(lk, outputs="points")
    assert again is not kernel and again.once == kernel.once and again.kinds == "points"
    m2, _, _ = lkk.linkage_batch(batch, PHI, ms.rpm(300), kernel=again, outputs="points")
    for key, track in m1.points.items():
        for f in FIELDS:
            np.testing.assert_array_equal(getattr(m2.points[key], f), getattr(track, f))
