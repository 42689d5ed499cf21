"""Linkage paths side by side: the numpy model, the compiled kernel through the API and raw,
plain numpy, and pylinkage -- for 1, 100 and 10,000 designs of three six-bars at 360 angles.

The linkages: a Watt II (two four-bars in series: a point on the first rocker drives a second
RRR dyad to the ground), a Stephenson III (a point on the four-bar's coupler drives an RRR dyad
to the ground) and paper 001's six-link (``ms.six_link()``: crank, RRR, a point on the rocker,
a rod and slider on a guide). Designs differ in their crank's and last dyad's lengths (up to
+-1 %), so that every group of a batch is a batch.

Each row is timed (CPU time of the process, every path on one thread) as the median of
``--repeat`` samples, each sample ``--runs`` times (three by default) in one process, and
printed as the three runs' times and their ratios to the numpy model's time in the same run:

* ``Linkage.motion``: every output (every point's position, velocity and acceleration, every
  link's angle and analogs, sliders, per-group pressure and transmission angles and assembly
  margins) at 600 rpm, the designs as ``(n, 1)`` parameter arrays (on the numpy model). For one
  design it is the default's steady state: its first calls on the model pay for the
  structure's kernel, which then serves (a just-in-time choice; the row is timed once the
  kernel is held); ``Linkage.motion(kernel=False)`` is the model alone and
  ``Linkage.motion(kernel=True)`` the kernel taken at once;
* ``plain numpy, every output``: the same outputs written out by hand for this linkage
  (:func:`plain_numpy`), checked against the model to 1e-12;
* ``plain numpy, positions``: the points' positions alone, by hand;
* ``kernel via linkage_batch``: the generated kernel through the API (the Motion of the batch,
  every output; for one design also ``kernel via one_motion``, what
  ``Linkage.motion(kernel=True)`` calls, a block of its own per call); ``kernel raw``: the
  kernel's call into a reused block. Both in chunks of a 2
  MiB block (:data:`KERNEL_BLOCK`, a few designs), which stays in the caches; ``kernel raw,
  chunks of 182 designs`` shows the cost of a 33 MB block written out to memory. These rows
  are the default code generator's (C where a compiler is found); ``..., numba`` the same on
  numba's kernel, side by side; ``kernel raw, points only``: the kernel of the points'
  positions, velocities and accelerations alone (``outputs="points"``: what pylinkage's
  kinematics computes), and ``linkage_batch, points only`` the same through the API (the
  Motion of the points' tracks);
* pylinkage 1.3.0 (``pip install pylinkage==1.3.0``; the rows are skipped without it): its
  position loop ``Linkage.step`` (one design after the other; at 10,000 designs on a sample of
  10, scaled, and marked so), its compiled ``step_fast``, its ensemble API
  (``Ensemble.simulate``: positions of every member in one compiled call) and its kinematics
  ``step_fast_with_kinematics`` (positions, velocities and accelerations); its positions are
  checked equal to the model's to 1e-9.

Below each table, the ratios the paths are judged by (:data:`GOALS`), per run.

With ``--compile``, for each code generator (C and numba), new processes with a new cache
directory time the kernel's first compilation (blocking; wall time, and CPU time with the C
compiler's), its load from the disk cache (numba's after its start: its import and first-use
set-up, paid once per process by any compiled function, timed apart), and
``linkage_kernel(..., wait=False)``: how soon the first call returns, how many motions the model
serves while the kernel compiles in the background, and when the kernel is ready.

Run: ``python benchmarks/bench_linkage_paths.py [--designs 1 100 10000] [--runs 3]
[--compile] [--json]``; ``--show FILE`` prints the report saved with ``--json``. The machine
these run on is shared: compare ratios within a run.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import mechsynth as ms
from mechsynth.kinematics import linkage_kernels as lkk
from mechsynth.kinematics.compiled import BatchWorkspace

SPEED = ms.rpm(600)
PHI = ms.cycle(360)


# ---------------------------------------------------------------------------- the linkages
def four_bar():
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.10, 0.0)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.10), ("D", 0.07))
    )


def watt_ii():
    lk = four_bar().attach("K", on="DB", along=0.05, left=0.02).ground_point("F", 0.16, 0.06)
    return lk.rrr("E", ("K", 0.08), ("F", 0.06))


def stephenson_iii():
    lk = four_bar().attach("C", on=("A", "B"), along=0.05, left=0.03)
    return lk.ground_point("F", 0.06, 0.12).rrr("E", ("C", 0.07), ("F", 0.08))


LINKAGES = {"Watt II": watt_ii, "Stephenson III": stephenson_iii, "six-link": ms.six_link}
# the crank varies too: every group of a batch is then a batch (with the last dyad's lengths
# alone, the model would solve the crank and the four-bar once for all designs)
VARIED = {"Watt II": ("OA", "KE", "FE"), "Stephenson III": ("OA", "CE", "FE"),
          "six-link": ("OA", "KN")}  # fmt: skip


def designs(name, n, seed=0):
    """``n`` designs of the linkage: its crank's and last dyad's lengths scaled by up to
    +-1 %."""
    lk = LINKAGES[name]()
    rng = np.random.default_rng(seed)
    values = {k: lk.parameters[k] * (1.0 + rng.uniform(-0.01, 0.01, (n, 1))) for k in VARIED[name]}
    if n == 1:
        values = {k: float(v[0, 0]) for k, v in values.items()}
    return lk(**values)


# ---------------------------------------------------------------------------- plain numpy
def _jet_rrr(p1, p2, l1, l2, branch):
    """C at l1 from p1 and l2 from p2 with its analogs, the two links' angle jets and the
    group's margin (textbook loop closure, by hand)."""
    x1, y1, dx1, dy1, ddx1, ddy1 = p1
    x2, y2, dx2, dy2, ddx2, ddy2 = p2
    ux, uy = x2 - x1, y2 - y1
    d2 = ux * ux + uy * uy
    a = (l1 * l1 - l2 * l2 + d2) / (2.0 * d2)
    h = branch * np.sqrt(l1 * l1 / d2 - a * a)
    ex, ey = a * ux - h * uy, a * uy + h * ux
    cx, cy = x1 + ex, y1 + ey
    fx, fy = cx - x2, cy - y2
    cr = ex * fy - ey * fx
    rx, ry = dx2 - dx1, dy2 - dy1
    w1, w2 = (rx * fx + ry * fy) / cr, (rx * ex + ry * ey) / cr
    sx = ddx2 - ddx1 + w1 * w1 * ex - w2 * w2 * fx
    sy = ddy2 - ddy1 + w1 * w1 * ey - w2 * w2 * fy
    e1, e2 = (sx * fx + sy * fy) / cr, (sx * ex + sy * ey) / cr
    c = (cx, cy, dx1 - w1 * ey, dy1 + w1 * ex,
         ddx1 - e1 * ey - w1 * w1 * ex, ddy1 + e1 * ex - w1 * w1 * ey)  # fmt: skip
    t1, t2 = np.arctan2(ey, ex), np.arctan2(fy, fx)
    mu = np.arccos(np.cos(t1 - t2))
    margin = ((l1 + l2) ** 2 - d2) * (d2 - (l1 - l2) ** 2) / (4.0 * l1 * l1 * l2 * l2)
    return c, (t1, w1, e1), (t2, w2, e2), mu, np.abs(np.pi / 2 - mu), margin


