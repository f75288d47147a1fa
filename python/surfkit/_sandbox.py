"""A child process that scans mesh files one at a time for ``surfkit.batch``, so that a
file which hangs a reader or crashes it costs its own row only: the parent waits for each
answer at most the time limit, kills the child when it passes it (or finds it dead) and
starts a fresh one for the next file.

Protocol: one JSON line per request on the child's stdin (``{"path", "options"}``), one
JSON line per answer (the row of ``surfkit.batch.scan_one``) on a private copy of its
stdout; anything the child's libraries print goes to its stderr.
"""

from __future__ import annotations

import json
import os
import selectors
import signal
import subprocess
import sys
import time
from typing import Any


class Sandbox:
    """One child scanning process, started on first use and replaced after a failure."""

    def __init__(self) -> None:
        self._child: subprocess.Popen[bytes] | None = None

    @property
    def pid(self) -> int | None:
        """The child's process id (None before the first scan)."""
        return None if self._child is None else self._child.pid

    def _start(self) -> subprocess.Popen[bytes]:
        if self._child is None or self._child.poll() is not None:
            self._child = subprocess.Popen(
                [sys.executable, "-m", "surfkit._sandbox"],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
            )
        return self._child

    def scan(self, path: str, options: dict[str, Any], timeout: float) -> dict[str, Any]:
        """The row of ``path``: the child's, or one with ``error`` when the child took
        longer than ``timeout`` seconds or died."""
        child = self._start()
        assert child.stdin is not None and child.stdout is not None
        start = time.perf_counter()
        try:
            child.stdin.write((json.dumps({"path": path, "options": options}) + "\n").encode())
            child.stdin.flush()
        except BrokenPipeError:
            return self._died(child, path, start)
        with selectors.DefaultSelector() as waiting:
            waiting.register(child.stdout, selectors.EVENT_READ)
            ready = waiting.select(timeout)
        if not ready:
            child.kill()
            child.wait()
            self._child = None
            return _error_row(path, f"timed out after {timeout:g} s (the scan was stopped)", start)
        line = child.stdout.readline()
        if not line:
            return self._died(child, path, start)
        return json.loads(line)

    def _died(self, child: subprocess.Popen[bytes], path: str, start: float) -> dict[str, Any]:
        code = child.wait()
        self._child = None
        how = (
            f"killed by signal {-code} ({signal.Signals(-code).name})"
            if code < 0
            else f"exit status {code}"
        )
        return _error_row(path, f"the scanning process died ({how})", start)

    def close(self) -> None:
        """Ends the child (it also ends when the parent closes its stdin)."""
        if self._child is not None and self._child.poll() is None:
            assert self._child.stdin is not None
            self._child.stdin.close()
            self._child.wait()
        self._child = None

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # at interpreter exit the pipes may be gone already
            pass


def _error_row(path: str, message: str, start: float) -> dict[str, Any]:
    from surfkit.batch import error_row

    return error_row(path, message, time.perf_counter() - start)


def _serve() -> None:
    """The child's loop: a request per line in, a row per line out."""
    answers = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)  # whatever a library prints must not mix with the answers
    from surfkit.batch import scan_one

    for request in sys.stdin:
        job = json.loads(request)
        row = scan_one(job["path"], job["options"])
        answers.write(json.dumps(row) + "\n")
        answers.flush()


if __name__ == "__main__":
    _serve()
