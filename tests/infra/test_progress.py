"""Progress bars (chainid.infra.progress) only on an open terminal."""
from __future__ import annotations

import io
import sys

import pytest

from chainid.infra.progress import progress_enabled, progress_iter


class _Tty(io.StringIO):
    def isatty(self):
        return True


def test_progress_only_on_an_open_terminal(monkeypatch):
    monkeypatch.setattr(sys, "stderr", _Tty())
    assert progress_enabled() is True and progress_enabled(quiet=True) is False
    closed = io.StringIO()
    closed.close()
    with pytest.raises(ValueError):
        closed.isatty()  # on a closed file: ValueError
    monkeypatch.setattr(sys, "stderr", closed)
    assert progress_enabled() is False
    assert list(progress_iter(iter([3, 1, 2]), desc="x")) == [3, 1, 2]
    monkeypatch.setattr(sys, "stderr", object())  # no isatty at all
    assert progress_enabled() is False
    monkeypatch.setattr(sys, "stderr", io.StringIO())  # a pipe or a log
    assert progress_enabled() is False