def _jet_attach(base, angle, u, v):
    """A point fixed on a link: ``u`` along its direction ``angle`` from ``base``, ``v`` left."""
    t, w, e = angle
    c, s = np.cos(t), np.sin(t)
    ox, oy = u * c - v * s, u * s + v * c
    x, y, dx, dy, ddx, ddy = base
    return (x + ox, y + oy, dx - oy * w, dy + ox * w,
            ddx - oy * e - ox * w * w, ddy + ox * e - oy * w * w)  # fmt: skip


def _jet_rrp(p, length, gx, gy, angle, branch):
    """A rod of ``length`` from ``p`` to a slider on the fixed guide through (gx, gy) at
    ``angle``: the slider's point and travel jets, the rod's angle jet, margin and pressure."""
    x, y, dx, dy, ddx, ddy = p
    cg, sg = np.cos(angle), np.sin(angle)
    t = (x - gx) * cg + (y - gy) * sg  # foot of p along the guide
    hgt = -(x - gx) * sg + (y - gy) * cg
    t1, h1 = dx * cg + dy * sg, -dx * sg + dy * cg
    t2, h2 = ddx * cg + ddy * sg, -ddx * sg + ddy * cg
    w = branch * np.sqrt(length * length - hgt * hgt)
    a1 = -h1 / w  # the rod's angle to the guide, its analogs
    a2 = -(h2 + hgt * a1 * a1) / w
    w1 = hgt * a1
    w2 = -(length * length * a1 * a1 + hgt * h2) / w
    s, s1, s2 = t + w, t1 + w1, t2 + w2
    point = (gx + s * cg, gy + s * sg, s1 * cg, s1 * sg, s2 * cg, s2 * sg)
    rod = (np.arctan2(point[1] - y, point[0] - x), a1, a2)
    margin = (length * length - hgt * hgt) / (length * length)
    return point, (s, s1, s2), rod, margin, np.arcsin(np.abs(hgt) / length)


