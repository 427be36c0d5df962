"""A decimal comma goes with any delimiter but the comma itself (the one pair a reader cannot tell apart)."""
from __future__ import annotations

import pytest

from chainid.records.readerspec import ReaderSpec


@pytest.mark.parametrize("delimiter", ["tab", ";", "|", "whitespace"])
def test_a_decimal_comma_with_another_delimiter_is_accepted(delimiter):
    spec = ReaderSpec(decimal=",", delimiter=delimiter)
    assert spec.decimal == ","


def test_a_decimal_comma_with_a_comma_delimiter_is_refused():
    with pytest.raises(ValueError, match="decimal = ',' needs another delimiter than ','"):
        ReaderSpec(decimal=",", delimiter=",")
