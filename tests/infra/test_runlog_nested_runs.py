"""Inside a nested run (a command that runs another, e.g. a benchmark case inside ``benchmark-gap``), the
messages collected and merged into a JSON are the inner run's, and the outer run's are its own again after it."""
from __future__ import annotations

from chainid.infra import runlog


def test_collected_and_merged_messages_belong_to_the_innermost_run():
    with runlog.collecting("outer"):
        runlog.warn("outer message")
        with runlog.collecting("inner"):
            runlog.warn("inner message")
            assert runlog.collected() == ["inner message"]
            assert runlog.merge_warnings({"a": 1}) == {"a": 1, "warnings": ["inner message"]}
        assert runlog.collected() == ["outer message"]
    assert runlog.collected() == []
