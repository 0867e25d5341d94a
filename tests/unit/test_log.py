"""The rank-tagged log writes to the sys.stderr of the moment (pytest's capsys, a tool's redirect)."""

import io
import sys

from pice.log import configure


def test_log_follows_the_current_stderr(monkeypatch):
    log = configure()
    for _ in range(2):  # a second swap must be followed too, not only the stream at set-up
        buf = io.StringIO()
        monkeypatch.setattr(sys, "stderr", buf)
        log.warning("layout solved")
        assert buf.getvalue() == "pice [rank 0] WARNING: layout solved\n"
