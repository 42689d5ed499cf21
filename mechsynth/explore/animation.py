"""The cycle's motion as the browser plays it: every frame's points, blocks, outlines and
velocity and acceleration vectors, sent once per design and drawn by the page's script at the
display's frame rate (no server round trip per frame).

Plain numpy (no Panel): :func:`frames` gives the columns of the page's frame source and the
drawing's fixed structure, in display units; :data:`PLAYER_JS` is the script that draws them.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import MechanismError
from .model import State, is_periodic

__all__ = ["FRAMES", "frames", "frame_glyphs", "fit_ranges", "PLAYER_JS", "COLORS"]

#: frames per cycle sent to the browser (it interpolates between them)
FRAMES = 180
COLORS = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442"]


def frames(state: State, design, n: int = FRAMES, trace=()) -> tuple[dict, dict]:
    """``(columns, meta)`` of one cycle of ``design`` in ``n`` frames, lengths in the display
    unit of ``state``.

    ``columns``: ``x:P``, ``y:P`` for every point P of the sketch; ``vx:P``, ``vy:P``,
    ``ax:P``, ``ay:P`` for the points whose motion the mechanism gives, scaled so that the
    longest vector over the cycle is a quarter of the drawing's size (the vectors' directions
    and their ratios are exact; ``meta["vscale"]``, ``meta["ascale"]`` give display length per
    unit of the SI quantity); ``a:i`` the angle (rad) of slider i; ``ox:i``, ``oy:i`` moving
    outline i; ``input``, the input at each frame (deg, or the display length of a driving
    slider's displacement).

    ``meta``: the structure the script draws (bars and plates with colours, moving joints,
    ground points, sliders, fixed guides and outlines, the traced paths of ``trace``), the
    extent of the cycle (``extent``: x0, x1, y0, y1), the input's label and unit.
    """
    n = int(n)
    if n < 2:
        raise MechanismError(f"frames: n must be at least 2, got {n}")
    periodic = is_periodic(design)
    phi = design.turn(n) if hasattr(design, "turn") else np.arange(n) * (2 * np.pi / n)
    sk = design.sketch(phi)
    f = state.display.factor("m")
    cols: dict[str, Any] = {}
    for p, (x, y) in sk.points.items():
        cols[f"x:{p}"] = (np.asarray(x, float) / f).tolist()
        cols[f"y:{p}"] = (np.asarray(y, float) / f).tolist()
    x0, x1, y0, y1 = (v / f for v in sk.extent())
    size = max(x1 - x0, y1 - y0, 1e-12)
    # velocity and acceleration of the points the motion gives (the page's speed or analogs)
    m = design.motion(phi, speed=state.speed) if state.speed else design.motion(phi)
    vec = [p for p in (m.points or {}) if p in sk.points and p not in sk.ground]
    vmax = amax = 0.0
    for p in vec:
        tr = m.points[p]
        vmax = max(vmax, float(np.nanmax(np.hypot(tr.vx, tr.vy))))
        amax = max(amax, float(np.nanmax(np.hypot(tr.ax, tr.ay))))
    vscale = 0.25 * size / vmax if vmax > 0 else 0.0
    ascale = 0.25 * size / amax if amax > 0 else 0.0
    for p in vec:
        tr = m.points[p]
        for key, arr, sc in (
            ("vx", tr.vx, vscale),
            ("vy", tr.vy, vscale),
            ("ax", tr.ax, ascale),
            ("ay", tr.ay, ascale),
        ):
            cols[f"{key}:{p}"] = (np.broadcast_to(np.asarray(arr, float), (n,)) * sc).tolist()
    sliders = []
    for i, s in enumerate(sk.sliders):
        a = np.broadcast_to(np.asarray(s.angle, dtype=float), (sk.frames,))
        cols[f"a:{i}"] = a.tolist()
        sliders.append({"point": s.point, "through": s.through, "i": i})
    outlines_fixed, moving = [], []
    for i, o in enumerate(sk.outlines):
        if np.ndim(o.x) == 2:
            cols[f"ox:{i}"] = (np.asarray(o.x, float) / f).tolist()
            cols[f"oy:{i}"] = (np.asarray(o.y, float) / f).tolist()
            moving.append(i)
        else:
            outlines_fixed.append(
                [(np.asarray(o.x, float) / f).tolist(), (np.asarray(o.y, float) / f).tolist()]
            )
    if periodic:
        shown = np.degrees(np.abs(np.asarray(phi, float))) % 360.0
        unit, label = "deg", "crank angle"
    else:
        shown = np.asarray(phi, float) / f
        unit, label = state.unit_label("m"), "input displacement"
    cols["input"] = shown.tolist()
    # fixed guides over the block's travel
    guides = []
    block = 0.06 * size
    for s in sk.sliders:
        if s.through is not None:
            continue
        px = np.asarray(sk.points[s.point][0], float) / f
        py = np.asarray(sk.points[s.point][1], float) / f
        a0 = float(np.ravel(np.asarray(s.angle, dtype=float))[0])
        u = (math.cos(a0), math.sin(a0))
        t = px * u[0] + py * u[1]
        ext = 0.08 * size
        t0, t1 = float(t.min()) - ext, float(t.max()) + ext
        bx, by = float(px[0] - t[0] * u[0]), float(py[0] - t[0] * u[1])
        guides.append([[bx + t0 * u[0], bx + t1 * u[0]], [by + t0 * u[1], by + t1 * u[1]]])
    joints = (
        sk.joints
        if sk.joints is not None
        else tuple(dict.fromkeys(p for b in sk.bars for p in b.points))
    )
    if state.kind.file_data is None:  # a built-in's points that drag (the horsehead) too
        from .editor import DRAGGABLE

        more = [p for p in DRAGGABLE.get(state.kind.key, {}) if p in sk.points]
        joints = tuple(dict.fromkeys((*joints, *more)))
    meta = {
        "n": n,
        "bars": [
            {"points": list(b.points), "color": COLORS[i % len(COLORS)]}
            for i, b in enumerate(sk.bars)
        ],
        "joints": [p for p in joints if p not in sk.ground],
        "ground": list(sk.ground),
        "sliders": sliders,
        "guides": guides,
        "outlines": outlines_fixed,
        "moving_outlines": moving,
        "vectors": vec,
        "vscale": vscale,
        "ascale": ascale,
        "block": block,
        # what the view must hold: the points, and the blocks drawn around them
        "extent": [x0 - block, x1 + block, y0 - block, y1 + block],
        "input_label": label,
        "input_unit": unit,
        "periodic": periodic,
        "points": list(sk.points),
        "trace": [p for p in trace if p in sk.points],
    }
    return cols, meta


def fit_ranges(extent, width_px: float, height_px: float, pad: float = 0.08):
    """``(x0, x1, y0, y1)`` of a view with equal scales on both axes over a frame of
    ``width_px`` x ``height_px`` that holds ``extent`` (x0, x1, y0, y1) with a margin of
    ``pad`` of its size (the page's script does the same on the frame it has)."""
    x0, x1, y0, y1 = (float(v) for v in extent)
    m = pad * max(x1 - x0, y1 - y0, 1e-12)
    scale = max((x1 - x0 + 2 * m) / width_px, (y1 - y0 + 2 * m) / height_px)
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    return (
        cx - scale * width_px / 2,
        cx + scale * width_px / 2,
        cy - scale * height_px / 2,
        cy + scale * height_px / 2,
    )


# The player: one script for every callback (Bokeh CustomJS); ``what`` says which called it.
# State lives on window.mx_explore; every change it makes to the document is local
# ({sync: false}) except the view's ranges and the frame shown when the player stops, so
# playing costs the server nothing.
PLAYER_JS = r"""
const mx = (window.mx_explore = window.mx_explore || {pos: 0, playing: false, dir: 1,
                                                       drawn: 0, t_play: 0, fps: 0});
const S = sources;
function meta() {
  const txt = S.meta.data.json && S.meta.data.json[0];
  if (!txt) return null;
  if (mx._txt !== txt) { mx._txt = txt; mx.meta = JSON.parse(txt); }
  return mx.meta;
}
function local(model, attrs) { model.setv(attrs, {sync: false}); }
function pt(F, p, k0, k1, t) {
  const x = F['x:' + p], y = F['y:' + p];
  return [x[k0] + (x[k1] - x[k0]) * t, y[k0] + (y[k1] - y[k0]) * t];
}
function draw(pos) {
  const M = meta();
  if (!M) return;
  const F = S.frames.data, n = M.n;
  pos = ((pos % n) + n) % n;
  const k0 = Math.floor(pos), k1 = (k0 + 1) % n, t = pos - k0;
  const P = {};
  for (const p of M.points) P[p] = pt(F, p, k0, k1, t);
  const bars = {xs: [], ys: [], color: []}, plates = {xs: [], ys: [], color: []};
  for (const b of M.bars) {
    const d = b.points.length >= 3 ? plates : bars;
    d.xs.push(b.points.map(p => P[p][0])); d.ys.push(b.points.map(p => P[p][1]));
    d.color.push(b.color);
  }
  local(S.bars, {data: bars}); local(S.plates, {data: plates});
  local(S.joints, {data: {x: M.joints.map(p => P[p][0]), y: M.joints.map(p => P[p][1]),
                          name: M.joints.slice()}});
  const blk = {x: [], y: [], angle: [], w: [], h: []};
  const gx = M.guides.map(g => g[0]), gy = M.guides.map(g => g[1]);
  for (const s of M.sliders) {
    const a = F['a:' + s.i][k0];
    blk.x.push(P[s.point][0]); blk.y.push(P[s.point][1]); blk.angle.push(a);
    blk.w.push(1.6 * M.block); blk.h.push(M.block);
    if (s.through !== null) {
      const r = 2.5 * M.block, c = Math.cos(a), sn = Math.sin(a), q = P[s.through];
      gx.push([q[0] - r * c, q[0] + r * c]); gy.push([q[1] - r * sn, q[1] + r * sn]);
    }
  }
  local(S.blocks, {data: blk}); local(S.guides, {data: {xs: gx, ys: gy}});
  const ox = M.outlines.map(o => o[0]), oy = M.outlines.map(o => o[1]);
  for (const i of M.moving_outlines) { ox.push(F['ox:' + i][k0]); oy.push(F['oy:' + i][k0]); }
  local(S.outlines, {data: {xs: ox, ys: oy}});
  const show = vectors.active, vel = {xs: [], ys: []}, acc = {xs: [], ys: []};
  for (const p of M.vectors) {
    const [x, y] = P[p];
    if (show.includes(0)) {
      vel.xs.push([x, x + F['vx:' + p][k0]]); vel.ys.push([y, y + F['vy:' + p][k0]]);
    }
    if (show.includes(1)) {
      acc.xs.push([x, x + F['ax:' + p][k0]]); acc.ys.push([y, y + F['ay:' + p][k0]]);
    }
  }
  local(S.vel, {data: vel}); local(S.acc, {data: acc});
  const inp = F.input[k0];
  // the curves' markers: each moved marker repaints its figure, so they follow when the
  // player stands still
  if (!mx.playing) for (const sp of spans) local(sp, {location: M.periodic ? 360 * pos / n : inp});
  const txt = `${M.input_label} ${inp.toFixed(M.periodic ? 0 : 1)} ${M.input_unit}`;
  local(overlay, {text: txt});  // on the canvas: cheap at every frame
  // the page's text re-lays the page out (some 30 ms): only when the player stands still
  if (!mx.playing) local(label, {text: `<span id="input-shown">${txt}</span>`});
  mx.pos = pos; mx.drawn += 1;
}
mx.draw = draw;
function fit(force) {
  const M = meta();
  if (!M) return;
  const [x0, x1, y0, y1] = M.extent;
  const w = fig.inner_width, h = fig.inner_height;
  if (!(w > 0 && h > 0)) return;
  const xr = fig.x_range, yr = fig.y_range;
  const inside = x0 >= xr.start && x1 <= xr.end && y0 >= yr.start && y1 <= yr.end;
  const small = (x1 - x0) < 0.2 * (xr.end - xr.start) && (y1 - y0) < 0.2 * (yr.end - yr.start);
  if (!force && inside && !small) return;
  const m = 0.08 * Math.max(x1 - x0, y1 - y0, 1e-12);
  const sc = Math.max((x1 - x0 + 2 * m) / w, (y1 - y0 + 2 * m) / h);
  const cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  xr.setv({start: cx - sc * w / 2, end: cx + sc * w / 2,
           reset_start: cx - sc * w / 2, reset_end: cx + sc * w / 2});
  yr.setv({start: cy - sc * h / 2, end: cy + sc * h / 2,
           reset_start: cy - sc * h / 2, reset_end: cy + sc * h / 2});
  mx.fits = (mx.fits || 0) + 1;
}
function loop(ts) {
  if (!mx.playing) return;
  const M = meta();
  if (mx.last === undefined) mx.last = ts;
  const dt = Math.min((ts - mx.last) / 1000, 0.25);
  mx.last = ts;
  const period = Math.max(period_s.value, 0.2);
  draw(mx.pos + mx.dir * dt * M.n / period);
  // the frame slider follows when the player stops (moving it re-lays the page out: some
  // 60 ms a frame, which would halve the frame rate)
  mx.frames_played += 1;
  mx.fps = mx.frames_played / Math.max((ts - mx.t_play) / 1000, 1e-3);
  requestAnimationFrame(loop);
}
function stop() {
  mx.playing = false;
  draw(mx.pos);
  play.setv({label: 'Play'});
  mx.expect = Math.round(mx.pos) % (meta() || {n: 1}).n;
  frame.setv({value: mx.expect});  // the server's frame
}
if (what === 'meta') {
  const M = meta();
  if (M) {
    if (frame.end !== M.n - 1) frame.setv({end: M.n - 1});
    draw(Math.min(mx.pos, M.n - 1)); fit(Boolean(S.meta.data.force[0]));
  }
} else if (what === 'frame') {
  if (frame.value === mx.expect) { mx.expect = null; }
  else { if (mx.playing) stop(); draw(frame.value); }
} else if (what === 'play') {
  if (mx.playing) { stop(); } else {
    mx.playing = true; mx.last = undefined; mx.frames_played = 0;
    mx.t_play = performance.now(); play.setv({label: 'Pause'});
    requestAnimationFrame(loop);
  }
} else if (what === 'back' || what === 'fwd') {
  if (mx.playing) stop();
  const M = meta(), step = M ? M.n / 72 : 1;
  draw(mx.pos + (what === 'fwd' ? step : -step));  // 5 degrees, or 1/72 of a travel
  // the slider (and the server) follow; the drawing is already there (callbacks run
  // later, so the slider's own callback is told by the value it will see)
  mx.expect = Math.round(mx.pos) % M.n;
  frame.setv({value: mx.expect});
} else if (what === 'reverse') {
  mx.dir = -mx.dir;
} else if (what === 'vectors') {
  draw(mx.pos);
} else if (what === 'resize') {
  fit(true);
}
"""


def frame_glyphs(cols: dict, meta: dict, k: int) -> dict[str, dict]:
    """The glyph sources' data at frame ``k`` (what the page's script draws there, without
    interpolation): ``bars``, ``plates``, ``joints``, ``blocks``, ``guides``, ``outlines``."""
    n = meta["n"]
    k = int(k) % n
    pt = {p: (cols[f"x:{p}"][k], cols[f"y:{p}"][k]) for p in meta["points"]}
    bars = {"xs": [], "ys": [], "color": []}
    plates = {"xs": [], "ys": [], "color": []}
    for b in meta["bars"]:
        d = plates if len(b["points"]) >= 3 else bars
        d["xs"].append([pt[p][0] for p in b["points"]])
        d["ys"].append([pt[p][1] for p in b["points"]])
        d["color"].append(b["color"])
    js = meta["joints"]
    joints = {"x": [pt[p][0] for p in js], "y": [pt[p][1] for p in js], "name": list(js)}
    blocks = {"x": [], "y": [], "angle": [], "w": [], "h": []}
    gx = [g[0] for g in meta["guides"]]
    gy = [g[1] for g in meta["guides"]]
    w = meta["block"]
    for s in meta["sliders"]:
        a = cols[f"a:{s['i']}"][k]
        blocks["x"].append(pt[s["point"]][0])
        blocks["y"].append(pt[s["point"]][1])
        blocks["angle"].append(a)
        blocks["w"].append(1.6 * w)
        blocks["h"].append(w)
        if s["through"] is not None:
            r, (tx, ty) = 2.5 * w, pt[s["through"]]
            gx.append([tx - r * math.cos(a), tx + r * math.cos(a)])
            gy.append([ty - r * math.sin(a), ty + r * math.sin(a)])
    ox = [o[0] for o in meta["outlines"]] + [cols[f"ox:{i}"][k] for i in meta["moving_outlines"]]
    oy = [o[1] for o in meta["outlines"]] + [cols[f"oy:{i}"][k] for i in meta["moving_outlines"]]
    return {
        "bars": bars,
        "plates": plates,
        "joints": joints,
        "blocks": blocks,
        "guides": {"xs": gx, "ys": gy},
        "outlines": {"xs": ox, "ys": oy},
    }


# Accessible names for what Bokeh leaves without one (a slider's handle, whose title is a
# separate element; a checkbox beside a text that is no <label>). Shadow roots are walked.
A11Y_JS = r"""
function walk(root, fn) {
  fn(root);
  for (const el of root.querySelectorAll('*')) if (el.shadowRoot) walk(el.shadowRoot, fn);
}
walk(document, (root) => {
  for (const h of root.querySelectorAll('.noUi-handle')) {
    const t = root.querySelector('.bk-slider-title');
    const name = t ? t.textContent.split(':')[0].trim() : '';
    if (name && h.getAttribute('aria-label') !== name) h.setAttribute('aria-label', name);
  }
  // a checkbox drawn beside a text that is no <label> (Bokeh's Checkbox)
  for (const c of root.querySelectorAll('input[type=checkbox]')) {
    if (c.labels && c.labels.length) continue;
    const t = c.nextElementSibling ? c.nextElementSibling.textContent.trim() : '';
    if (t && c.getAttribute('aria-label') !== t) c.setAttribute('aria-label', t);
  }
});
"""
