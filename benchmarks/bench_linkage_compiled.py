"""Would a compiled kernel pay for a general linkage? The measurement behind the verdict in
docs/linkages.md ("Speed"), reproducible (not run by the tests).

Paper 001's six-link (crank, RRR, a point on the rocker, RRP) is written as one chain of calls to
the blocks of ``mechsynth.kinematics.blocks`` -- the functions ``Linkage.motion`` runs for its
groups -- and compiled the way ``mechsynth.kinematics.compiled`` compiles the four-bar and the
slider-crank (their own code with ``ops`` rebound to ``scalar_ops``, a serial loop over angles
inside a parallel loop over designs). The script checks the kernel against ``Linkage.motion`` to
1e-12, then reports its compilation time and its throughput against the numpy model's on the
same batch (design-angle evaluations per second; one thread unless ``--threads``).

Run: python benchmarks/bench_linkage_compiled.py [--designs N] [--threads T]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import mechsynth as ms
from mechsynth.kinematics import blocks, scalar_ops
from mechsynth.kinematics.compiled import _twin
from mechsynth.kinematics.tracks import PointJet


def six_link():
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05)
        .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57)))
    )


def six_link_chain(c, s, oa, ab, db, dx, dy, k_along, k_left, kn, gx, gy, ga):
    """The six-link's groups in solving order, as the linkage solves them: the crank pin A, the
    RRR dyad A-B-D, K on the rocker's frame (origin D, axis D -> B), the RRP dyad K-N."""
    a = crank_pin(c, s, oa)  # noqa: F821 - bound by _twin
    zero = 0.0 * a.x
    d = PointJet(dx + zero, dy + zero, zero, zero, zero, zero)
    _, _, rocker = dyad_rrr(a, d, ab, db, 1)  # noqa: F821
    k = coupler_point(d, rocker, k_along, k_left)  # noqa: F821
    _, slide, _ = dyad_rrp(k, kn, gx, gy, ga, 1)  # noqa: F821
    return slide


def compile_kernel():
    import numba

    jit = numba.njit(error_model="numpy", inline="always")
    ns = {
        "ops": scalar_ops,
        "_check_nonnegative": scalar_ops.check_nonnegative,
        "_check_toggle": scalar_ops.check_toggle,
    }
    for f in (
        blocks.link_angle,
        blocks.crank_pin,
        blocks.dyad_rrr,
        blocks._rrp_slide,
        blocks.dyad_rrp,
        blocks.coupler_point,
    ):
        fn = getattr(f, "__wrapped__", f)
        ns[fn.__name__] = _twin(fn, ns, jit)
    chain = _twin(six_link_chain, ns, jit)

    @numba.njit(error_model="numpy")
    def row(p, cphi, sphi, out, i):
        for j in range(cphi.shape[0]):
            sl = chain(
                cphi[j], sphi[j], p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10]
            )
            out[0, i, j], out[1, i, j], out[2, i, j] = sl

    @numba.njit(error_model="numpy", parallel=True)
    def kernel(P, cphi, sphi, out):
        for i in numba.prange(P.shape[0]):
            row(P[i], cphi, sphi, out, i)

    return kernel


NAMES = ("OA", "AB", "DB", "D_x", "D_y", "K_along", "K_left", "KN", "N_guide_x", "N_guide_y",
         "N_guide_angle")  # fmt: skip


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=10_000)
    ap.add_argument("--angles", type=int, default=360)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    import numba

    numba.set_num_threads(args.threads)
    six = six_link()
    phi = ms.cycle(args.angles)
    n = args.designs
    rng = np.random.default_rng(0)
    P = np.tile([six.parameters[k] for k in NAMES], (n, 1))
    P[:, 2] = rng.uniform(0.07, 0.09, n)  # the rocker DB varies over the batch

    t = time.perf_counter()
    kernel = compile_kernel()
    out = np.empty((3, 2, args.angles))
    kernel(P[:2], np.cos(phi), np.sin(phi), out)
    t_compile = time.perf_counter() - t
    print(f"compilation: {t_compile:.1f} s (one linkage structure, in this process)")

    # the kernel is the model: agree with Linkage.motion to 1e-12
    ref = six(DB=P[:50, 2:3]).motion(phi).sliders["N"]
    out = np.empty((3, 50, args.angles))
    kernel(P[:50], np.cos(phi), np.sin(phi), out)
    for k, f in enumerate(("position", "velocity", "acceleration")):
        r = np.asarray(getattr(ref, f))
        err = np.max(np.abs(out[k] - r)) / max(1.0, np.max(np.abs(r)))
        assert err < 1e-12, (f, err)
    print("kernel = Linkage.motion to 1e-12 (slider N: position, velocity, acceleration)")

    def compiled():
        o = np.empty((3, n, args.angles))
        kernel(P, np.cos(phi), np.sin(phi), o)
        return o

    chunk = max(1, 2**16 // args.angles)

    def numpy_model():
        for i in range(0, n, chunk):
            six(DB=P[i : i + chunk, 2:3]).motion(phi).sliders["N"]

    def timed(fn):
        times = []
        for _ in range(args.repeat):
            t = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t)
        return statistics.median(times)

    tc, tn = timed(compiled), timed(numpy_model)
    evals = n * args.angles
    print(
        f"{n} designs x {args.angles} angles: compiled {evals / tc:.3g} evaluations/s "
        f"({args.threads} thread(s)), numpy model {evals / tn:.3g} (x {tn / tc:.2g})"
    )
    gain = evals / tc - evals / tn
    breakeven = t_compile / (1.0 / (evals / tn) - 1.0 / (evals / tc)) if gain > 0 else np.inf
    print(f"break-even: {breakeven:.3g} design-angle evaluations of this structure per process")


if __name__ == "__main__":
    main()
