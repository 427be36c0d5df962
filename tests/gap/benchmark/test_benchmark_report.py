"""The benchmark's report (chainid.gap.benchmark.report): rates per family, compound and transfer rates, the
summary texts and the confusion matrix, by hand from the rows."""
from __future__ import annotations

import pytest


def test_compound_rates_by_hand():
    from chainid.gap.benchmark.report import summarise

    def row(truth, verdict, confounded=(), family="mismatch+"):
        return {"family": family, "truth": truth, "verdict": verdict, "snr": 10.0, "shrinkage": 0.9, "seconds": 1.0,
                "confounded": [list(c) for c in confounded], "chain": "c", "plan": "p", "noise": 0.01, "levels": []}

    rows = [row(["stiffness_level", "slack"], "contact_law", [("contact_law", "stiffness_level+slack")]),
            row(["stiffness_level", "friction"], "stiffness_level+friction"),
            row(["friction", "sensor_delay"], "friction", family="pair"),
            row(["machine_compliance", "backlash"], "stiffness_level+backlash+slack")]
    s = summarise(rows)
    assert s["compound_both_named_rate"] == 2 / 4  # rows 2 and 4 (machine_compliance reads as stiffness_level)
    assert s["compound_exact_rate"] == 1 / 4  # only row 2 names exactly the true pair
    assert s["compound_named_or_confounded_rate"] == 3 / 4  # row 1's verdict comes with the true pair as confound


def test_benchmark_family_rates_by_hand():
    """Twelve hand-made cases, every rate counted by hand: singles scored from SNR_MIN (3) on, machine_compliance
    named stiffness_level is right; compounds: both named / exact / named-or-confounded / detectable; controls;
    outside cases (an error is a miss); the median shrinkage of the right verdicts; the misses."""
    from chainid.gap.benchmark.report import family_rates

    def row(family, truth, verdict, snr=5.0, shrinkage=None, **kw):
        return {"family": family, "truth": truth, "verdict": verdict, "snr": snr, "shrinkage": shrinkage,
                "seconds": 2.0, **kw}

    rows = [row("single", ["friction"], "friction", 5.0, 0.6), row("single", ["machine_compliance"],
            "stiffness_level", 4.0, 0.8), row("single", ["backlash"], "hysteresis", 10.0, 0.7),
            row("single", ["slack"], "none", 1.0),
            row("mismatch", ["stiffness_level"], "stiffness_level", 5.0, 0.5),
            row("mismatch+", ["stiffness_level", "friction"], "friction+stiffness_level", 6.0, 0.9),
            row("pair", ["friction", "sensor_delay"], "friction", 6.0, 0.4,
                confounded=[["friction", "friction+sensor_delay"]]),
            row("pair", ["hysteresis", "slack"], "hysteresis+slack+backlash", 8.0, 0.3, effect_snr=[2.0, 5.0]),
            row("control", [], "none", 0.5), row("control", [], "friction", 0.5),
            row("outside", ["drift"], "unexplained", truth_named=[]),
            row("outside", ["chatter"], "friction", truth_named=["friction"], chatter=True),
            row("outside", ["relaxation"], "error: ValueError: boom", truth_named=[])]
    r = family_rates(rows)
    assert (r["n_cases"], r["single_n"], r["single_n_all"], r["single_right_rate"]) == (13, 3, 4, 2 / 3)
    assert (r["mismatch_right_rate"], r["mismatch_n"]) == (1.0, 1)
    assert (r["compound_n"], r["compound_both_named_rate"], r["compound_exact_rate"]) == (3, 2 / 3, 1 / 3)
    assert r["compound_named_or_confounded_rate"] == 1.0
    assert (r["compound_detectable_n"], r["compound_detectable_both_named_rate"]) == (2, 0.5)
    assert (r["mismatch_plus_both_named_rate"], r["pair_both_named_rate"]) == (1.0, 0.5)
    assert (r["control_none_rate"], r["control_n"]) == (0.5, 2)
    assert (r["outside_not_named_rate"], r["outside_n"]) == (2 / 3, 3)
    assert r["outside_verdicts"] == {"error: ValueError: boom": 1, "friction": 1, "unexplained": 1}
    assert (r["chatter_reported_rate"], r["chatter_n"]) == (1.0, 1)
    assert [e["error"] for e in r["errors"]] == ["error: ValueError: boom"]
    assert r["median_shrinkage_when_right"] == pytest.approx(0.7)  # of 0.6, 0.8, 0.5, 0.9
    assert r["median_seconds"] == 2.0
    assert [(m["family"], m["verdict"]) for m in r["misses"]] == [
        ("single", "hysteresis"), ("pair", "friction"), ("pair", "hysteresis+slack+backlash"),
        ("control", "friction"), ("outside", "error: ValueError: boom")]
    assert r["confusion"]["backlash"]["hysteresis"] == 1 and r["confusion"]["none"] == {
        **{v: 0 for v in r["confusion"]["none"]}, "none": 1, "friction": 1}
    assert r["confusion"]["machine_compliance"]["stiffness_level"] == 1


