"""Batch kinematics: the compiled (numba) kernels agree with the numpy model to 1e-12 on random
designs; validation, fallbacks and the output buffer."""

import numpy as np
import pytest

from mechsynth.errors import MechanismError
from mechsynth.kinematics import FourBar, SliderCrank, compiled
from mechsynth.kinematics.compiled import four_bar_batch, slider_crank_batch

PHI = np.linspace(0.0, 2.0 * np.pi, 97)
FB_FIELDS = [
    "rocker_angle",
    "rocker_omega",
    "rocker_epsilon",
    "coupler_angle",
    "coupler_omega",
    "coupler_epsilon",
]
SC_FIELDS = ["position", "velocity", "acceleration", "rod_angle", "rod_omega", "rod_epsilon"]

needs_numba = pytest.mark.skipif(not compiled.numba_available(), reason="numba not installed")


def _full_turn_designs(n, seed):
    """Random crank-rockers and double-cranks with a 2 % margin on both full-turn conditions."""
    rng = np.random.default_rng(seed)
    b, c, long_side = rng.uniform(0.3, 3.0, (3, 4 * n))
    upper = np.minimum(b + c - long_side, long_side - np.abs(b - c))
    ok = upper > 0.05
    b, c, long_side, upper = b[ok][:n], c[ok][:n], long_side[ok][:n], upper[ok][:n]
    short = rng.uniform(0.05, 0.9, b.size) * upper
    swap = rng.random(b.size) < 0.3  # some double-cranks (ground shortest)
    a = np.where(swap, long_side, short)
    d = np.where(swap, short, long_side)
    return a, b, c, d


def _slider_designs(n, seed):
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.05, 1.0, n)
    e = rng.uniform(-1.0, 1.0, n) * a
    b = (a + np.abs(e)) * rng.uniform(1.05, 4.0, n)
    return a, b, e


def _assert_same(x, y, fields, angles):
    for f in fields:
        u, v = getattr(x, f), getattr(y, f)
        assert u.shape == v.shape
        assert np.all(np.isfinite(u)), f
        diff = np.angle(np.exp(1j * (u - v))) if f in angles else u - v
        scale = np.max(np.abs(v), axis=1, keepdims=True)
        assert np.max(np.abs(diff) / np.maximum(scale, 1.0)) < 1e-12, f


@needs_numba
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_four_bar_kernel_matches_numpy_model(branch):
    a, b, c, d = _full_turn_designs(300, 7)
    fast = four_bar_batch(a, b, c, d, PHI, branch=branch, backend="numba")
    ref = four_bar_batch(a, b, c, d, PHI, branch=branch, backend="numpy")
    assert fast.backend == "numba" and ref.backend == "numpy"
    _assert_same(fast, ref, FB_FIELDS, {"rocker_angle", "coupler_angle"})
    # and the numpy backend is the model itself
    _, _, cpl, rck = FourBar(a[:, None], b[:, None], c[:, None], d[:, None], branch=branch).jets(
        PHI
    )
    np.testing.assert_array_equal(ref.rocker_epsilon, rck.d2)
    np.testing.assert_array_equal(ref.coupler_angle, cpl.value)


@needs_numba
def test_slider_crank_kernel_matches_numpy_model():
    a, b, e = _slider_designs(300, 8)
    fast = slider_crank_batch(a, b, e, PHI, backend="numba")
    ref = slider_crank_batch(a, b, e, PHI, backend="numpy")
    _assert_same(fast, ref, SC_FIELDS, {"rod_angle"})
    m = SliderCrank(a[:, None], b[:, None], e[:, None]).motion(PHI)
    np.testing.assert_array_equal(ref.acceleration, m.slider.acceleration)


@needs_numba
def test_kernel_atan2_agrees_with_numpy():
    atan2 = compiled._kernels()["atan2"]
    rng = np.random.default_rng(3)
    y = rng.normal(size=2000) * 10.0 ** rng.integers(-8, 8, 2000)
    x = rng.normal(size=2000) * 10.0 ** rng.integers(-8, 8, 2000)
    y[:6], x[:6] = [0.0, 1.0, 0.0, -1.0, 1.0, -1.0], [1.0, 0.0, -1.0, 0.0, 1.0, -1.0]
    got = np.array([atan2(yy, xx) for yy, xx in zip(y, x)])
    ref = np.arctan2(y, x)
    assert np.max(np.abs(got - ref) / np.spacing(np.maximum(np.abs(ref), 1e-300))) <= 4


