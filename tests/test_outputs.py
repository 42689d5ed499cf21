"""Outputs that survive: every file is written to a temporary file beside it and renamed when
complete, so an interrupted or failed write never leaves a truncated file nor destroys the
previous one; each run lists its files with SHA-256 in manifest.json."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import fileio

ROOT = Path(__file__).resolve().parents[1]
DESIGN = ROOT / "examples" / "design_slider_crank.toml"


def _leftovers(folder):
    return [p.name for p in Path(folder).iterdir() if ".part" in p.name]


@pytest.mark.parametrize("exc", [KeyboardInterrupt, RuntimeError])
def test_an_interrupted_write_keeps_the_previous_file(tmp_path, exc):
    target = tmp_path / "table.csv"
    fileio.write_text(target, "a,b\n1,2\n")
    with pytest.raises(exc):
        with fileio.atomic(target) as fh:
            fh.write("a,b\n3,")
            raise exc()
    assert target.read_text() == "a,b\n1,2\n"
    assert _leftovers(tmp_path) == []


def test_every_writer_goes_through_the_atomic_helper(tmp_path, monkeypatch):
    """A figure, an NPZ, a CSV of a motion and a GIF: each failing half-way leaves nothing."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    png = fileio.save_figure(fig, tmp_path / "f.png", dpi=50)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    npz = fileio.save_npz(tmp_path / "a.npz", x=np.arange(5.0))
    assert np.load(npz)["x"].tolist() == [0, 1, 2, 3, 4]
    before = png.read_bytes()

    def broken(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(fig, "savefig", broken)
    with pytest.raises(KeyboardInterrupt):
        fileio.save_figure(fig, png)
    assert png.read_bytes() == before and _leftovers(tmp_path) == []
    plt.close(fig)

    sc = ms.SliderCrank(crank=0.07, rod=0.24)
    csv = sc.motion(ms.cycle(8)).to_csv(tmp_path / "m.csv")
    assert len(Path(csv).read_text().splitlines()) == 9
    anim = sc.animate(frames=4, dpi=30)
    gif = anim.save(tmp_path / "m.gif")
    assert gif.read_bytes()[:6] == b"GIF89a" and _leftovers(tmp_path) == []


def test_output_folder_checks(tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    for bad, match in (("", "non-empty"), (f, "existing file"), (f / "sub", "which is a file")):
        with pytest.raises(ms.MechanismError, match=match):
            fileio.output_dir(bad)
    assert fileio.output_dir(tmp_path / "new" / "deep").is_dir()


def _env():
    return dict(os.environ, PYTHONPATH=str(ROOT))


def _animate(out, frames=60):
    return [sys.executable, "-m", "mechsynth", "animate", str(DESIGN), "--out", str(out),
            "--frames", str(frames), "--quiet"]  # fmt: skip


def test_manifest_lists_the_files_with_their_checksums(tmp_path):
    out = tmp_path / "run"
    r = subprocess.run(_animate(out, 8), capture_output=True, text=True, env=_env(), cwd=ROOT)
    assert r.returncode == 0, r.stderr
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["version"] == ms.__version__
    assert manifest["options"]["frames"] == 8
    names = {e["file"] for e in manifest["files"]}
    assert names == {"design_slider_crank.png", "design_slider_crank.gif"}
    for e in manifest["files"]:
        assert fileio.sha256(out / e["file"]) == e["sha256"]
        assert (out / e["file"]).stat().st_size == e["bytes"]


def _interrupt_run(tmp_path, delays, sig=signal.SIGINT):
    out = tmp_path / "run"
    r = subprocess.run(_animate(out), capture_output=True, text=True, env=_env(), cwd=ROOT)
    assert r.returncode == 0, r.stderr
    complete = {p.name: p.read_bytes() for p in out.iterdir()}
    for delay in delays:
        proc = subprocess.Popen(
            _animate(out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
            env=_env(), cwd=ROOT,
        )  # fmt: skip
        # interrupt while a file is being written (a temporary file exists), ``delay`` s
        # after the first one appears
        t0 = time.monotonic()
        while not _leftovers(out) and proc.poll() is None and time.monotonic() - t0 < 300:
            time.sleep(0.005)
        time.sleep(delay)
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=300)
        code, word = (130, "interrupted") if sig == signal.SIGINT else (143, "terminated")
        assert proc.returncode in (0, code), err
        if proc.returncode == code:
            assert "Traceback" not in err and word in err
            assert len(err.strip().splitlines()) == 1, err
        # every file is the previous complete one or a complete new one (the output is
        # deterministic: the same bytes); nothing half-written is left
        assert _leftovers(out) == []
        for p in out.iterdir():
            assert p.read_bytes() == complete[p.name] or p.name == "manifest.json", p.name
        # the manifest describes exactly the files on disk, whatever the run had replaced
        manifest = json.loads((out / "manifest.json").read_text())
        listed = {e["file"]: e["sha256"] for e in manifest["files"]}
        assert set(listed) == {p.name for p in out.iterdir()} - {"manifest.json"}
        for name, digest in listed.items():
            assert fileio.sha256(out / name) == digest, name


@pytest.mark.skipif(os.name != "posix", reason="SIGINT to a child process")
def test_ctrl_c_never_leaves_a_truncated_or_destroyed_file(tmp_path):
    _interrupt_run(tmp_path, [0.0])


@pytest.mark.skipif(os.name != "posix", reason="SIGTERM to a child process")
def test_sigterm_ends_a_run_as_ctrl_c_does(tmp_path):
    _interrupt_run(tmp_path, [0.0, 0.05], sig=signal.SIGTERM)


@pytest.mark.slow
@pytest.mark.skipif(os.name != "posix", reason="SIGINT to a child process")
def test_ctrl_c_at_many_moments(tmp_path):
    _interrupt_run(tmp_path, [0.0, 0.01, 0.05, 0.1, 0.2, 0.5, 1.0])


@pytest.mark.parametrize("bad", ["", "   ", "."])
def test_a_writer_without_a_file_name_says_so(tmp_path, monkeypatch, bad):
    monkeypatch.chdir(tmp_path)
    m = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2).motion(ms.cycle(8))
    with pytest.raises(ms.MechanismError, match="give a file name"):
        m.to_csv(bad)  # was an OSError about a '.part' file renamed over '.'
    assert list(tmp_path.iterdir()) == []  # nothing left behind


def test_a_writer_refuses_a_folder_and_a_non_path(tmp_path):
    m = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2).motion(ms.cycle(8))
    with pytest.raises(ms.MechanismError, match="it is a folder; give a file name"):
        m.to_csv(tmp_path)
    with pytest.raises(ms.MechanismError, match="a file name must be a string or a path, got 3"):
        m.to_csv(3)
    assert list(tmp_path.iterdir()) == []