def test_benchmark_summary_counts_a_case_at_the_snr_threshold():
    """Single-effect cases with residual ≥ SNR_MIN × noise are scored: one at exactly SNR_MIN (right), one
    below it (wrong, not scored), one above (wrong): rate 1/2 = "50.0 %" in the text.
    Bugs caught: >= made != or >, the percentage garbled."""
    from chainid.gap.benchmark.report import SNR_MIN, format_summary, summarise

    def row(snr, verdict):
        return {"family": "single", "truth": ["friction"], "verdict": verdict, "snr": snr, "shrinkage": 0.5,
                "seconds": 1.0, "chain": "c", "plan": "p", "noise": 1.0, "seed": 0, "levels": {}}

    rows = [row(SNR_MIN, "friction"), row(0.5 * SNR_MIN, "hysteresis"), row(2 * SNR_MIN, "backlash")]
    s = summarise(rows)
    assert s["single_n"] == 2 and s["single_right_rate"] == 0.5
    assert "single effects, right verdict (residual >= 3x noise): 50.0 % of 2" in format_summary(s)


def _trow(direction, verdict, sh, shr, ok, truth=("friction",)):
    return {"excitation": "transfer", "family": "transfer", "direction": direction, "truth": list(truth),
            "verdict": verdict, "transfer_shrinkage": sh, "transfer_shrinkage_refit": shr, "transfers": ok,
            "transfer_chain": verdict, "seed": 1, "snr": 9.0, "shrinkage": 0.9, "seconds": 1.0}


def test_transfer_rates_by_hand():
    from chainid.gap.benchmark.report import transfer_rates

    rows = [_trow("harmonic>random", "friction", 0.8, 0.6, True), _trow("harmonic>random", "hysteresis", 0.2, None, False),
            _trow("random>harmonic", "friction", None, None, False),
            _trow("random>harmonic", "machine_compliance", 0.9, 0.7, True, truth=("stiffness_level",))]
    t = transfer_rates(rows)
    assert t["n"] == 4
    assert t["median_shrinkage"] == pytest.approx(0.8)  # of 0.8, 0.2, 0.9 (None left out)
    assert t["median_shrinkage_refit"] == pytest.approx(0.65)  # of 0.6, 0.7
    assert t["transfers_rate"] == 0.5
    assert t["fit_right_rate"] == 0.75  # machine_compliance reads as stiffness_level
    h, r = t["by_direction"]["harmonic>random"], t["by_direction"]["random>harmonic"]
    assert (h["n"], h["median_shrinkage"], h["median_shrinkage_refit"], h["transfers_rate"]) == (2, 0.5, 0.6, 0.5)
    assert (r["n"], r["median_shrinkage"], r["fit_right_rate"]) == (2, 0.9, 1.0)
    assert list(t["by_direction"]) == ["harmonic>random", "random>harmonic"]
    assert t["rows"][2] == {"direction": "random>harmonic", "truth": ["friction"], "verdict": "friction",
                            "transfer_chain": "friction", "transfer_shrinkage": None,
                            "transfer_shrinkage_refit": None, "transfers": False, "seed": 1}
    empty = transfer_rates([])
    assert empty["n"] == 0 and empty["median_shrinkage"] is None and empty["transfers_rate"] is None


def _row(exc, family, truth, verdict, snr=9.0, **kw):
    return {"excitation": exc, "family": family, "truth": truth, "verdict": verdict, "snr": snr, "shrinkage": 0.8,
            "seconds": 2.0, "chain": "c", "plan": exc, "noise": 0.01, "levels": [1.0], "seed": 7} | kw