def plain_numpy(lk, phi, w):
    """Every output of ``lk.motion(phi, speed=w)`` by hand: ``{name: array}``."""
    v = lk.parameters
    cp, sp = np.cos(phi), np.sin(phi)
    r = v["OA"]
    ax, ay = v["O_x"] + r * cp, v["O_y"] + r * sp
    one = np.ones_like(phi)
    pts = {"A": (ax, ay, -r * sp, r * cp, -r * cp, -r * sp)}
    zero = np.zeros(np.broadcast_shapes(np.shape(ax), *(np.shape(x) for x in v.values())))
    out = {}
    ground = {p: (v[f"{p}_x"], v[f"{p}_y"]) for p in ("O", "D", "F") if f"{p}_x" in v}
    for p, (x, y) in ground.items():
        pts[p] = (x + zero, y + zero, zero, zero, zero, zero)
    links = {"OA": (phi + v["phase"], one, 0.0 * phi)}
    b, tab, tdb, mu, pr, mg = _jet_rrr(pts["A"], pts["D"], v["AB"], v["DB"], 1)
    pts["B"], links["AB"], links["DB"] = b, tab, tdb
    out.update({"mu B": mu, "pressure B": pr, "margin B": mg})
    if "KE" in v:  # Watt II
        pts["K"] = _jet_attach(pts["D"], tdb, v["K_along"], v["K_left"])
        e, tke, tfe, mu, pr, mg = _jet_rrr(pts["K"], pts["F"], v["KE"], v["FE"], 1)
        pts["E"], links["KE"], links["FE"] = e, tke, tfe
        out.update({"mu E": mu, "pressure E": pr, "margin E": mg})
    elif "CE" in v:  # Stephenson III
        pts["C"] = _jet_attach(pts["A"], tab, v["C_along"], v["C_left"])
        e, tce, tfe, mu, pr, mg = _jet_rrr(pts["C"], pts["F"], v["CE"], v["FE"], 1)
        pts["E"], links["CE"], links["FE"] = e, tce, tfe
        out.update({"mu E": mu, "pressure E": pr, "margin E": mg})
    else:  # the six-link: the slider's guide through O, offset to its left
        pts["K"] = _jet_attach(pts["D"], tdb, v["K_along"], v["K_left"])
        ang, off = v["N_guide_angle"], v["N_guide_offset"]
        gx, gy = v["O_x"] - off * np.sin(ang), v["O_y"] + off * np.cos(ang)
        n, slide, rod, mg, pr = _jet_rrp(pts["K"], v["KN"], gx, gy, ang, -1)
        pts["N"], links["KN"], links["N"] = n, rod, (ang + zero, zero, zero)
        out.update({"slider N": slide, "margin N": mg, "pressure N": pr, "mu N": np.pi / 2 - pr})
    w2 = w * w
    for p, (x, y, dx, dy, ddx, ddy) in pts.items():
        out[f"point {p}"] = (x, y, w * dx, w * dy, w2 * ddx, w2 * ddy)
    for k, (t, d1, d2) in links.items():
        out[f"link {k}"] = (t, w * d1, w2 * d2)
    if "slider N" in out:
        s, s1, s2 = out["slider N"]
        out["slider N"] = (s, w * s1, w2 * s2)
    return out


