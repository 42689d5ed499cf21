"""Sweeps on the compiled kernels agree with the numpy model (the reference), measure for
measure; measures that need more than the kernels give fall back to the model."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.kinematics import compiled
from mechsynth.kinematics.compiled import BatchWorkspace, batch_motion
from mechsynth.synthesis import sweep

needs_numba = pytest.mark.skipif(not compiled.numba_available(), reason="numba not installed")
PHI = np.linspace(0.0, 2 * np.pi, 97, endpoint=False)


def _same(a, b):
    np.testing.assert_array_equal(a.feasible, b.feasible)
    for k in a.values:
        x, y = a.values[k].filled(np.nan), b.values[k].filled(np.nan)
        np.testing.assert_allclose(x, y, rtol=1e-11, atol=1e-12, equal_nan=True, err_msg=k)


@needs_numba
def test_slider_crank_sweep_equals_the_model():
    grid = {"crank": np.linspace(0.02, 0.09, 9), "offset": np.linspace(-0.04, 0.05, 7)}
    measures = {
        "acc": ob.peak_acceleration("slider"),
        "vel": ob.peak_velocity("slider"),
        "pressure": ob.max_pressure_angle(),
        "rod omega": ob.peak_angular_velocity("rod"),
        "tr": ob.time_ratio(),
    }
    kw = dict(fixed={"rod": 0.12}, measures=measures, angles=120, speed=ms.rpm(300),
              progress=False, chunk=10)  # fmt: skip
    fast = sweep(ms.SliderCrank, grid, kernels=True, **kw)
    ref = sweep(ms.SliderCrank, grid, kernels=False, **kw)
    assert 0 < fast.feasible.sum() < fast.size  # some designs cannot turn: masked alike
    _same(fast, ref)


@needs_numba
def test_four_bar_sweep_equals_the_model_and_falls_back_for_points():
    grid = {"crank": np.linspace(0.8, 1.6, 6), "rocker": np.linspace(2.0, 3.5, 5)}
    measures = {
        "mu": ob.min_transmission_angle(),
        "pressure": ob.max_pressure_angle(),
        "rocker eps": ob.peak_angular_acceleration("rocker"),
    }
    kw = dict(fixed={"coupler": 4.3, "ground": 5.2}, angles=90, progress=False)
    fast = sweep(ms.FourBar, grid, measures, kernels=True, **kw)
    ref = sweep(ms.FourBar, grid, measures, kernels=False, **kw)
    _same(fast, ref)
    # B's velocity is a point track: not in the compiled motion, evaluated on the model
    point = {"B speed": ob.peak_velocity("B")}
    _same(
        sweep(ms.FourBar, grid, point, kernels=True, **kw),
        sweep(ms.FourBar, grid, point, kernels=False, **kw),
    )


@needs_numba
def test_batch_motion_is_the_models_motion():
    sc = ms.SliderCrank(np.array([0.05, 0.07])[:, None], 0.24, np.array([0.0, -0.03])[:, None])
    m = sc.motion(PHI, speed=12.0)
    fast = batch_motion(sc, PHI, speed=12.0, workspace=BatchWorkspace())
    np.testing.assert_allclose(fast.slider.acceleration, m.slider.acceleration, atol=1e-12)
    np.testing.assert_allclose(fast.pressure_angle, m.pressure_angle, atol=1e-12)
    np.testing.assert_allclose(fast.transmission_angle, m.transmission_angle, atol=1e-12)
    np.testing.assert_allclose(fast.links["rod"].omega, m.links["rod"].omega, atol=1e-10)
    fb = ms.FourBar(np.array([1.0, 1.2])[:, None], 4.3, 3.0, 5.2, branch="crossed")
    m, fast = fb.motion(PHI), batch_motion(fb, PHI)
    np.testing.assert_allclose(fast.transmission_angle, m.transmission_angle, atol=1e-12)
    np.testing.assert_allclose(fast.pressure_angle, m.pressure_angle, atol=1e-12)
    np.testing.assert_allclose(fast.links["rocker"].epsilon, m.links["rocker"].epsilon, atol=1e-10)
    assert batch_motion(ms.DwellSliderCrank.__new__(ms.DwellSliderCrank), PHI) is None


def test_workspace_reuses_its_block():
    ws = BatchWorkspace()
    a = ws.block(10, 36)
    b = ws.block(4, 36)
    assert np.shares_memory(a, b) and b.shape == (8, 4, 36) and b.flags.c_contiguous


@needs_numba
def test_batch_motion_computes_its_angles_only_when_they_are_read():
    """The pressure and transmission angles are passes over the whole block: computed the
    first time each is read (the kernel's outputs untouched), equal to the model's."""
    import pickle

    from mechsynth.kinematics.tracks import Motion

    sc = ms.SliderCrank(np.array([0.05, 0.07])[:, None], 0.24, np.array([0.0, -0.03])[:, None])
    m, ws = sc.motion(PHI, speed=12.0), BatchWorkspace()
    block = ws.block(2, PHI.size)
    block[6:] = np.nan
    fast = batch_motion(sc, PHI, speed=12.0, workspace=ws)
    np.testing.assert_allclose(fast.slider.acceleration, m.slider.acceleration, atol=1e-12)
    assert np.isnan(block[6:]).all()  # not read: not computed
    np.testing.assert_allclose(fast.pressure_angle, m.pressure_angle, atol=1e-12)
    assert np.shares_memory(fast.pressure_angle, block[6]) and np.isnan(block[7]).all()
    np.testing.assert_allclose(fast.transmission_angle, m.transmission_angle, atol=1e-12)
    assert not np.isnan(block[7]).any()
    # a four-bar's pressure angle is read from its transmission angle: both computed
    fb = ms.FourBar(np.array([1.0, 1.2])[:, None], 4.3, 3.0, 5.2, branch="crossed")
    block[6:] = np.nan
    fast, m = batch_motion(fb, PHI, workspace=ws), fb.motion(PHI)
    assert np.isnan(block[6:]).all()
    np.testing.assert_allclose(fast.pressure_angle, m.pressure_angle, atol=1e-12)
    np.testing.assert_allclose(fast.transmission_angle, m.transmission_angle, atol=1e-12)
    # sent elsewhere, it is a plain Motion with the same arrays
    again = pickle.loads(pickle.dumps(fast))
    assert type(again) is Motion
    np.testing.assert_array_equal(again.raw_transmission_angle, fast.raw_transmission_angle)


@needs_numba
def test_a_chart_that_needs_no_angles_skips_them_and_gives_the_same_numbers(monkeypatch):
    grid = {"crank": np.linspace(0.02, 0.09, 9), "offset": np.linspace(-0.04, 0.05, 7)}
    kw = dict(fixed={"rod": 0.12}, angles=120, speed=ms.rpm(300), progress=False, chunk=10)
    peaks = {"acc": ob.peak_acceleration("slider"), "rod eps": ob.peak_angular_acceleration("rod")}
    angles = {"pressure": ob.max_pressure_angle(), "mu": ob.min_transmission_angle()}
    read = []
    p, t = compiled._ANGLES[ms.SliderCrank]
    monkeypatch.setitem(compiled._ANGLES, ms.SliderCrank, (
        lambda *a: read.append("pressure") or p(*a), lambda *a: read.append("mu") or t(*a)
    ))  # fmt: skip
    lean = sweep(ms.SliderCrank, grid, peaks, **kw)
    assert read == []  # no measure read an angle: none computed
    full = sweep(ms.SliderCrank, grid, {**peaks, **angles}, **kw)
    assert read and set(read) == {"pressure", "mu"}
    np.testing.assert_array_equal(lean.feasible, full.feasible)
    for k in peaks:  # the same numbers, bit for bit
        np.testing.assert_array_equal(lean.values[k].filled(np.nan), full.values[k].filled(np.nan))
    _same(full, sweep(ms.SliderCrank, grid, {**peaks, **angles}, kernels=False, **kw))


@needs_numba
def test_batch_motion_scales_only_the_rates_that_are_read():
    """The kernels give the analogs; a rate is multiplied by the crank speed (or its square)
    where it lies in the block the first time it is read, to the bit what the batch function
    gives at that speed, and the rates never read are left as analogs."""
    crank, rod, off = np.array([0.05, 0.07, 0.06]), 0.24, np.array([0.0, -0.03, 0.02])
    sc, w = ms.SliderCrank(crank[:, None], rod, off[:, None]), 12.5
    ref = compiled.slider_crank_batch(crank, rod, off, PHI, speed=w)
    analog = compiled.slider_crank_batch(crank, rod, off, PHI)
    ws = BatchWorkspace()
    fast = batch_motion(sc, PHI, speed=w, workspace=ws)
    block = ws.block(3, PHI.size)
    np.testing.assert_array_equal(block[:6], np.stack([getattr(analog, f) for f in (
        "position", "velocity", "acceleration", "rod_angle", "rod_omega", "rod_epsilon")]))
    np.testing.assert_array_equal(fast.slider.acceleration, ref.acceleration)
    np.testing.assert_array_equal(fast.slider.acceleration, ref.acceleration)  # once only
    np.testing.assert_array_equal(block[1], analog.velocity)  # not read: an analog still
    np.testing.assert_array_equal(fast.links["rod"].omega, ref.rod_omega)
    np.testing.assert_array_equal(fast.links["rod"].epsilon, ref.rod_epsilon)
    np.testing.assert_array_equal(fast.slider.velocity, ref.velocity)
    assert fast.omega == w and fast.slider.velocity is fast.sliders["B"].velocity
    fb = ms.FourBar(np.array([1.0, 1.2])[:, None], 4.3, 3.0, 5.2)
    m = fb.motion(PHI, speed=w)
    fast = batch_motion(fb, PHI, speed=w)
    scale = np.abs(m.links["rocker"].epsilon).max()
    assert np.abs(fast.links["rocker"].epsilon - m.links["rocker"].epsilon).max() < 1e-12 * scale