@needs_numba
def test_speed_scales_like_motion():
    a, b, c, d = 1.0, 4.3, 3.0, 5.2
    w = 12.0
    res = four_bar_batch(a, b, c, d, PHI, speed=w)
    m = FourBar(a, b, c, d).motion(PHI, speed=w)
    np.testing.assert_allclose(res.rocker_omega[0], m.links["rocker"].omega, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(
        res.coupler_epsilon[0], m.links["coupler"].epsilon, rtol=1e-12, atol=1e-10
    )
    sc = slider_crank_batch(0.07, 0.24, 0.01, PHI, speed=w)
    ms = SliderCrank(0.07, 0.24, 0.01).motion(PHI, speed=w)
    np.testing.assert_allclose(sc.acceleration[0], ms.slider.acceleration, rtol=1e-12, atol=1e-10)


@needs_numba
def test_designs_near_toggle_or_not_assemblable_go_to_the_numpy_model():
    # a double-rocker evaluated where it closes, one that does not close everywhere, one fine
    phi = np.linspace(-0.5, 0.5, 11)
    ok = four_bar_batch([1.0, 1.0], [2.0, 4.3], [1.5, 3.0], [2.2, 5.2], phi, full_turn=False)
    ref = four_bar_batch(
        [1.0, 1.0], [2.0, 4.3], [1.5, 3.0], [2.2, 5.2], phi, full_turn=False, backend="numpy"
    )
    _assert_same(ok, ref, FB_FIELDS, {"rocker_angle", "coupler_angle"})
    with pytest.raises(MechanismError, match=r"RRR dyad: .* at crank angle"):
        four_bar_batch([1.0, 1.0], [4.3, 1.0], [3.0, 1.5], [5.2, 2.2], PHI, full_turn=False)
    with pytest.raises(MechanismError, match=r"RRR dyad: links in line .* at crank angle 0 deg"):
        four_bar_batch(1.0, 2.0, 1.0, 2.0, np.array([0.0, 0.1]), full_turn=False)


def test_validation_is_the_mechanisms():
    with pytest.raises(ValueError, match=r"^crank must be positive .* got -1.0 \(design index"):
        four_bar_batch([1.0, -1.0], 4.3, 3.0, 5.2, PHI)
    with pytest.raises(MechanismError, match=r"crank \+ ground \(7 m\) not less than"):
        four_bar_batch(2.0, 4.3, 2.0, 5.0, PHI)
    with pytest.raises(MechanismError, match=r"rod \(0.1 m\) not longer than"):
        slider_crank_batch(0.07, 0.1, 0.04, PHI)
    with pytest.raises(ValueError, match="backend must be one of"):
        four_bar_batch(1.0, 4.3, 3.0, 5.2, PHI, backend="cuda")
    with pytest.raises(ValueError, match="phi must be a 1-D array"):
        four_bar_batch(1.0, 4.3, 3.0, 5.2, PHI[:, None])
    with pytest.raises(ValueError, match="coupler must be a scalar or a 1-D array"):
        four_bar_batch(1.0, np.ones((2, 2)) * 4.3, 3.0, 5.2, PHI)
    with pytest.raises(ValueError, match="speed must be finite"):
        slider_crank_batch(0.07, 0.24, 0.0, PHI, speed=np.nan)


@pytest.mark.parametrize("backend", ["numpy", pytest.param("numba", marks=needs_numba)])
def test_output_buffer_is_reused(backend):
    a, b, c, d = _full_turn_designs(5, 1)
    buf = np.empty((6, 5, PHI.size))
    res = four_bar_batch(a, b, c, d, PHI, backend=backend, out=buf)
    assert np.shares_memory(res.rocker_angle, buf)
    np.testing.assert_array_equal(buf[2], res.rocker_epsilon)
    with pytest.raises(ValueError, match=r"out must be .* shape \(6, 5, 97\)"):
        four_bar_batch(a, b, c, d, PHI, backend=backend, out=np.empty((6, 4, PHI.size)))


def test_numpy_fallback_without_numba(monkeypatch):
    monkeypatch.setattr(compiled, "numba_available", lambda: False)
    res = slider_crank_batch(0.07, 0.24, 0.0, PHI)
    assert res.backend == "numpy"
    ref = SliderCrank(0.07, 0.24).motion(PHI).slider
    np.testing.assert_array_equal(res.velocity[0], ref.velocity)
    with pytest.raises(ModuleNotFoundError, match="needs numba"):
        slider_crank_batch(0.07, 0.24, 0.0, PHI, backend="numba")


def test_numpy_backend_chunks_large_batches(monkeypatch):
    monkeypatch.setattr(compiled, "_NUMPY_CHUNK", 3 * PHI.size)  # chunks of 3 designs
    a, b, c, d = _full_turn_designs(10, 2)
    res = four_bar_batch(a, b, c, d, PHI, backend="numpy")
    _, _, _, rck = FourBar(a[:, None], b[:, None], c[:, None], d[:, None]).jets(PHI)
    np.testing.assert_array_equal(res.rocker_omega, rck.d1)


@needs_numba
def test_kernels_run_the_models_own_code():
    """The compiled chains are the model's functions (same code objects), not a second copy."""
    from mechsynth.kinematics import blocks, scalar_ops
    from mechsynth.kinematics.four_bar import four_bar_chain
    from mechsynth.kinematics.slider_crank import slider_crank_chain

    compiled._kernels()
    assert compiled._FB_CHAIN.py_func.__code__ is four_bar_chain.__code__
    assert compiled._SC_CHAIN.py_func.__code__ is slider_crank_chain.__code__
    rrr = compiled._FB_CHAIN.py_func.__globals__["dyad_rrr"]
    assert rrr.py_func.__code__ is blocks.dyad_rrr.__wrapped__.__code__
    assert rrr.py_func.__globals__["ops"] is scalar_ops
    # every elementary function the blocks use exists in the scalar stand-in
    from mechsynth.kinematics import ops

    for name in ops.__all__:
        if name != "is_symbolic":
            assert hasattr(scalar_ops, name), name


def test_cache_stamp_follows_the_code():
    def f(x):
        return x + 1.0

    def g(x):
        return x + 2.0

    def f_again(x):
        return x + 1.0

    assert compiled._stamp([f]) != compiled._stamp([g])
    assert compiled._stamp([f, g]) != compiled._stamp([g, f])
    assert 0 <= compiled._stamp([f]) < 2**60
    # same code in another function object: the stamp is of the code, not of the object
    f_again.__code__ = f.__code__
    assert compiled._stamp([f]) == compiled._stamp([f_again])


@needs_numba
def test_serial_and_threaded_kernels_agree(monkeypatch):
    a, b, c, d = _full_turn_designs(50, 7)
    serial = four_bar_batch(a, b, c, d, PHI)  # small: one thread
    monkeypatch.setattr(compiled, "PARALLEL_MIN", 0)
    threaded = four_bar_batch(a, b, c, d, PHI)
    np.testing.assert_array_equal(serial.rocker_epsilon, threaded.rocker_epsilon)
    np.testing.assert_array_equal(serial.coupler_angle, threaded.coupler_angle)
    s1 = slider_crank_batch(0.07, 0.24 + 0.01 * a, 0.01, PHI)
    s2 = slider_crank_batch(0.07, 0.24 + 0.01 * a, 0.01, PHI)
    np.testing.assert_array_equal(s1.acceleration, s2.acceleration)


@needs_numba
def test_grid_cache_follows_edited_angles():
    phi = PHI.copy()
    first = slider_crank_batch(0.07, 0.24, 0.0, phi).position.copy()
    phi += 0.3  # edited in place: the remembered cos/sin must not be reused
    again = slider_crank_batch(0.07, 0.24, 0.0, phi).position
    ref = SliderCrank(0.07, 0.24, 0.0).motion(phi).slider.position
    np.testing.assert_allclose(again[0], ref, rtol=0, atol=1e-13)
    assert not np.allclose(first, again)


def test_batch_validation_names_the_condition_per_design():
    with pytest.raises(MechanismError, match=r"design index \(1,\)"):
        slider_crank_batch([0.07, 0.3], 0.24, 0.0, PHI)
    with pytest.raises(ValueError, match="coupler must be positive"):
        four_bar_batch(1.0, [4.3, -1.0], 3.0, 5.2, PHI)
    with pytest.raises(ValueError, match="offset must be finite"):
        slider_crank_batch(0.07, 0.24, [0.0, np.nan], PHI)
    with pytest.raises(ValueError, match="do not broadcast"):
        four_bar_batch([1.0, 1.1], [4.3, 4.4, 4.5], 3.0, 5.2, PHI)


def test_compilation_is_announced_once_in_one_line(capsys):
    import time

    with compiled.announce_compilation("a test kernel", after=0.05):
        time.sleep(0.3)
    with compiled.announce_compilation("a test kernel", after=0.05):
        time.sleep(0.3)
    with compiled.announce_compilation("a quick kernel", after=5.0):
        pass
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "compiling a test kernel" in err