def plain_positions(lk, phi):
    """The points' positions alone, by hand."""
    v = lk.parameters
    cp, sp = np.cos(phi), np.sin(phi)
    ax, ay = v["O_x"] + v["OA"] * cp, v["O_y"] + v["OA"] * sp

    def rrr(x1, y1, x2, y2, l1, l2):
        ux, uy = x2 - x1, y2 - y1
        d2 = ux * ux + uy * uy
        a = (l1 * l1 - l2 * l2 + d2) / (2.0 * d2)
        h = np.sqrt(l1 * l1 / d2 - a * a)
        return x1 + a * ux - h * uy, y1 + a * uy + h * ux

    def attach(x0, y0, x1, y1, u, w):
        dx, dy = x1 - x0, y1 - y0
        r = np.sqrt(dx * dx + dy * dy)
        c, s = dx / r, dy / r
        return x0 + u * c - w * s, y0 + u * s + w * c

    dx, dy = v["D_x"], v["D_y"]
    bx, by = rrr(ax, ay, dx, dy, v["AB"], v["DB"])
    out = {"A": (ax, ay), "B": (bx, by)}
    if "KE" in v:
        kx, ky = attach(dx, dy, bx, by, v["K_along"], v["K_left"])
        out.update(K=(kx, ky), E=rrr(kx, ky, v["F_x"], v["F_y"], v["KE"], v["FE"]))
    elif "CE" in v:
        cx, cy = attach(ax, ay, bx, by, v["C_along"], v["C_left"])
        out.update(C=(cx, cy), E=rrr(cx, cy, v["F_x"], v["F_y"], v["CE"], v["FE"]))
    else:
        kx, ky = attach(dx, dy, bx, by, v["K_along"], v["K_left"])
        ang, off = v["N_guide_angle"], v["N_guide_offset"]
        cg, sg = np.cos(ang), np.sin(ang)
        gx, gy = v["O_x"] - off * sg, v["O_y"] + off * cg
        t = (kx - gx) * cg + (ky - gy) * sg
        hgt = -(kx - gx) * sg + (ky - gy) * cg
        s = t - np.sqrt(v["KN"] ** 2 - hgt * hgt)
        out.update(K=(kx, ky), N=(gx + s * cg, gy + s * sg))
    return out


def check_plain(lk, phi):
    """The hand-written outputs equal the model's to 1e-12 (relative to each output's size)."""
    m = lk.motion(phi, speed=SPEED)
    ref = plain_numpy(lk, phi, SPEED)
    pairs = []
    for p, track in m.points.items():
        pairs += zip(vars(track).values(), ref[f"point {p}"])
    for k, track in m.links.items():
        pairs += zip(vars(track).values(), ref[f"link {k}"])
    for key, tm in m.raw_transmission_angles.items():
        pairs += [(tm, ref[f"mu {key}"])]
    for key, pa in m.pressure_angles.items():
        pairs += [(pa, ref[f"pressure {key}"])]
    for key, mg in m.extra["assembly margins"].items():
        pairs += [(mg, ref[f"margin {key}"])]
    for key, s in m.sliders.items():
        pairs += zip(vars(s).values(), ref[f"slider {key}"])
    worst = 0.0
    for a, b in pairs:
        a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
        worst = max(worst, float(np.max(np.abs(a - b)) / max(1.0, np.max(np.abs(a)))))
    assert worst < 1e-12, worst
    pos = plain_positions(lk, phi)
    for p, (x, y) in pos.items():
        assert np.allclose(x, m.points[p].x, rtol=0, atol=1e-12), p
        assert np.allclose(y, m.points[p].y, rtol=0, atol=1e-12), p
    return worst, len(pairs)


# ---------------------------------------------------------------------------- pylinkage
def pylinkage_of(lk):
    """The same linkage in pylinkage 1.3.0 (one design), its crank turning a degree per step
    from 1 degree (its first step's position), and the joints in the model's point order."""
    import pylinkage as pl

    v = lk.parameters
    m = lk.motion(np.array([np.radians(1.0)]))
    g = {p: pl.Ground(v[f"{p}_x"], v[f"{p}_y"], name=p) for p in ("O", "D", "F") if f"{p}_x" in v}
    a = pl.Crank(g["O"], v["OA"], angular_velocity=np.radians(1.0), initial_angle=0.0, name="A")

    def near(p):
        return dict(x=float(m.points[p].x[0]), y=float(m.points[p].y[0]), name=p)

    b = pl.RRRDyad(a, g["D"], v["AB"], v["DB"], **near("B"))
    joints = {"A": a, "B": b}

    def fixed(name, p0, p1, along, left):
        return pl.FixedDyad(p0, p1, float(np.hypot(along, left)), float(np.arctan2(left, along)),
                            name=name)  # fmt: skip

    if "KE" in v:
        joints["K"] = fixed("K", g["D"], b, v["K_along"], v["K_left"])
        joints["E"] = pl.RRRDyad(joints["K"], g["F"], v["KE"], v["FE"], **near("E"))
    elif "CE" in v:
        joints["C"] = fixed("C", a, b, v["C_along"], v["C_left"])
        joints["E"] = pl.RRRDyad(joints["C"], g["F"], v["CE"], v["FE"], **near("E"))
    else:
        joints["K"] = fixed("K", g["D"], b, v["K_along"], v["K_left"])
        ang, off = v["N_guide_angle"], v["N_guide_offset"]
        gx, gy = v["O_x"] - off * np.sin(ang), v["O_y"] + off * np.cos(ang)
        g["G1"] = pl.Ground(gx, gy, name="G1")
        g["G2"] = pl.Ground(gx + np.cos(ang), gy + np.sin(ang), name="G2")
        joints["N"] = pl.RRPDyad(joints["K"], g["G1"], g["G2"], v["KN"], **near("N"))
    linkage = pl.Linkage([*g.values(), *joints.values()], name=lk.name)
    names = [c.name for c in linkage.components]
    return linkage, names


