"""Files in and out, safely: every input file is read and every output file written here.

Reading
    :func:`read_toml` and :func:`read_text` accept only a regular file of reasonable size that
    is UTF-8 text; a directory, a device (``/dev/urandom``), a missing file, a binary file or
    malformed TOML is a :class:`~mechsynth.errors.MechanismError` in one line naming the path.

Writing
    :func:`atomic` writes to a temporary file in the destination's folder and renames it over
    the destination only when the writing finished (``os.replace``, atomic on POSIX and
    Windows): an interrupted, failed or concurrent run never leaves a truncated file and never
    destroys a previous complete one. :func:`write_text`, :func:`write_bytes`,
    :func:`save_figure`, :func:`save_npz` and :func:`write_csv` are built on it, and
    :func:`output_dir` checks an ``--out`` folder before anything is computed.
    :func:`write_manifest` lists a run's files with their SHA-256, the options and the package
    version in ``manifest.json``.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import tempfile
import tomllib
from pathlib import Path

from .errors import MechanismError

__all__ = [
    "MAX_INPUT_BYTES",
    "read_toml",
    "read_text",
    "output_dir",
    "atomic",
    "write_text",
    "write_bytes",
    "write_csv",
    "save_figure",
    "save_npz",
    "sha256",
    "write_manifest",
]

#: every file written completely (renamed into place) since the list was last cleared: the
#: command line clears it when a run starts, so an interrupted run knows what it replaced
WRITTEN: list[Path] = []

#: largest input file read (bytes): problem, design and unit files and cards are small
MAX_INPUT_BYTES = 64 * 2**20


# ------------------------------------------------------------------------------- reading
def _regular_file(source, what: str) -> Path:
    if isinstance(source, (bytes, bytearray)) or not isinstance(source, (str, os.PathLike)):
        raise MechanismError(f"{what} must be a path, got {source!r}")
    if str(source) == "":
        raise MechanismError(f"{what}: the path is empty")
    path = Path(source)
    if not path.exists():
        raise MechanismError(f"{what} {path} not found")
    if path.is_dir():
        raise MechanismError(f"{what} {path} is a directory, not a file")
    if not path.is_file():
        raise MechanismError(f"{what} {path} is not a regular file (a device or a pipe)")
    size = path.stat().st_size
    if size > MAX_INPUT_BYTES:
        raise MechanismError(
            f"{what} {path} is {size / 2**20:.0f} MiB: larger than any {what} should be "
            f"({MAX_INPUT_BYTES // 2**20} MiB at most)"
        )
    return path


def read_text(source, what: str = "file") -> tuple[str, Path]:
    """``(text, path)`` of a UTF-8 text file, or a one-line MechanismError."""
    path = _regular_file(source, what)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise MechanismError(f"{what} {path} cannot be read: {exc.strerror or exc}") from None
    if b"\x00" in raw:
        raise MechanismError(f"{what} {path} is a binary file, not text")
    try:
        return raw.decode("utf-8-sig"), path
    except UnicodeDecodeError as exc:
        raise MechanismError(
            f"{what} {path} is not UTF-8 text (a binary file? byte {exc.start} is "
            f"{raw[exc.start : exc.start + 1]!r})"
        ) from None


def read_toml(source, what: str = "file") -> tuple[dict, Path | None]:
    """``(data, path)`` of a TOML file (``path`` None when ``source`` is a dict already)."""
    if isinstance(source, dict):
        return source, None
    text, path = read_text(source, what)
    try:
        return tomllib.loads(text), path
    except tomllib.TOMLDecodeError as exc:
        raise MechanismError(f"{path}: not valid TOML ({exc})") from None
    except RecursionError:
        raise MechanismError(f"{path}: not valid TOML (nested too deeply)") from None


# ------------------------------------------------------------------------------- writing
def output_dir(out, create: bool = True) -> Path | None:
    """The ``--out`` folder as a Path (None for None), checked before any work: not empty, not
    an existing file, not under a file, writable. Created when ``create``."""
    if out is None:
        return None
    if not isinstance(out, (str, os.PathLike)) or str(out).strip() == "":
        raise MechanismError(f"the output folder must be a non-empty path, got {out!r}")
    path = Path(out)
    if path.exists() and not path.is_dir():
        raise MechanismError(f"output folder {path} is an existing file, not a folder")
    for parent in path.parents:
        if parent.exists():
            if not parent.is_dir():
                raise MechanismError(f"output folder {path} is under {parent}, which is a file")
            break
    if create:
        try:
            path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise MechanismError(
                f"output folder {path} cannot be created: {exc.strerror or exc}"
            ) from None
        if not os.access(path, os.W_OK | os.X_OK):
            raise MechanismError(f"output folder {path} is not writable")
    return path


def _target(path) -> Path:
    """``path`` as a file to write: a name that is not empty and not an existing folder."""
    if not isinstance(path, (str, os.PathLike)):
        raise MechanismError(f"a file name must be a string or a path, got {path!r}")
    if isinstance(path, str) and not path.strip():
        raise MechanismError(f"cannot write {path!r}: give a file name")
    path = Path(path)
    if not path.name:
        raise MechanismError(f"cannot write {str(path)!r}: give a file name")
    if path.is_dir():
        raise MechanismError(f"cannot write {path}: it is a folder; give a file name")
    return path


@contextlib.contextmanager
def atomic(path, mode: str = "w", **open_kwargs):
    """Open a temporary file beside ``path`` for writing and move it over ``path`` when the
    block ends without an exception; on any exception (Ctrl-C included) the temporary file is
    removed and ``path`` keeps its previous content.

    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with atomic(d / "x.txt") as fh:
    ...     _ = fh.write("done")
    >>> (d / "x.txt").read_text()
    'done'
    """
    path = _target(path)
    folder = path.parent if str(path.parent) else Path(".")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=folder)
    except OSError as exc:
        raise MechanismError(f"cannot write {path}: {exc.strerror or exc}") from None
    try:
        if "b" in mode:
            fh = os.fdopen(fd, mode)
        else:
            open_kwargs.setdefault("encoding", "utf-8")
            fh = os.fdopen(fd, mode, **open_kwargs)
        with fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
        WRITTEN.append(path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


@contextlib.contextmanager
def atomic_path(path):
    """A temporary path with ``path``'s own name, in a temporary folder beside it, for writers
    that take a file name (matplotlib's ``savefig``, animation writers): moved over ``path``
    when the block ends without an exception, removed otherwise."""
    import shutil

    path = _target(path)
    folder = path.parent if str(path.parent) else Path(".")
    try:
        tmpdir = tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".part", dir=folder)
    except OSError as exc:
        raise MechanismError(f"cannot write {path}: {exc.strerror or exc}") from None
    tmp = Path(tmpdir) / path.name
    try:
        yield tmp
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
        WRITTEN.append(path)
    finally:
        shutil.rmtree(tmpdir, ignore_errors=True)


def write_text(path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically; returns the path."""
    with atomic(path, "w", newline="") as fh:
        fh.write(text)
    return Path(path)


def write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; returns the path."""
    with atomic(path, "wb") as fh:
        fh.write(data)
    return Path(path)


def write_csv(path, header, rows) -> Path:
    """A CSV file (``header``: column names; ``rows``: sequences) written atomically."""
    import csv

    with atomic(path, "w", newline="") as fh:
        w = csv.writer(fh)
        if header is not None:
            w.writerow(header)
        w.writerows(rows)
    return Path(path)


def save_figure(fig, path, **kwargs) -> Path:
    """``fig.savefig`` into ``path`` atomically (the format from the suffix)."""
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, **kwargs)
    return path


def save_npz(path, **arrays) -> Path:
    """``numpy.savez_compressed`` into ``path`` atomically."""
    import numpy as np

    with atomic(path, "wb") as fh:
        np.savez_compressed(fh, **arrays)
    return Path(path)


def sha256(path) -> str:
    """SHA-256 hex digest of a file's content."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def write_manifest(out, files, options=None, command=None) -> Path:
    """``manifest.json`` in ``out``: every file of the run (relative name, bytes, SHA-256),
    the options, the command and the package version. Written last and atomically, so a
    manifest always describes complete files."""
    from . import __version__

    out = Path(out)
    entries = []
    for f in files:
        f = Path(f)
        if not f.is_file():
            continue
        try:
            name = str(f.resolve().relative_to(out.resolve()))
        except ValueError:
            name = str(f)
        entries.append({"file": name, "bytes": f.stat().st_size, "sha256": sha256(f)})
    data = {
        "package": "mechsynth",
        "version": __version__,
        "command": command,
        "options": options or {},
        "files": entries,
    }
    return write_text(out / "manifest.json", json.dumps(data, indent=2, default=str) + "\n")


def settle_manifest(out, options=None, command=None, status="interrupted") -> Path | None:
    """After a run into ``out`` that did not finish (``status``), make ``manifest.json``
    describe the files as they are: the previous run's files (hashed again: some were
    replaced) and those this run completed (:data:`WRITTEN`), with the status. Nothing is
    done when there is no manifest or when the run changed none of its files (a bad input
    refused before any work keeps the previous run's manifest as it was)."""
    from . import __version__

    out = Path(out)
    manifest = out / "manifest.json"
    if not manifest.is_file():
        return None
    try:
        old = json.loads(manifest.read_text(encoding="utf-8"))
        listed = [e["file"] for e in old.get("files", [])]
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        old, listed = {}, []
    root = out.resolve()
    mine = []
    for f in WRITTEN:
        try:
            name = str(Path(f).resolve().relative_to(root))
        except ValueError:
            continue  # written elsewhere
        if name != "manifest.json":
            mine.append(name)
    if not mine:
        return None
    entries = []
    for name in dict.fromkeys(listed + mine):  # in order, once
        f = out / name
        if f.is_file():
            entries.append({"file": name, "bytes": f.stat().st_size, "sha256": sha256(f)})
    data = {
        "package": "mechsynth",
        "version": __version__,
        "command": command,
        "options": options or {},
        "status": status,
        "note": "the run did not finish: the files of the previous run it had replaced and "
        "those it completed are listed as they are on disk",
        "files": entries,
    }
    return write_text(manifest, json.dumps(data, indent=2, default=str) + "\n")
