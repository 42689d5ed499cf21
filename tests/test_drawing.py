"""Drawing and animation of every mechanism from its sketch (one generic renderer)."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.animation import FuncAnimation  # noqa: E402
from PIL import Image  # noqa: E402

import mechsynth as ms  # noqa: E402
from mechsynth.kinematics.sketch import Bar, Sketch  # noqa: E402
from mechsynth.machines.dwell import DwellSliderCrank  # noqa: E402
from mechsynth.machines.nail_header import NailHeader  # noqa: E402
from mechsynth.plotting import layout_problems  # noqa: E402

C320 = dict(A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98, units="in")

MECHANISMS = {
    "slider-crank": ms.SliderCrank(crank=0.07, rod=0.24, offset=0.01),
    "four-bar": ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2),
    "dwell": DwellSliderCrank(r=0.3, k=1.2, gamma=np.deg2rad(20), xi=0.1),
    "nail-header": NailHeader(),
    "pumping-unit": ms.BeamPumpingUnit.from_api(**C320),
}


def _length(line, i, j):
    x, y = line.get_data()
    return float(np.hypot(x[j] - x[i], y[j] - y[i]))


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_every_mechanism_draws_without_layout_defects(name):
    mech = MECHANISMS[name]
    ax = mech.draw(0.7)
    assert ax.get_xlabel().endswith(", m") and ax.get_ylabel() == "y, m"
    assert "= " in ax.get_title()  # the crank angle is stated
    assert layout_problems(ax.figure) == []


def test_slider_crank_links_at_their_lengths_and_slider_on_its_guide():
    sc = MECHANISMS["slider-crank"]
    phi = 0.9
    ax = sc.draw(phi, trace=("B",))
    crank, rod = ax.lines[:2]
    assert _length(crank, 0, 1) == pytest.approx(sc.crank, rel=1e-12)
    assert _length(rod, 0, 1) == pytest.approx(sc.rod, rel=1e-12)
    m = sc.motion(np.array([phi]))
    assert rod.get_data()[0][1] == pytest.approx(float(m.points["B"].x[0]))
    assert rod.get_data()[1][1] == pytest.approx(sc.offset)
    path = next(line for line in ax.lines if line.get_label() == "path of B")
    x, y = path.get_data()
    assert np.allclose(y, sc.offset) and x.max() == pytest.approx(
        float(sc.dead_centre_positions[0]), rel=1e-4
    )


def test_four_bar_coupler_point_plate_and_rocker():
    fb = MECHANISMS["four-bar"]
    ax = fb.draw(1.2, coupler_points={"P": (2.0, 1.0)}, trace=("P",))
    crank, coupler, rocker = ax.lines[:3]
    assert _length(crank, 0, 1) == pytest.approx(fb.crank)
    assert _length(coupler, 0, 1) == pytest.approx(fb.coupler)
    assert _length(coupler, 0, 2) == pytest.approx(np.hypot(2.0, 1.0))
    assert _length(rocker, 0, 1) == pytest.approx(fb.rocker)
    assert rocker.get_data()[0][0] == pytest.approx(fb.ground)


def test_nail_header_drawn_in_the_machine_s_clockwise_angle():
    nh = MECHANISMS["nail-header"]
    ax = nh.draw(-np.deg2rad(30))
    assert "clockwise" in ax.get_title() and "30.0°" in ax.get_title()
    crank, rod, slider = ax.lines[:3]
    assert _length(crank, 0, 1) == pytest.approx(nh.l_oa)
    assert _length(rod, 0, 1) == pytest.approx(nh.l_ab)
    assert _length(slider, 0, 1) == pytest.approx(np.hypot(nh.x_bc, nh.y_c))


def test_display_units_scale_the_drawing():
    sc = MECHANISMS["slider-crank"]
    with ms.display_units("mm-deg"):
        ax = sc.draw(0.3)
    assert ax.get_xlabel() == "x, mm"
    assert _length(ax.lines[0], 0, 1) == pytest.approx(1e3 * sc.crank)


def test_drawing_a_batch_or_an_unknown_trace_fails_clearly():
    with pytest.raises(ValueError, match="one design at a time"):
        ms.SliderCrank(crank=np.array([[0.05], [0.06]]), rod=0.3).draw(0.0)
    with pytest.raises(ValueError, match="cannot trace 'Z'"):
        MECHANISMS["slider-crank"].draw(0.0, trace=("Z",))
    with pytest.raises(ValueError, match="one crank angle"):
        MECHANISMS["slider-crank"].draw([0.0, 1.0])


def test_sketch_checks_its_names():
    with pytest.raises(ValueError, match="unknown points"):
        Sketch(points={"O": ([0.0], [0.0])}, bars=(Bar("crank", ("O", "A")),))


def test_double_rocker_draws_at_the_asked_angle_only():
    fb = ms.FourBar(crank=2.5, coupler=2.0, rocker=2.2, ground=4.0, full_turn=False)
    ax = fb.draw(0.3)
    assert _length(ax.lines[0], 0, 1) == pytest.approx(2.5)


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_animation_saves_a_gif_with_every_frame(name, tmp_path):
    anim = MECHANISMS[name].animate(frames=6, dpi=40)
    assert isinstance(anim, FuncAnimation)
    path = anim.save(tmp_path / "m.gif")
    with Image.open(path) as im:
        assert im.n_frames == 6


def test_animation_html_snippet_and_mp4_without_ffmpeg(tmp_path):
    from matplotlib import animation as manim

    anim = MECHANISMS["slider-crank"].animate(frames=4, dpi=30)
    html = anim.to_html()
    assert "<script" in html and anim._repr_html_() == html
    if not manim.writers.is_available("ffmpeg"):
        with pytest.raises(ValueError, match="ffmpeg"):
            anim.save(tmp_path / "m.mp4")
    with pytest.raises(ValueError, match=r"\.gif, \.mp4 or \.html"):
        anim.save(tmp_path / "m.avi")


def test_animation_playback_follows_the_machine_speed():
    unit = MECHANISMS["pumping-unit"]
    slow = unit.animate(frames=48, speed=ms.spm(6), dpi=30)  # 10 s per stroke
    assert slow.playback == "real time" and slow.playback_fps == pytest.approx(4.8)
    fast = MECHANISMS["slider-crank"].animate(frames=36, speed=ms.rpm(600), dpi=30)
    assert fast.playback == "slowed x 30"  # 0.1 s per turn shown in 3 s
    plain = MECHANISMS["slider-crank"].animate(frames=36, dpi=30)
    assert plain.playback == "3 s per turn"


def test_animation_turns_the_nail_header_clockwise():
    nh = MECHANISMS["nail-header"]
    assert np.all(np.diff(nh.turn(8)) < 0)


@pytest.mark.parametrize("angles", [[0.0, 0.5, 1.0], (0.0, 0.5, 1.0), range(3), np.arange(3)])
def test_motion_accepts_any_array_like(angles):
    expected = np.asarray(angles, dtype=float)
    for mech in MECHANISMS.values():
        m = mech.motion(angles)
        assert np.allclose(m.phi, expected)
        assert np.asarray(m.points[next(iter(m.points))].x).shape == (3,)