def pylinkage_check(lk):
    """pylinkage's positions equal the model's at the same crank angles (to 1e-9)."""
    linkage, names = pylinkage_of(lk)
    phi = np.radians(np.arange(1.0, 361.0))
    traj = linkage.step_fast(iterations=360)
    m = lk.motion(phi)
    for i, p in enumerate(names):
        if p in m.points:
            assert np.allclose(traj[:, i, 0], m.points[p].x, atol=1e-9), p
            assert np.allclose(traj[:, i, 1], m.points[p].y, atol=1e-9), p


# ---------------------------------------------------------------------------- timing
def timed(rows, repeat):
    """``{row: the median CPU time of one call}`` of ``rows`` (``{row: (fn, scale)}``, the time
    scaled) over ``repeat`` samples, each sample as many calls as take some 20 ms (a call of
    tens of microseconds timed alone reads its cold caches and the clock's own cost), after one
    call. The rows are timed in turn within each sample, so that a change of the machine's load
    during a run weighs on every row alike (timed one row after the other, the ratio of
    ``Linkage.motion`` to plain numpy for one design moved between 0.7 and 1.2 from one run to
    the next). CPU time: every path runs on one thread, and on a shared machine the process's
    CPU time counts its own work, not the time other processes hold the cores (its wall time
    varied 5-10 x between runs at a load average of 10 on 2 cores)."""
    calls = {}
    for label, (fn, _) in rows.items():
        t = time.process_time()
        fn()
        first = time.process_time() - t
        calls[label] = max(1, min(10_000, int(0.02 / max(first, 1e-7))))
    times: dict = {label: [] for label in rows}
    for _ in range(repeat):
        for label, (fn, _) in rows.items():
            k = calls[label]
            t = time.process_time()
            for _ in range(k):
                fn()
            times[label].append((time.process_time() - t) / k)
    return {label: statistics.median(times[label]) * scale for label, (_, scale) in rows.items()}


#: designs per call: 10,000 designs run in chunks (as sweeps do), the block of every output of
#: 10,000 six-bars at 360 angles would be 1.7 GB
CHUNK = 2**16 // 360

#: the kernel's block per call (doubles): 2 MiB, within this machine's caches (1 MiB L2 a
#: core, 32 MiB L3 shared), so the kernel's 60-odd output rows are not written out to memory
#: and read back at every chunk (measured on a Watt II, 10,000 designs, CPU time: 130-170 ms
#: in blocks of 0.7-2.9 MB, 300-320 ms in blocks of 182 designs, 33 MB)
KERNEL_BLOCK = 2**18