def test_summarise_splits_excitations_and_formats_the_non_harmonic_lines():
    """Harmonic rows at the top level; each non-harmonic excitation apart and pooled; transfer apart; the
    terminal lines say each rate with its n, PASS/MISS against issue 18's targets and the misses."""
    from chainid.gap.benchmark.report import format_summary, summarise

    rows = [_row("harmonic", "single", ["friction"], "friction"),
            _row("random", "single", ["friction"], "friction"), _row("random", "single", ["slack"], "backlash"),
            _row("sweep", "single", ["friction"], "friction"), _row("sweep", "control", [], "none", snr=0.5),
            _row("sweep", "outside", ["chatter"], "friction", truth_named=["friction"], chatter=True),
            _trow("harmonic>random", "friction", 0.8, 0.6, True)]
    s = summarise(rows)
    assert (s["n_cases"], s["harmonic_n"]) == (7, 1)
    assert s["single_right_rate"] == 1.0 and s["single_n"] == 1  # the harmonic one only
    assert sorted(s["by_excitation"]) == ["random", "sweep"]
    assert s["by_excitation"]["random"]["single_right_rate"] == 0.5
    nh = s["nonharmonic"]
    assert (nh["single_right_rate"], nh["single_n"], nh["control_none_rate"]) == (2 / 3, 3, 1.0)
    assert s["transfer"]["n"] == 1 and s["rows"] is rows
    txt = format_summary(s | {"wall_seconds": 12.4})
    lines = txt.splitlines()
    assert "non-harmonic excitations (residual >= 3x noise; n in brackets):" in lines
    i = lines.index("non-harmonic excitations (residual >= 3x noise; n in brackets):")
    assert lines[i + 2] == (f"{'random':<12}{'50.0 % (2)':>14}{'n/a (0)':>14}{'n/a (0)':>14}{'n/a (0)':>14}"
                            f"{'n/a (0)':>14}{'n/a':>10}")
    assert lines[i + 3].startswith("sweep") and lines[i + 3].endswith(f"{'100.0 %':>10}")
    assert lines[i + 4].startswith(f"{'pooled':<12}{'66.7 % (3)':>14}")
    assert ("  MISS: non-harmonic single_right_rate = 66.7 % (target >= 90 %)") in lines
    assert ("  PASS: non-harmonic control_none_rate = 100.0 % (target >= 95 %)") in lines
    assert "  MISS: non-harmonic compound_both_named_rate = n/a (target >= 80 %)" in lines
    assert "  1 non-harmonic miss(es), e.g.:" in lines
    assert "    random single: truth slack -> backlash (snr 9.0, seed 7)" in lines
    assert ("transfer (1 cases): median pooled shrinkage on the other set 80.0 % (target >= 70 %: PASS); after a "
            "per-record refit of offset, spring and dashpot 60.0 %; verdict 'transfers' 100.0 %; true effect named "
            "on the fitting set 100.0 %") in lines
    assert "  harmonic>random: 1 cases, median shrinkage 80.0 %, after refit 60.0 %, transfers 100.0 %" in lines
    assert "median diagnosis time 2.00 s over 7 cases; wall 12 s" in lines
    assert "  PASS: single_right_rate = 100.0 % (target >= 92 %)" in lines
    assert "  MISS: compound_both_named_rate = n/a (target >= 85 %)" in lines


def test_format_summary_without_harmonic_rows_and_with_errors():
    from chainid.gap.benchmark.report import format_summary, summarise

    rows = [_row("quake", "single", ["friction"], "error: ValueError: boom"),
            _row("quake", "single", ["friction"], "friction")]
    txt = format_summary(summarise(rows) | {"wall_seconds": 3.0})
    lines = txt.splitlines()
    assert lines[0] == "2 cases; wall 3 s"
    assert "harmonic families:" not in txt
    assert lines[-1] == "1 case(s) raised an error (counted as misses), e.g. error: ValueError: boom"
    assert format_summary(summarise(rows)).splitlines()[0] == "2 cases"


def test_format_summary_confusion_matrix_and_misses():
    from chainid.gap.benchmark.report import format_summary, summarise

    rows = [_row("harmonic", "single", ["friction"], "friction"),
            _row("harmonic", "single", ["machine_compliance"], "hysteresis+slack"),
            _row("harmonic", "control", [], "none", snr=0.1),
            _row("harmonic", "single", ["backlash"], "error: RuntimeError: x")]
    lines = format_summary(summarise(rows)).splitlines()
    i = lines.index("confusion (rows: truth of single / mismatch / control cases; columns: verdict)")
    cols = ["(combination)", "error: RuntimeError: x", "friction", "none"]
    w = len("error: RuntimeError: x") + 1  # the widest column label + 1 (>= 8)
    assert lines[i + 1] == " " * 22 + "".join(f"{c[:w - 1]:>{w}}" for c in cols)
    assert lines[i + 2] == f"{'backlash':<22}" + "".join(f"{n:>{w}}" for n in (0, 1, 0, 0))
    assert lines[i + 4] == f"{'machine_compliance':<22}" + "".join(f"{n:>{w}}" for n in (1, 0, 0, 0))
    assert "1 case(s) raised an error (counted as misses), e.g. error: RuntimeError: x" in "\n".join(lines)
    assert "2 miss(es), e.g.:" in lines
    assert "  single: truth machine_compliance -> hysteresis+slack (snr 9.0, c, harmonic, noise 0.01)" in lines
