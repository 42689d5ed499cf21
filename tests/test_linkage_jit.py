"""``Linkage.motion``'s default (``kernel=None``): the model serves a structure's one-design
motions while their time is summed; once that time pays for the kernel (its load, or its
build: ``KERNEL_COSTS``) the kernel is asked for in the background and serves from then on."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.errors import MechanismError
from mechsynth.kinematics import linkage as L
from mechsynth.kinematics import linkage_kernels as lkk


def _fresh(tag: str):
    """A Watt II six-bar whose point names no other test uses (no kernel held for it)."""
    a, b, k, e = (f"{p}{tag}" for p in "ABKE")
    lk = (
        ms.Linkage(ground={"O": (0, 0), "D": (0.10, 0.0)})
        .crank(a, about="O", length=0.03)
        .rrr(b, (a, 0.10), ("D", 0.07))
        .attach(k, on=f"D{b}", along=0.05, left=0.02)
        .ground_point("F", 0.16, 0.06)
    )
    return lk.rrr(e, (k, 0.08), ("F", 0.06)), e


def _values(m):
    out = [v for p in m.points.values() for v in vars(p).values()]
    out += [v for t in m.links.values() for v in vars(t).values()]
    return out + list(m.pressure_angles.values()) + list(m.transmission_angles.values())


def _close(m1, m2):
    """Every output within 1e-12 of the larger of 1 and its magnitude (the kernel's promise)."""
    for a, b in zip(_values(m1), _values(m2), strict=True):
        scale = max(1.0, float(np.max(np.abs(b))))
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale)


def _bit_equal(m1, m2):
    for a, b in zip(_values(m1), _values(m2), strict=True):
        np.testing.assert_array_equal(np.broadcast_to(a, np.shape(b)), b)


@pytest.fixture
def kernels(monkeypatch, tmp_path):
    """An empty disk cache, no kernel held, the tallies reset; skipped without a backend."""
    monkeypatch.setenv("MECHSYNTH_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(lkk, "_KERNELS", {})
    monkeypatch.setattr(L, "_TALLY", {})
    if lkk.kernel_backend() is None:
        pytest.skip("no kernel backend (neither a C compiler nor numba)")
    return lkk.kernel_backend()


def test_the_model_serves_until_its_time_pays_for_the_kernel(kernels, monkeypatch):
    lk, out = _fresh("j")
    phi = ms.cycle(360)
    price = L.KERNEL_COSTS[kernels]
    first = lk.motion(phi, speed=ms.rpm(600))
    tally = L._TALLY[id(lk._groups)]
    assert not lkk.is_compiled(lk)
    assert tally[2] == price["build"] and 0.0 < tally[1] < price["build"]
    _bit_equal(first, lk.motion(phi, speed=ms.rpm(600), kernel=False))  # the model's
    assert lkk.held_kernel(lk) is None and lkk.kernel_pending(lk) is None  # nothing asked
    spent = tally[1]
    lk(OAj=0.031).motion(phi)  # another design of the structure adds to the same tally
    assert tally[1] > spent
    monkeypatch.setitem(L.KERNEL_COSTS, kernels, {"build": 0.0, "load": 0.0})
    tally[2] = None  # priced again at the next call: paid for at once
    asked = lk.motion(phi, speed=ms.rpm(600))
    _bit_equal(asked, first)  # that call is still the model's: the kernel is not waited for
    assert tally[2] == np.inf  # asked once
    pending = lkk.kernel_pending(lk)
    if pending is not None:
        pending.join(120)
    kernel = lkk.held_kernel(lk)
    assert kernel is not None
    fast = lk.motion(phi, speed=ms.rpm(600))
    assert fast.points[out].x.base is not None  # a view of the kernel's block
    _bit_equal(fast, lk.motion(phi, speed=ms.rpm(600), kernel=True))
    _close(fast, lk.motion(phi, speed=ms.rpm(600), kernel=False))
    assert lkk.is_compiled(lk)


def test_a_kernel_on_disk_costs_its_load_and_none_without_a_backend(kernels, monkeypatch):
    lk, _ = _fresh("k")
    lkk.linkage_kernel(lk)  # built: in this process and on the disk
    monkeypatch.setattr(lkk, "_KERNELS", {})  # a new process, as it were
    assert L._kernel_price(lk, lkk) == L.KERNEL_COSTS[kernels]["load"]
    monkeypatch.setattr(lkk, "kernel_backend", lambda probe=True: None)
    assert L._kernel_price(lk, lkk) == np.inf


def test_held_kernels_serve_the_default_not_false_nor_batches(kernels):
    lk, out = _fresh("h")
    phi = ms.cycle(90)
    lkk.linkage_kernel(lk)
    fast = lk.motion(phi)
    model = lk.motion(phi, kernel=False)
    assert fast.points[out].x.base is not None and model.points[out].x.base is None
    _close(fast, model)
    # a batch of designs, a number, a 2-D grid: the model, nothing tallied
    batch = lk(OAh=np.array([[0.03], [0.031]])).motion(phi)
    assert batch.points[out].x.shape == (2, 90)
    grid = lk.motion(phi.reshape(9, 10))
    np.testing.assert_array_equal(grid.points[out].x.ravel(), model.points[out].x)
    assert np.ndim(lk.motion(0.3).points[out].x) == 0
    # a speed or acceleration that varies with the angle: the model (the kernel takes numbers)
    w = 60.0 + np.cos(phi)
    for k in (None, True):
        varying = lk.motion(phi, speed=w, epsilon=-np.sin(phi), kernel=k)
        _bit_equal(varying, lk.motion(phi, speed=w, epsilon=-np.sin(phi), kernel=False))
    assert id(lk._groups) not in L._TALLY
    # a design the kernel cannot close goes to the model, which names the group
    with pytest.raises(MechanismError, match="cannot|assembl"):
        lk(AhBh=0.2).motion(phi)


def test_kernels_off_puts_every_motion_on_the_model(kernels, monkeypatch):
    lk, out = _fresh("o")
    phi = ms.cycle(90)
    lkk.linkage_kernel(lk)  # held, yet not taken
    monkeypatch.setenv(lkk.BACKEND_ENV, "off")
    assert lkk.kernel_backend() is None and lkk.linkage_kernel(lk) is None
    for k in (None, True):
        assert lk.motion(phi, kernel=k).points[out].x.base is None  # the model's own arrays
    monkeypatch.setenv(lkk.BACKEND_ENV, "fast")
    with pytest.raises(MechanismError, match="'c', 'numba', 'auto' or 'off'"):
        lkk.kernel_backend()
