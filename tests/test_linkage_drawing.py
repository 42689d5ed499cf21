"""Drawing and animating a general Linkage from its topology (the sketch every renderer uses)."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

import mechsynth as ms  # noqa: E402
from mechsynth.kinematics import Circle  # noqa: E402
from mechsynth.machines.nail_header import NailHeader  # noqa: E402
from mechsynth.plotting import layout_problems  # noqa: E402


def nail_header_linkage(nh: NailHeader):
    return (
        ms.Linkage(ground={"O": (0, 0), "E": (nh.x_e, nh.y_e)}, name="nail header")
        .crank("A", about="O", length=nh.l_oa, link="crank")
        .rrp("B", ("A", nh.l_ab), guide=((0.0, 0.0), 0.0), link="rod", slider="slider")
        .attach("C", on="slider", along=nh.x_bc, left=nh.y_c)
        .rpr("ejector", about="E", through="C", offset=nh.l_de, block="block")
        .with_output("B")
    )


def six_link():
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)}, name="six-link")
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05)
        .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57)))
    )


def test_six_link_sketch_follows_its_motion():
    lk = six_link()
    phi = ms.cycle(12)
    sk = lk.sketch(phi)
    m = lk.motion(phi)
    assert sk.frames == 12 and set(sk.ground) == {"O", "D"}
    for name in ("A", "B", "K", "N"):
        np.testing.assert_allclose(sk.points[name][0], m.points[name].x, atol=0)
    bars = {b.name: b.points for b in sk.bars}
    assert bars["OA"] == ("O", "A") and bars["KN"] == ("K", "N")
    assert set(bars["DB"]) == {"D", "B", "K"}  # the rocker carries K: a plate
    (slider,) = sk.sliders
    assert slider.point == "N" and slider.through is None
    np.testing.assert_allclose(slider.angle, ms.deg(57), atol=1e-12)


def test_a_slot_on_a_moving_link_lies_on_its_guide_line():
    nh = NailHeader()
    lk = nail_header_linkage(nh)
    phi = ms.cycle(24)
    sk = lk.sketch(phi)
    slot = next(s for s in sk.sliders if s.through is not None)
    assert slot.point == "C"
    fx, fy = sk.points[slot.through]
    cx, cy = sk.points["C"]
    ex, ey = sk.points["E"]
    u = np.stack([np.cos(slot.angle), np.sin(slot.angle)])
    # C lies on the slot line through the foot, and the foot is the offset away from E
    np.testing.assert_allclose((cx - fx) * u[1] - (cy - fy) * u[0], 0.0, atol=1e-12)
    np.testing.assert_allclose(np.hypot(fx - ex, fy - ey), abs(nh.l_de), rtol=1e-12)
    assert {"E", slot.through} <= set(next(b for b in sk.bars if b.name == "ejector").points)


def test_draw_and_animate_any_linkage(tmp_path):
    cam = (
        ms.Linkage(ground={"O": (0, 0)}, name="cam")
        .crank("A", about="O", length=0.01)
        .follower("F", on="OA", profile=Circle(0.05, center=(0.01, 0.0)),
                  guide=((0.0, 0.0), np.pi / 2), face=0.0)
    )  # fmt: skip
    for lk in (six_link(), nail_header_linkage(NailHeader()), cam):
        ax = lk.draw(ms.deg(40))
        assert layout_problems(ax.figure) == []
        matplotlib.pyplot.close(ax.figure)
        path = lk.animate(frames=5, dpi=30).save(tmp_path / f"{lk.name}.gif")
        with Image.open(path) as im:
            assert im.n_frames == 5
    profile = cam.sketch(ms.cycle(3)).outlines[0]
    # the cam circle drawn around its centre, which turns with the crank
    x, y = np.asarray(profile.x), np.asarray(profile.y)
    cx, cy = 0.01 * np.cos(ms.cycle(3)), 0.01 * np.sin(ms.cycle(3))
    np.testing.assert_allclose(np.hypot(x - cx[:, None], y - cy[:, None]), 0.05, atol=1e-12)


def test_values_rebuild_the_linkage_and_options_are_checked():
    lk = six_link()
    again = lk(**lk.as_dict())
    assert again.parameters == pytest.approx(lk.parameters)
    with pytest.raises(ValueError, match="unknown drawing option"):
        lk.sketch(ms.cycle(4), colour="red")