def kernel_chunk(kernel):
    """Designs per kernel call: a block of :data:`KERNEL_BLOCK` doubles."""
    return max(1, KERNEL_BLOCK // (kernel.outputs * PHI.size))


def paths(name, n, have_pylinkage):
    """``{row: function}`` for ``n`` designs of linkage ``name`` (in chunks of ``CHUNK``; the
    kernel's in chunks of :func:`kernel_chunk`, and in chunks of ``CHUNK`` for comparison)."""
    size = min(n, CHUNK)
    count = -(-n // size)
    lk = designs(name, size)
    kernels = backend_kernels(lk)
    kernel = next(iter(kernels.values()))  # the default generator's (C where a compiler is)
    ksize = min(n, kernel_chunk(kernel))
    kcount = -(-n // ksize)
    klk = designs(name, ksize)
    ws = BatchWorkspace()

    def raw_call(k, n_k, kernel=kernel):
        cols = [np.broadcast_to(np.asarray(k.parameters[p], float).reshape(-1), (n_k,))
                for p in kernel.names]  # fmt: skip
        params = np.ascontiguousarray(np.stack(cols, axis=1))
        block, flags = np.empty((kernel.outputs, n_k, PHI.size)), np.empty((n_k, 2))
        return lambda: kernel(params, PHI, block, flags, speed=(SPEED, 0.0), threads=False)

    def chunks(fn, times=count):
        def run():
            for _ in range(times):
                fn()

        return run

    if n == 1:  # the default's first calls pay for the kernel, which then serves (JIT)
        settle = time.perf_counter()
        while lkk.held_kernel(lk) is None and time.perf_counter() - settle < 120:
            lk.motion(PHI, speed=SPEED)
    rows = {
        "Linkage.motion": chunks(lambda: lk.motion(PHI, speed=SPEED)),
        **(
            {
                "Linkage.motion(kernel=False)": lambda: lk.motion(PHI, speed=SPEED, kernel=False),
                "Linkage.motion(kernel=True)": lambda: lk.motion(PHI, speed=SPEED, kernel=True),
            }
            if n == 1
            else {}
        ),
        "plain numpy, every output": chunks(lambda: plain_numpy(lk, PHI, SPEED)),
        "plain numpy, positions": chunks(lambda: plain_positions(lk, PHI)),
        "kernel via linkage_batch": chunks(
            lambda: lkk.linkage_batch(klk, PHI, SPEED, ws, kernel), kcount
        ),
        "kernel raw": chunks(raw_call(klk, ksize), kcount),
    }
    if n == 1:  # what Linkage.motion(kernel=True) calls
        rows["kernel via one_motion"] = lambda: lkk.one_motion(lk, PHI, SPEED, 0.0, kernel)
    points = lkk.linkage_kernel(lk, outputs="points")  # in blocks of the same size
    psize = min(n, kernel_chunk(points))
    pcount, plk, ws_points = -(-n // psize), designs(name, psize), BatchWorkspace()
    rows["kernel raw, points only"] = chunks(raw_call(plk, psize, points), pcount)
    rows["linkage_batch, points only"] = chunks(
        lambda: lkk.linkage_batch(plk, PHI, SPEED, ws_points, points, outputs="points"), pcount
    )
    for backend, other in list(kernels.items())[1:]:
        ws_other = BatchWorkspace()
        rows[f"kernel via linkage_batch, {backend}"] = chunks(
            lambda other=other, ws_other=ws_other: lkk.linkage_batch(
                klk, PHI, SPEED, ws_other, other
            ),
            kcount,
        )
        rows[f"kernel raw, {backend}"] = chunks(raw_call(klk, ksize, other), kcount)
    if ksize != size:
        rows[f"kernel raw, chunks of {size} designs"] = chunks(raw_call(lk, size))
    if have_pylinkage:
        one, _ = pylinkage_of(designs(name, 1))
        sample = min(n, 10)

        def loop():  # positions, one design after the other (the same linkage each time)
            for _ in range(sample):
                for _ in one.step(iterations=360):
                    pass

        def fast():
            for _ in range(n):
                one.step_fast(iterations=360)

        def kin():
            for _ in range(n):
                one.step_fast_with_kinematics(iterations=360)

        from pylinkage.population import Ensemble

        dims = np.tile(np.asarray(one.get_constraints(), float), (size, 1))
        pos = np.tile(np.asarray(one.get_coords(), float)[None], (size, 1, 1))
        ens = Ensemble(one, dims, pos)
        one.set_input_velocity(one._cranks[0], SPEED)
        scale = n / sample
        label = f" (sample of {sample}, x {scale:g})" if scale != 1 else ""
        rows[f"pylinkage step (loop){label}"] = (loop, scale)
        rows["pylinkage step_fast"] = fast
        rows["pylinkage Ensemble.simulate"] = chunks(lambda: ens.simulate(iterations=360))
        rows["pylinkage step_fast_with_kinematics"] = kin
    return rows


_CHILD = """
import resource, time
def cpu():
    r, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime + c.ru_utime + c.ru_stime
t = time.perf_counter()
import mechsynth.kinematics.linkage_kernels as lkk
from bench_linkage_paths import LINKAGES
lk = LINKAGES[{name!r}]()
t0 = time.perf_counter()
if {backend!r} == "numba":
    import numba
    from mechsynth.kinematics import scalar_ops
    scalar_ops.sqrt(1.0)  # numba's start: its import and first-use set-up (a cached function)
t1 = time.perf_counter()
c1 = cpu()
assert lkk.linkage_kernel(lk).backend == {backend!r}
t2 = time.perf_counter()
print(t0 - t, t1 - t0, t2 - t1, cpu() - c1)
"""

_CHILD_BEHIND = """
import time
import mechsynth.kinematics.linkage_kernels as lkk
from bench_linkage_paths import LINKAGES, PHI, SPEED
lk = LINKAGES[{name!r}]()
t = time.perf_counter()
first = lkk.linkage_kernel(lk, wait=False)
returned = time.perf_counter() - t
served = 0
thread = lkk.kernel_pending(lk)
while thread is not None and thread.is_alive():  # the model serves meanwhile
    lk.motion(PHI, speed=SPEED)
    served += 1
ready = time.perf_counter() - t
assert first is None and lkk.linkage_kernel(lk, wait=False) is not None
print(returned, ready, served)
"""


def fresh_process(script, name, cache, backend):
    """The numbers a new process prints (with its kernel cache in ``cache``, its kernels of
    ``backend``)."""
    env = dict(os.environ, MECHSYNTH_CACHE_DIR=cache, MECHSYNTH_KERNELS=backend)
    here = os.path.dirname(os.path.abspath(__file__))
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [here, env.get("PYTHONPATH", "")]))
    out = subprocess.run([sys.executable, "-c", script.format(name=name, backend=backend)], env=env,
                         capture_output=True, text=True, check=True)  # fmt: skip
    return [float(x) for x in out.stdout.split()]


def compile_times(name, backend):
    """``{what: seconds}`` of the ``backend``'s kernel's first compilation and later loads
    (new processes)."""
    got = {}
    with tempfile.TemporaryDirectory() as cache:
        _, start, got["compile (blocking)"], got["compile CPU"] = fresh_process(
            _CHILD, name, cache, backend
        )
        loads = [fresh_process(_CHILD, name, cache, backend) for _ in range(2)]
        got["numba start"] = [start] + [x[1] for x in loads]
        got["load from the cache"] = [x[2] for x in loads]
    with tempfile.TemporaryDirectory() as cache:
        returned, ready, served = fresh_process(_CHILD_BEHIND, name, cache, backend)
    got["wait=False returns"], got["kernel ready after"] = returned, ready
    got["model motions served meanwhile"] = served
    return got


def backend_kernels(lk) -> dict:
    """``{backend: kernel}`` of ``lk``'s structure for the generators this machine has, the
    default's first."""
    import mechsynth.kinematics.linkage_kernels as lkk

    first = lkk.kernel_backend()
    out = {}
    for backend in (first, *(b for b in ("c", "numba") if b != first)):
        os.environ[lkk.BACKEND_ENV] = backend
        try:
            if lkk.kernel_backend() == backend:
                out[backend] = lkk.linkage_kernel(lk)
        finally:
            os.environ.pop(lkk.BACKEND_ENV)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, nargs="+", default=[1, 100, 10_000])
    ap.add_argument("--linkages", nargs="+", default=list(LINKAGES))
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--compile", action="store_true", help="time compilation and loading")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--show", metavar="FILE", help="print the report saved by --json in FILE")
    args = ap.parse_args(argv)
    if args.show:
        with open(args.show) as f:
            show(json.load(f), args.repeat, args.runs)
        return
    import numba

    numba.set_num_threads(1)
    try:
        import pylinkage

        version = pylinkage.__version__
    except ImportError:
        version = None
        print("pylinkage is not installed (pip install pylinkage==1.3.0): its rows skipped")
    report = {"load average": os.getloadavg()[0], "pylinkage": version, "linkages": {}}
    for name in args.linkages:
        worst, count = check_plain(designs(name, 7), PHI)
        if version:
            pylinkage_check(designs(name, 1))
        entry = report["linkages"][name] = {"plain numpy agrees to": worst, "outputs": count}
        if args.compile:
            for backend in backend_kernels(designs(name, 1)):
                entry[f"compile {backend}"] = compile_times(name, backend)
        for n in args.designs:
            rows = paths(name, n, bool(version))
            got = {}
            rows = {k: fn if isinstance(fn, tuple) else (fn, 1.0) for k, fn in rows.items()}
            for _ in range(args.runs):
                run = timed(rows, args.repeat if n * PHI.size < 1e6 else 1)
                for label, t in run.items():
                    got.setdefault(label, []).append(t)
            entry[n] = got
    report["load average at the end"] = os.getloadavg()[0]
    if args.json:
        print(json.dumps(report, indent=2, default=str))
        return
    show(report, args.repeat, args.runs)


