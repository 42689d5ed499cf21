"""Fixed refinement slots that run out: angles closer than ``solvers._SAME_ANGLE`` (peaks at
one dead centre, each found to the 1-D search's tolerance) take one slot before the program
grows, and their rows' multipliers add up in it (``Transcription.merge_slots``)."""

import numpy as np
import pytest
from test_refinement_slots import _minimized  # the same coarse-grid problem

from mechsynth.synthesis import solvers as SV
from mechsynth.synthesis import transcription as T


def test_merge_slots_moves_each_rows_multiplier_and_adds_the_merged_ones():
    tr = _minimized(slots=4)._transcription()
    n_base = tr.n_base
    rng = np.random.default_rng(3)
    lam = rng.random(tr.lbg.size) + 1.0
    where = np.array([0, 1, 0, 2])  # slot 2 merged into 0, slot 3 moved to 2
    out = tr.merge_slots(lam, where)
    keys = tr.row_keys()
    row = {k: i for i, k in enumerate(keys)}
    checked = 0
    for i, (kind, branch, slot) in enumerate(keys):
        if slot < 0 or slot < n_base:  # not a per-angle row, or a base angle's
            assert out[i] == lam[i]
            continue
        at = {s: lam[row[(kind, branch, n_base + s)]] for s in range(4)}
        want = {0: at[0] + at[2], 1: at[1], 2: at[3], 3: 0.0}[slot - n_base]
        assert out[i] == pytest.approx(want, rel=1e-15)
        checked += 1
    assert checked == 4 * len({(k, b) for k, b, s in keys if s >= 0})
    # the sum over each branch's rows is kept
    assert out.sum() == pytest.approx(lam.sum(), rel=1e-14)


def test_angles_at_one_dead_centre_share_a_slot_before_the_program_grows():
    prob = _minimized(slots=4)
    T.clear_cache()
    cert = SV._Certifier(prob, "ipopt", None, 1e-9, 12, 2048)
    cert.rounds = 8  # past the rounds that move angles: every angle found is added
    a, b = 1.2345, 4.0
    cert._add([(a, 0), (b, 1), (a + 3e-8, 1)])  # within _SAME_ANGLE: a slot each still
    assert len(cert.extra) == 3 and cert.merged is None
    rebuilt = cert._add([(2.0, 0), (3.0, 1)])  # five angles in four slots: merged, not grown
    assert not rebuilt and cert.tr.n_extra == 4 and T.cache_info()["structures"] == 1
    assert cert.extra == [a, b, 2.0, 3.0]
    assert cert.owners == [{0, 1}, {1}, {0}, {1}]
    assert list(cert.merged) == [0, 1, 0, 2, 3]
    # apart by more than _SAME_ANGLE: the program grows (twice its slots) as before
    rebuilt = cert._add([(a + 2 * SV._SAME_ANGLE, 0)])
    assert rebuilt and cert.tr.n_extra == 8 and len(cert.extra) == 5
