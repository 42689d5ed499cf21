"""One Linkage design's motion with less Python around the model's numpy work: the crank's
cosines and sines from the remembered grid when its phase is the number 0, the groups' roles
looked up once, the memory guard's count made once per linkage -- the same motion as before."""

import numpy as np

import mechsynth as ms


def _watt_ii():
    lk = (
        ms.Linkage(ground={"O": (0, 0), "D": (0.10, 0.0)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.10), ("D", 0.07))
        .attach("K", on="DB", along=0.05, left=0.02)
        .ground_point("F", 0.16, 0.06)
    )
    return lk.rrr("E", ("K", 0.08), ("F", 0.06))


def _tracks(m):
    out = [v for p in m.points.values() for v in vars(p).values()]
    out += [v for t in m.links.values() for v in vars(t).values()]
    return out + list(m.pressure_angles.values()) + list(m.transmission_angles.values())


def test_a_zero_phase_takes_the_remembered_grid_and_gives_the_same_motion():
    lk = _watt_ii()
    phi = ms.cycle(360)
    fast = lk.motion(phi, speed=ms.rpm(600), kernel=False)  # the model's own path
    general = lk(phase=np.float64(0.0)).motion(phi, speed=ms.rpm(600), kernel=False)  # not 0
    for a, b in zip(_tracks(fast), _tracks(general), strict=True):
        np.testing.assert_array_equal(np.broadcast_to(a, np.shape(b)), b)
    # a phase turns the crank: the motion at phi with phase 0.3 is the one at phi + 0.3
    turned = lk(phase=0.3).motion(phi)
    shifted = lk.motion(phi + 0.3)
    for a, b in zip(_tracks(turned), _tracks(shifted), strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)
    assert np.allclose(fast.links["OA"].angle, phi)
    assert np.all(fast.links["OA"].omega == ms.rpm(600))


def test_roles_and_memory_count_follow_the_structure():
    lk = _watt_ii()
    g = lk.groups[1]
    assert g.p(lk.parameters, "l1") == 0.10 and g.has("l2") and not g.has("length")
    assert lk._motion_arrays == 12 * (len(lk.points) + len(lk.links)) + 8
    longer = lk.attach("P", on=("K", "E"), along=0.01)
    assert longer._motion_arrays == lk._motion_arrays + 12
    assert lk.rename(KE="link")._motion_arrays == lk._motion_arrays


def test_a_designs_batch_call_runs_little_python_around_the_kernel():
    """linkage_batch for one design: the motion made of views of the block from row indices
    read once per structure, the last block's views remembered -- a few Python frames per
    call, whatever the linkage's size (was one per point, link and group, and per parameter)."""
    import sys

    import pytest

    pytest.importorskip("numba")
    from mechsynth.kinematics import linkage_kernels as lkk
    from mechsynth.kinematics.compiled import BatchWorkspace

    lk, phi, ws, speed = _watt_ii(), ms.cycle(360), BatchWorkspace(), ms.rpm(600)
    kernel = lkk.linkage_kernel(lk)
    frames = []

    def count(frame, event, arg):
        if event == "call":
            frames.append(frame.f_code.co_name)

    for _ in range(2):  # the recipe and the block's views made on the first call
        motion, good, failed = lkk.linkage_batch(lk, phi, speed, ws, kernel)
    sys.setprofile(count)
    try:
        again, good, failed = lkk.linkage_batch(lk, phi, speed, ws, kernel)
    finally:
        sys.setprofile(None)
    assert len(frames) <= 25, frames  # 22 when written (86 before)
    assert good.all() and not failed.any()
    model = lk.motion(phi, speed=ms.rpm(600))
    for a, b in zip(_tracks(model), _tracks(again), strict=True):  # one design: (1, 360)
        np.testing.assert_allclose(np.reshape(b, -1), np.broadcast_to(a, (360,)), 1e-12, 1e-12)