def show(report, repeat, runs):
    """Print a report (of :func:`main`, or read back from its ``--json`` output)."""
    end = report.get("load average at the end")
    load = f"{report['load average']:.1f}" + (f" -> {end:.1f}" if end is not None else "")
    print(
        f"360 angles, one thread, CPU time, median of {repeat} per run, {runs} runs, the "
        f"rows timed in turn (load average {load}: a shared machine; ratios within a run)"
    )
    for name, entry in report["linkages"].items():
        print(f"\n{name}: plain numpy = Linkage.motion to {entry['plain numpy agrees to']:.1e} "
              f"({entry['outputs']} outputs)")  # fmt: skip
        for backend in ("c", "numba"):
            c = entry.get(f"compile {backend}")
            if c is None:
                continue
            print(f"  {backend} kernel, new process and empty cache: compiled in "
                  f"{c['compile (blocking)']:.2f} s wall, {c['compile CPU']:.2f} s CPU "
                  f"(with its compiler's; blocking); with wait=False the call returns in "
                  f"{c['wait=False returns'] * 1e3:.1f} ms and the model serves "
                  f"({c['model motions served meanwhile']:.0f} motions) until the kernel is "
                  f"ready after {c['kernel ready after']:.2f} s")  # fmt: skip
            loads = ", ".join(f"{x:.3f}" for x in c["load from the cache"])
            starts = ", ".join(f"{x:.2f}" for x in c["numba start"])
            tail = f" after numba's start ({starts} s: its import and set-up, once per process)"
            print(f"  {backend} kernel, new process, from the cache: {loads} s"
                  + (tail if backend == "numba" else ""))  # fmt: skip
        for n in (k for k in entry if str(k).isdigit()):
            got = entry[n]
            base = got["Linkage.motion"]
            print(f"  {n} design{'s' if int(n) > 1 else ''}:")
            for label, ts in got.items():
                ratio = " ".join(f"{b / t:6.2f}" for b, t in zip(base, ts))
                times = " ".join(f"{t * 1e3:9.3f}" for t in ts)
                print(f"    {label:38s} ms {times}   speed vs Linkage.motion x {ratio}")
            for what, (slow, fast) in GOALS.items():
                if slow in got and fast in got:
                    ratio = " ".join(f"{a / b:6.2f}" for a, b in zip(got[slow], got[fast]))
                    print(f"    {what:76s} x {ratio}")