def test_an_unfinished_run_leaves_a_manifest_true_to_the_files(tmp_path, monkeypatch):
    """A second run into the same folder, stopped after replacing a file, used to leave the
    first run's manifest describing content that was no longer there."""
    monkeypatch.setattr(fileio, "WRITTEN", [])
    fileio.write_text(tmp_path / "a.csv", "first\n")
    fileio.write_text(tmp_path / "b.csv", "first\n")
    fileio.write_manifest(tmp_path, [tmp_path / "a.csv", tmp_path / "b.csv"], command="one")
    fileio.WRITTEN.clear()
    # nothing replaced (a bad input refused before any work): the manifest stays as it was
    before = (tmp_path / "manifest.json").read_bytes()
    assert fileio.settle_manifest(tmp_path, command="two") is None
    assert (tmp_path / "manifest.json").read_bytes() == before
    # the second run replaced a.csv and wrote c.csv, then was stopped
    fileio.write_text(tmp_path / "a.csv", "second\n")
    fileio.write_text(tmp_path / "c.csv", "second\n")
    fileio.settle_manifest(tmp_path, command="two", status="interrupted")
    manifest = json.loads((tmp_path / "manifest.json").read_text())
    assert manifest["status"] == "interrupted" and manifest["command"] == "two"
    listed = {e["file"]: e["sha256"] for e in manifest["files"]}
    assert set(listed) == {"a.csv", "b.csv", "c.csv"}
    for name, digest in listed.items():
        assert fileio.sha256(tmp_path / name) == digest


