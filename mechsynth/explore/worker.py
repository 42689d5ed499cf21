"""The explorer's searches in processes of their own: the Optimize tab's solve, the Synthesis
tab's path search and min-max stage (the page's server stays free while they run)."""

from __future__ import annotations

import multiprocessing
import queue
import time


class Worker:
    """A search in a process of its own: started, polled for its messages, cancelled, and
    reaped when it ends (no zombie process stays behind)."""

    def __init__(self):
        self.proc = None
        self.queue = None
        self.t0 = 0.0
        self.stage = ""
        self.job = None

    @property
    def running(self) -> bool:
        return self.proc is not None

    def start(self, target, job, stage: str = "starting"):
        """Run ``target(job, queue)`` in a new (spawned) process."""
        ctx = multiprocessing.get_context("spawn")
        self.queue = ctx.Queue()
        self.proc = ctx.Process(target=target, args=(job, self.queue), daemon=True)
        self.proc.start()
        self.job, self.t0, self.stage = job, time.perf_counter(), stage

    def end(self, kill: bool = False):
        """Stop (``kill``: terminate first) and reap the process; close its queue."""
        proc, self.proc = self.proc, None
        if proc is not None:
            if kill:
                proc.terminate()
            proc.join(timeout=5)
            if proc.is_alive():
                proc.kill()
                proc.join(timeout=5)
            if not proc.is_alive():
                proc.close()
        if self.queue is not None:
            self.queue.close()
        self.queue = None

    def messages(self) -> list:
        """The messages posted so far; ``("error", ...)`` when the process ended silently."""
        out = []
        while self.queue is not None:
            try:
                out.append(self.queue.get_nowait())
            except (queue.Empty, OSError, ValueError):
                break
        if (
            not any(m[0] in ("done", "error") for m in out)
            and self.proc is not None
            and not self.proc.is_alive()
            and self.queue is not None
            and self.queue.empty()
        ):
            out.append(("error", "the process ended without a result"))
        return out

    @property
    def elapsed(self) -> float:
        return time.perf_counter() - self.t0