#: the ratios the paths are judged by (issue 31): ``{what: (row, row)}``, the first row's time
#: over the second's
GOALS = {
    "Linkage.motion faster than plain numpy, every output (goal >= 1)": (
        "plain numpy, every output",
        "Linkage.motion",
    ),
    "Linkage.motion faster than pylinkage's kinematics (goal >= 1)": (
        "pylinkage step_fast_with_kinematics",
        "Linkage.motion",
    ),
    "Linkage.motion(kernel=False), the model alone, faster than plain numpy, every output": (
        "plain numpy, every output",
        "Linkage.motion(kernel=False)",
    ),
    "Linkage.motion(kernel=True) faster than plain numpy, every output (goal >= 1)": (
        "plain numpy, every output",
        "Linkage.motion(kernel=True)",
    ),
    "Linkage.motion(kernel=True) faster than pylinkage's kinematics (goal >= 1)": (
        "pylinkage step_fast_with_kinematics",
        "Linkage.motion(kernel=True)",
    ),
    "the kernel's time via linkage_batch / raw (goal <= 2)": (
        "kernel via linkage_batch",
        "kernel raw",
    ),
    "the kernel's time via one_motion / raw (goal <= 2)": (
        "kernel via one_motion",
        "kernel raw",
    ),
    "kernel raw faster than pylinkage's kinematics (goal >= 30)": (
        "pylinkage step_fast_with_kinematics",
        "kernel raw",
    ),
    "kernel via linkage_batch faster than pylinkage's kinematics": (
        "pylinkage step_fast_with_kinematics",
        "kernel via linkage_batch",
    ),
    "kernel raw faster than plain numpy, positions (goal >= 1)": (
        "plain numpy, positions",
        "kernel raw",
    ),
    "C kernel raw faster than numba's": ("kernel raw, numba", "kernel raw"),
    "kernel raw, points only, faster than pylinkage's kinematics (goal >= 30)": (
        "pylinkage step_fast_with_kinematics",
        "kernel raw, points only",
    ),
    "kernel raw, points only, faster than plain numpy, positions (goal >= 1)": (
        "plain numpy, positions",
        "kernel raw, points only",
    ),
    "linkage_batch, points only, faster than pylinkage's kinematics (goal >= 30)": (
        "pylinkage step_fast_with_kinematics",
        "linkage_batch, points only",
    ),
    "linkage_batch, points only, faster than plain numpy, positions (goal >= 1)": (
        "plain numpy, positions",
        "linkage_batch, points only",
    ),
    "linkage_batch, points only: its time / the raw points' kernel's": (
        "linkage_batch, points only",
        "kernel raw, points only",
    ),
}


if __name__ == "__main__":
    main()
