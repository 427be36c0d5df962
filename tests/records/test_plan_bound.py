"""A simulation plan is bounded: more than MAX_PLAN_TESTS (10 000) tests is one error naming the count and the
limit, raised while reading (no hang on a 10⁶-line plan); a plan at the limit is read whole, repeated ids
refused by name."""
from __future__ import annotations

import pytest

from chainid.cli import main
from chainid.records.simulate import MAX_PLAN_TESTS, TestSpec, read_plan, simulate


def _plan(path, n, repeat_last=False):
    rows = [f"{i},{1 + i % 7},2.2,0.25" for i in range(n)]
    if repeat_last:
        rows.append(f"{n - 1},1,2.2,0.25")
    path.write_text("test,omega,x0,A\n" + "\n".join(rows) + "\n")
    return path


def test_the_limit_is_ten_thousand():
    assert MAX_PLAN_TESTS == 10_000


def test_a_plan_at_the_limit_is_read(tmp_path):
    plan = read_plan(_plan(tmp_path / "p.csv", 10_000))
    assert len(plan) == 10_000 and plan[-1].test == "9999" and plan[-1].omega == 1 + 9999 % 7


def test_a_plan_over_the_limit_is_refused_with_its_count(tmp_path):
    p = _plan(tmp_path / "p.csv", 25_000)
    with pytest.raises(ValueError, match=r"the plan has 25000 tests: valid range <= 10000 tests in one series"):
        read_plan(p)
    with pytest.raises(ValueError, match=r"plan: the plan has 10001 tests: valid range <= 10000"):
        simulate([TestSpec(str(i), 1.0, 2.2, 0.25) for i in range(10_001)], None, 1.0)


def test_a_repeated_id_is_named(tmp_path):
    with pytest.raises(ValueError, match=r"row 1002: test id '999' is repeated"):
        read_plan(_plan(tmp_path / "p.csv", 1000, repeat_last=True))


def test_the_cli_refuses_in_one_line_and_writes_nothing(tmp_path, capsys):
    p = _plan(tmp_path / "p.csv", 10_001)
    assert main(["simulate", str(tmp_path / "o.csv"), "--plan", str(p)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "the plan has 10001 tests: valid range <= 10000" in err[0]
    assert not (tmp_path / "o.csv").exists()