@pytest.mark.slow
def test_interrupted_at_every_write_of_a_run(tmp_path, monkeypatch, capsys):
    """A second run into a complete --out, stopped by Ctrl-C just before each of its writes in
    turn (and after its last): exit 130, no temporary file left, every file complete (the first
    run's or the second's), and manifest.json true to the files on disk."""
    from mechsynth.cli import main

    problem = str(ROOT / "examples" / "optimize_slider_crank.toml")
    out = tmp_path / "run"
    first = ["optimize", problem, "--starts", "1", "--out", str(out), "--quiet"]
    assert main(first) == 0
    capsys.readouterr()
    # the second run differs (another seed and speed of the bar): its files change
    second = ["optimize", problem, "--starts", "2", "--seed", "3", "--out", str(out), "--quiet"]
    real_replace = os.replace
    writes = []

    def counting(src, dst):
        writes.append(dst)
        return real_replace(src, dst)

    monkeypatch.setattr(os, "replace", counting)
    assert main(second) == 0
    n = len(writes)
    assert n >= 4  # result.json, report.txt, optimum.png, manifest.json
    capsys.readouterr()
    for k in range(n + 1):
        calls = []

        def stop_at_k(src, dst, k=k, calls=calls):
            calls.append(dst)
            if len(calls) == k + 1:
                raise KeyboardInterrupt
            return real_replace(src, dst)

        monkeypatch.setattr(os, "replace", stop_at_k)
        rc = main(second)
        err = capsys.readouterr().err
        assert rc in (0, 130), (k, err)
        if k < n:
            assert rc == 130 and "interrupted" in err and "Traceback" not in err, (k, err)
        assert _leftovers(out) == [], k
        manifest = json.loads((out / "manifest.json").read_text())
        listed = {e["file"]: e["sha256"] for e in manifest["files"]}
        on_disk = {p.name for p in out.iterdir()} - {"manifest.json"}
        assert set(listed) == on_disk, (k, listed, on_disk)
        for name, digest in listed.items():
            assert fileio.sha256(out / name) == digest, (k, name)


@pytest.mark.parametrize("sig, code, word", [(signal.SIGTERM, 143, "terminated"),
                                             (signal.SIGINT, 130, "interrupted")])
def test_an_interrupt_swallowed_by_a_finalizer_prints_no_traceback(monkeypatch, capsys, sig,
                                                                   code, word):
    """A signal that lands in a weakref callback during garbage collection (matplotlib's
    transforms have them) raises KeyboardInterrupt there, where Python swallows it and prints
    it with a traceback; the run goes on and still ends as interrupted, in one line."""
    import gc
    import weakref

    from mechsynth import cli

    class Thing:
        pass

    def run(argv, debug):
        cli._INTERRUPTED.append(sig)  # what the handler records before it raises

        def finalizer(_):
            raise KeyboardInterrupt

        t = Thing()
        ref = weakref.ref(t, finalizer)  # noqa: F841  (kept until t goes)
        del t
        gc.collect()
        return 0

    monkeypatch.setattr(cli, "_run", run)
    monkeypatch.setattr(sys, "unraisablehook", sys.__unraisablehook__)  # not pytest's own
    before = sys.unraisablehook
    assert cli.main(["animate", "x.toml"]) == code
    err = capsys.readouterr().err
    assert "Traceback" not in err and word in err and len(err.strip().splitlines()) == 1
    assert sys.unraisablehook is before
