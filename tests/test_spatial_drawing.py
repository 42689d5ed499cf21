"""The spatial drive's 3-D animation (equal scales, the real geometry, a small GIF) and the
tolerance chart's limit line solved on rays (spatial_design.limit_contour)."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

import mechsynth as ms  # noqa: E402
from mechsynth.errors import MechanismError  # noqa: E402
from mechsynth.machines.pumping_unit.spatial_design import limit_contour  # noqa: E402
from mechsynth.machines.pumping_unit.spatial_drawing import animate_drive  # noqa: E402
from mechsynth.plotting import layout_problems  # noqa: E402

C320 = dict(A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98, units="in")
TH = np.linspace(0.0, 2.0 * np.pi, 24, endpoint=False)
LOAD, SPEED = 60e3, ms.spm(6)


@pytest.fixture(scope="module")
def drive():
    unit = ms.BeamPumpingUnit.from_api(**C320)
    return ms.SpatialPumpingUnit.from_planar(unit, crank_spacing=1.2, equalizer_width=1.2)


def test_the_animation_draws_the_drive_in_3d_with_equal_scales(drive, tmp_path):
    anim = animate_drive(drive, speed=SPEED, frames=6, dpi=40)
    fig = anim.figure
    (ax,) = [a for a in fig.axes if a.name == "3d"]
    assert layout_problems(fig) == []
    # equal scales: the box's sides in proportion to the data ranges shown
    spans = np.array([np.ptp(ax.get_xlim()), np.ptp(ax.get_ylim()), np.ptp(ax.get_zlim())])
    # (matplotlib keeps the box in its view's order: with y drawn vertical, z x y)
    box = np.roll(np.asarray(ax.get_box_aspect()), -1)
    np.testing.assert_allclose(box / box.max(), spans / spans.max(), rtol=1e-9)
    # the moving lines are the motion's joints at each frame
    m = drive.motion(drive.sense * np.linspace(0.0, 2.0 * np.pi, 6, endpoint=False))
    anim._func(4)
    (left,) = [ln for ln in ax.get_lines() if ln.get_label().startswith("left crank")]
    xs, ys, zs = left.get_data_3d()
    want = np.array([m.points[k].position[4] for k in ("O", "A", "B")])
    np.testing.assert_allclose(np.column_stack([xs, ys, zs]), want, atol=1e-12)
    path = anim.save(tmp_path / "drive.gif")
    from PIL import Image

    with Image.open(path) as im:
        assert im.n_frames == 6
    assert path.stat().st_size < 150_000  # small: 6 frames at 40 dpi


def test_the_animation_refuses_bad_input(drive):
    with pytest.raises(MechanismError, match="frames must be at least 2"):
        animate_drive(drive, frames=1)
    with pytest.raises(MechanismError, match="at least two finite crank angles"):
        animate_drive(drive, angles=[0.0, np.nan])


def test_the_limit_line_is_on_the_limit_and_agrees_with_the_grid(drive):
    reach1, reach2, limit = np.radians(0.6), 0.008, 0.05
    c1, c2, split = limit_contour(
        drive, "phase_mismatch", reach1, "crank_difference", reach2, TH, SPEED, LOAD,
        limit=limit, rays=7, rtol=1e-3,
    )  # fmt: skip
    ok = np.isfinite(c1)
    assert ok.sum() >= 5
    np.testing.assert_allclose(split[ok], limit, rtol=1.01e-3)
    # on the rays: just inside is within the limit, just outside beyond it (the exact model)
    from mechsynth.machines.pumping_unit.spatial_design import _peak_splits

    near = [{"phase_mismatch": a * f, "crank_difference": b * f} for a, b in zip(c1[ok], c2[ok])
            for f in (0.97, 1.03)]  # fmt: skip
    s = _peak_splits(near, drive, TH, SPEED, LOAD, None).reshape(-1, 2)
    assert np.all(s[:, 0] < limit) and np.all(s[:, 1] > limit)
    # a box wholly within the limit has no line; a bad reach is named
    tiny = limit_contour(drive, "phase_mismatch", 1e-6, "crank_difference", 1e-6, TH, SPEED, LOAD,
                         rays=3)  # fmt: skip
    assert np.isnan(tiny[0]).all()
    with pytest.raises(MechanismError, match="reach2 must be a positive finite number"):
        limit_contour(drive, "phase_mismatch", 0.01, "crank_difference", -1.0, TH, SPEED, LOAD)
