"""Mutation testing per package with cosmic-ray (a real mutation tool), outside CI.

For every package of ``chainid`` (chain, signal, model, records, damping, gap, dynamics, infra, cli, report)
this script

1. copies the repository to a temporary folder (cosmic-ray mutates the files in place; the working tree is
   never touched), with a sibling ``shared`` linked to ``../shared`` (real-data tests look there);
2. runs ``cosmic-ray init`` on ``chainid/<package>`` with that package's targeted tests (``TARGETS``) as the
   test command, which enumerates every mutant of cosmic-ray's operators;
3. keeps a seeded random sample of ``--sample`` mutants (the rest are removed from the session);
4. checks that the targeted tests pass on the unmutated copy (else the package is reported, not counted);
5. runs ``cosmic-ray exec`` with a per-mutant timeout (3 × the baseline time + 10 s; a timeout counts as
   killed, as in cosmic-ray) and a per-package time budget (``--budget`` minutes over all packages);
6. writes the kill rate per package to ``benchmarks/MUTATION.md`` (date, tool version, command) and every
   surviving mutant with its diff to ``benchmarks/mutation_survivors.json``.  The triage of the survivors
   (equivalent, or a missing test) is kept by hand in ``benchmarks/mutation_survivors.md``.

Kill rate = killed / (killed + survived); incompetent mutants (the mutated code does not import) are
reported, not counted.

Usage (from the repository root; needs ``pip install ".[mutation]"``)::

    python benchmarks/mutation.py                          # all packages, 15 mutants each, seed 20, 40 min
    python benchmarks/mutation.py --packages chain infra --sample 10
    python benchmarks/mutation.py --list                   # number of mutants per package, no run
    python benchmarks/mutation.py --retest benchmarks/mutation_survivors.json --retest-out F.md
                                                           # the survivors again, against today's tests

Not part of the test suite (it takes tens of minutes of CPU).
"""
from __future__ import annotations

import argparse
import ast
import datetime as _dt
import json
import os
import random
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from importlib import metadata
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

#: targeted tests per package: the fast test files (or node ids) that exercise it; pytest arguments
TARGETS: dict[str, tuple[str, ...]] = {
    "chain": (
        "tests/chain/test_catalogue.py",
        "tests/chain/test_chain_spec.py",
        "tests/chain/test_grade.py",
        "tests/chain/test_presets.py",
        "tests/cli/test_cli_stiffness.py",
        "tests/model/test_api_input.py",
        "tests/chain/test_preset_options.py",
    ),
    "signal": (
        "tests/records/test_record_files.py",
        "--deselect=tests/records/test_record_files.py::test_side_file_round_trip_and_bounds",
        "tests/records/test_time_origin.py",
        "tests/signal/test_cycle_fits.py",
        "tests/signal/test_harmonic_estimate.py",
        "tests/signal/test_steady_window.py",
        "tests/signal/test_estimate_window_half_open.py",
        "tests/signal/test_first_pass_window_half_open.py",
        "tests/signal/test_sample_on_a_cycle_boundary.py",
        "tests/signal/test_steady_scatter_with_a_given_tolerance.py",
    ),
    "model": (
        "tests/damping/test_identify.py::test_fewer_than_six_tests_refused",
        "tests/damping/test_identify.py::test_fit_law_stats_against_brute_force",
        "tests/damping/test_identify.py::test_inertia_force_units",
        "tests/damping/test_identify.py::test_law_predictions",
        "tests/damping/test_identify.py::test_mass_term_units",
        "tests/damping/test_identify.py::test_predict_force_estimates_test_parameters",
        "tests/damping/test_identify.py::test_predict_force_matches_model",
        "tests/damping/test_identify.py::test_rank_laws_prefers_true_law",
        "tests/gap/benchmark/test_benchmark_report.py::test_benchmark_summary_counts_a_case_at_the_snr_threshold",
        "tests/gap/core/test_selection.py::test_at_noise_floor_chi2_band",
        "tests/gap/core/test_selection.py::test_near_tie_order_pinned_then_count_then_bic",
        "tests/gap/core/test_stationarity.py::test_check_floor_per_quantity",
        "tests/gap/core/test_stationarity.py::test_too_few_cycles_not_checked",
        "tests/gap/core/test_stationarity.py::test_trend_follows_the_shakers_mean_and_amplitude_not_time",
        "tests/gap/core/test_stationarity.py::test_trend_noise_floor_closed_form",
        "tests/gap/harmonic/test_harmonic_diagnosis.py::test_diagnose_baseline_db_is_on_the_holdout",
        "tests/gap/harmonic/test_harmonic_prepare.py::test_bin_noise_removes_a_local_linear_trend_in_phase_and_time",
        "tests/gap/harmonic/test_harmonic_prepare.py::test_cycle_stats_whole_cycles_by_hand",
        "tests/gap/harmonic/test_harmonic_problem.py::test_bic_sample_size_is_the_training_bins",
        "tests/gap/harmonic/test_harmonic_problem.py::test_noise_db_uses_the_requested_split",
        "tests/gap/harmonic/test_harmonic_where.py::test_delay_signature_reads_a_pure_lag",
        "tests/gap/harmonic/test_harmonic_where.py::test_localise_energy_error_per_cycle_is_the_loop_integral",
        "tests/gap/harmonic/test_harmonic_where.py::test_localise_multi_valued_residual_by_hand",
        "tests/gap/harmonic/test_jackknife.py::test_jackknife_of_a_mean_is_the_standard_error",
        "tests/gap/timedomain/test_time_where.py::test_local_peak_over_the_octave_median",
        "tests/model/test_augmented_model.py",
        "tests/model/test_bouc_wen_operator.py",
        "tests/model/test_pinned_at_a_bound.py",
        "tests/model/test_base_models.py",
        "tests/model/test_effects.py",
        "tests/model/test_kernels.py",
        "tests/model/test_laws.py",
        "tests/model/test_model_file.py",
        "tests/model/test_operators.py",
        "tests/model/test_practice.py",
        "tests/model/test_predict_force.py",
        "tests/model/test_time_damping.py",
        "--deselect=tests/model/test_time_damping.py::test_dominant_frequency_and_amplitude_of_a_ramped_record",
        "--deselect=tests/model/test_time_damping.py::test_hysteretic_rule_keeps_the_energy_per_cycle",
        "tests/records/test_simulate_records.py",
        "--deselect=tests/records/test_simulate_records.py::test_a_chain_simulation_refuses_compression_only",
        "--deselect=tests/records/test_simulate_records.py::test_a_test_without_ramp_starts_at_rest_at_the_mean",
        "--deselect=tests/records/test_simulate_records.py::test_estimate_memory_by_hand",
        "--deselect=tests/records/test_simulate_records.py::test_memory_refusal_states_the_limit_in_gib",
        "--deselect=tests/records/test_simulate_records.py::test_simulation_messages_name_the_test_the_value_and_the_range",
        "--deselect=tests/records/test_simulate_records.py::test_taper_envelope_and_slope_by_hand",
        "--deselect=tests/records/test_simulate_records.py::test_taper_may_reach_half_the_cycles",
        "--deselect=tests/records/test_simulate_records.py::test_taper_of_a_two_second_period_by_hand",
        "tests/model/test_law_ranking_ties.py",
        "tests/model/test_model_file_schema.py",
        "tests/model/test_passivity_rule.py",
    ),
    "records": (
        "tests/records/test_excitation.py",
        "tests/records/test_plausibility.py",
        "tests/records/test_readers.py",
        "tests/records/test_readers_readme.py",
        "tests/records/test_record.py",
        "tests/records/test_record_files.py",
        "tests/records/test_simulate_records.py",
        "tests/records/test_validate_record.py",
        "tests/records/test_writer.py",
        "tests/signal/test_steady_window.py::test_clean_record_unchanged_by_adaptive_tolerance",
        "tests/signal/test_steady_window.py::test_cycle_stats_match_per_cycle_lstsq",
        "tests/signal/test_steady_window.py::test_drifting_mean_keeps_window_where_mean_holds",
        "tests/signal/test_steady_window.py::test_long_record_decimated_search_is_accurate",
        "tests/signal/test_steady_window.py::test_ringing_at_reversals_and_late_start",
        "tests/signal/test_steady_window.py::test_scatter_of_iid_jitter_is_measured",
        "tests/signal/test_steady_window.py::test_shaker_record_wandering_amplitude_kept_adaptive",
        "tests/signal/test_steady_window.py::test_steady_tolerance_floor_and_cap",
        "tests/signal/test_steady_window.py::test_taper_that_never_holds_3_percent_gets_longest_usable_window",
        "tests/signal/test_steady_window.py::test_try_analyse_reason_and_data_errors",
        "tests/records/test_chain_force_dips.py",
        "tests/records/test_plan_bound.py",
        "tests/records/test_dead_channels.py",
        "tests/records/test_binary_safety.py",
        # a mutant of check_memory would read the 2e9-row dataset for real (16 GiB: the OOM killer, which may pick
        # another process on a shared machine)
        "--deselect=tests/records/test_binary_safety.py::test_an_hdf5_dataset_declaring_two_billion_rows_is_refused_before_reading",
        "tests/records/test_pattern_bounds.py",
        "tests/records/test_plausible_slips.py",
        "tests/records/test_slack_warning_throughout_only.py",
        "tests/records/test_time_unit_slip_by_speed.py",
        "tests/records/test_side_file_window_half_open.py",
        # small files against a monkeypatched limit or a declared shape; the readers proper are stubbed, so a
        # mutant of check_memory never allocates the declared size
        "tests/records/test_memory_check_every_reader.py",
        "tests/records/test_daq_text.py",
        "tests/records/test_segments_split.py",
        "tests/records/test_excitation_step_times_and_pulse.py",
        "tests/records/test_reader_decimal_comma_delimiters.py",
        "tests/records/test_short_row_in_a_multiblock_file.py",
    ),
    "damping": (
        "tests/damping/test_audit.py",
        "tests/damping/test_audit_data.py",
        "tests/damping/test_damping_plots.py",
        "tests/damping/test_identify.py",
        "tests/damping/test_identify_excluded.py",
        "tests/damping/test_identify_results.py",
        "tests/damping/test_window_half_open.py",
        "tests/damping/test_linear_base_window_half_open.py",
        "tests/damping/test_identify_given_mass.py",
    ),
    "gap": (
        "tests/gap/benchmark/test_benchmark_chain.py",
        "tests/gap/benchmark/test_benchmark_grid.py",
        "--deselect=tests/gap/benchmark/test_benchmark_grid.py::test_small_benchmark",
        "tests/gap/benchmark/test_benchmark_nonharmonic.py",
        "tests/gap/benchmark/test_benchmark_report.py",
        "tests/gap/benchmark/test_ode_chirp_plan.py",
        "tests/gap/core/test_fit_starts.py",
        "tests/gap/core/test_interpret.py",
        "tests/gap/core/test_noise.py",
        "tests/gap/core/test_selection.py",
        "--deselect=tests/gap/core/test_selection.py::test_step_rule_by_hand",
        "tests/gap/core/test_stationarity.py",
        "tests/gap/core/test_step_figures.py",
        "tests/gap/core/test_summary.py",
        "tests/gap/core/test_verdict.py",
        "tests/gap/harmonic/test_compound_causes.py::test_excluded_test_with_reason_and_strict",
        "tests/gap/harmonic/test_compound_causes.py::test_mismatch_alone_is_one_step",
        "tests/gap/harmonic/test_harmonic_diagnosis.py",
        "--deselect=tests/gap/harmonic/test_harmonic_diagnosis.py::test_baseline_law_fitted_on_training_tests_only",
        "--deselect=tests/gap/harmonic/test_harmonic_diagnosis.py::test_damping_law_and_delay_recovered",
        "--deselect=tests/gap/harmonic/test_harmonic_diagnosis.py::test_negative_slack_recovered",
        "--deselect=tests/gap/harmonic/test_harmonic_diagnosis.py::test_out_of_library_drift_not_misnamed",
        "--deselect=tests/gap/harmonic/test_harmonic_diagnosis.py::test_real_friction_damper_linear",
        "--deselect=tests/gap/harmonic/test_harmonic_diagnosis.py::test_sub_noise_effect_gives_none",
        "tests/gap/harmonic/test_harmonic_prepare.py",
        "tests/gap/harmonic/test_harmonic_problem.py",
        "tests/gap/harmonic/test_harmonic_where.py",
        "tests/gap/harmonic/test_jackknife.py",
        "tests/gap/harmonic/test_law_choice.py",
        "tests/gap/test_diagnose_inputs.py",
        "tests/gap/test_gap_plots.py",
        "tests/gap/test_model_io.py",
        "tests/gap/test_negative_damping.py",
        "tests/gap/test_saved_models.py::test_simulate_model_then_predict_round_trips_to_the_noise_level",
        "tests/gap/test_transfer.py",
        "tests/gap/timedomain/test_time_compound.py::test_stiffness_level_and_slack_against_one_contact_law",
        "tests/gap/timedomain/test_time_data.py",
        "tests/gap/timedomain/test_time_diagnosis.py",
        "--deselect=tests/gap/timedomain/test_time_diagnosis.py::test_no_effect_is_none",
        "--deselect=tests/gap/timedomain/test_time_diagnosis.py::test_random_excitation_recovers_each_family",
        "tests/gap/timedomain/test_time_models.py",
        "tests/gap/timedomain/test_time_route.py",
        "tests/gap/timedomain/test_time_where.py",
        "tests/model/test_operators.py::test_coulomb_sign_is_the_instant_sign_but_on_a_turning_point",
        "tests/model/test_sliding_sign_reversal.py",
        "tests/model/test_delay_hook_composition.py",
        "tests/records/test_excitation.py::test_excitation_closed_forms",
        "tests/records/test_excitation.py::test_excitation_derivatives_are_exact",
        "tests/records/test_time_origin.py::test_diagnose_same_tests_at_any_origin",
        "tests/gap/test_kinematics_rest.py",
        "tests/gap/test_kinematics_rest_periodic.py",
        "tests/gap/core/test_fit_cache_order.py",
        "tests/gap/core/test_rebuild_order.py",
        "tests/gap/core/test_trusted_path.py",
        "tests/gap/harmonic/test_prepare_window_half_open.py",
        "tests/gap/harmonic/test_resample_refit_converges.py",
        "tests/gap/timedomain/test_band_limited_comparison.py::test_noise_share_is_the_butterworth_closed_form",
        "tests/gap/timedomain/test_band_limited_comparison.py::test_filtered_white_noise_keeps_its_noise_share",
        "tests/gap/timedomain/test_band_limited_comparison.py::test_each_run_of_a_view_is_filtered_on_its_own",
        "tests/gap/timedomain/test_band_limited_comparison.py::test_the_rule_needs_fast_motion_and_a_force_without_it",
        "tests/gap/core/test_profile_likelihood_intervals.py",
        "tests/gap/harmonic/test_profile_interval_against_brute_force.py",
        "tests/gap/harmonic/test_delay_basin_scan.py",
        "tests/gap/timedomain/test_time_delay_basin_scan.py",
        "tests/gap/timedomain/test_discretisation_bias.py",
        "tests/gap/timedomain/test_profile_chi2_and_held_fits.py",
        "tests/gap/benchmark/test_sim_coverage.py",
        "tests/gap/benchmark/test_benchmark_summary_from_json.py",
    ),
    "dynamics": (
        "tests/cli/test_cli_dynamics.py",
        "--deselect=tests/cli/test_cli_dynamics.py::test_dynamics_sine_drive_defaults_to_the_librarys_omega",
        "--deselect=tests/cli/test_cli_dynamics.py::test_json_has_the_final_tensions_modes_line_and_drive",
        "--deselect=tests/cli/test_cli_dynamics.py::test_text_report_states_the_run",
        "tests/dynamics/test_chain_line.py",
        "tests/dynamics/test_drives.py",
        "tests/dynamics/test_dynamics_plots.py",
        "tests/dynamics/test_energy_balance.py",
        "tests/dynamics/test_integrators.py",
        "tests/dynamics/test_modes.py",
        "tests/dynamics/test_run_checks.py",
        "tests/dynamics/test_segment_damping.py",
        "tests/dynamics/test_segment_model.py",
        "tests/dynamics/test_segments.py",
        "tests/dynamics/test_simulation.py",
        "--deselect=tests/dynamics/test_simulation.py::test_one_segment_reproduces_the_paper_test_model",
        "tests/dynamics/test_sweeps.py",
        "tests/dynamics/test_waves.py",
        "--deselect=tests/dynamics/test_simulation.py::test_one_segment_reproduces_the_paper_test_model",
        "tests/dynamics/test_work_bound.py",
        "tests/dynamics/test_drive_resolution.py",
        "tests/dynamics/test_output_aliasing_bound.py",
        "tests/dynamics/test_segment_effects.py",
        "--deselect=tests/dynamics/test_segment_effects.py::test_stiffness_level_scales_the_link_term",
        "tests/dynamics/test_segment_effects_series.py",
        "tests/dynamics/test_segment_model_effects.py",
    ),
    "infra": (
        "tests/infra/test_fileio.py",
        "tests/infra/test_files_sacred.py",
        "tests/infra/test_floattext.py",
        "tests/infra/test_floattext_blocks.py",
        "tests/infra/test_jsonio.py",
        "tests/infra/test_lazy_exports.py",
        "tests/infra/test_numba_cache.py",
        "tests/infra/test_parallel.py",
        "tests/infra/test_parallel_limits.py",
        # (the SIGINT tests of test_parallel_limits.py signal on events -- every case announced, the parent
        # handles SIGINT again -- not after a delay, so they are in again)
        "tests/infra/test_progress.py",
        "tests/infra/test_workers_die_with_parent.py",
        "tests/infra/test_parent_death_signal.py",
        "tests/cli/test_warnings_through_the_run.py",
        "tests/cli/test_warnings_in_json.py",
        "tests/cli/test_error_lines.py",
        "tests/infra/test_runlog_nested_runs.py",
    ),
    "cli": (
        "tests/chain/test_grade.py",
        "tests/chain/test_presets.py",
        "--deselect=tests/chain/test_presets.py::test_match_finds_a_mooring_preset_by_dimensions_only_inside_its_range",
        "tests/cli/test_cli_audit_data.py",
        "tests/cli/test_cli_benchmark.py",
        "tests/cli/test_cli_bounds.py",
        "tests/cli/test_cli_chains.py",
        "tests/cli/test_cli_convert.py",
        "tests/cli/test_cli_diagnose.py",
        "tests/cli/test_cli_dynamics.py",
        "tests/cli/test_cli_generate.py",
        "tests/cli/test_cli_identify.py",
        "tests/cli/test_cli_input_checks.py",
        "tests/cli/test_cli_outputs.py",
        # timing-dependent under load (a SIGINT sent after a delay to a subprocess that imports without
        # bytecode and with an empty numba cache): failed the unmutated copy's baseline twice
        "--deselect=tests/cli/test_cli_outputs.py::test_sigint_mid_write_exits_130_and_leaves_no_partial_output",
        "tests/cli/test_cli_parser.py",
        "tests/cli/test_cli_predict.py",
        "tests/cli/test_cli_simulate.py",
        "tests/cli/test_json_stdout.py",
        "tests/damping/test_audit.py::test_cli_identify_fewer_than_six_tests",
        "tests/damping/test_audit.py::test_cli_identify_linear_model_allows_compression",
        "tests/damping/test_audit.py::test_cli_side_file_roundtrip",
        "tests/damping/test_audit_data.py::test_audit_data_needs_six_tests",
        "tests/damping/test_audit_data.py::test_audit_data_recovers_the_law",
        "tests/damping/test_audit_data.py::test_audit_data_through_the_reading_options",
        "tests/damping/test_audit_data.py::test_audit_without_data_is_table1",
        "tests/damping/test_identify_excluded.py",
        "tests/infra/test_files_sacred.py",
        "tests/model/test_kernels.py::test_cli_stiffness_json",
        # timing-dependent under load (a SIGINT sent after a delay to a subprocess that imports without
        # bytecode and with an empty numba cache): failed the unmutated copy's baseline twice
        "--deselect=tests/cli/test_cli_outputs.py::test_sigint_mid_write_exits_130_and_leaves_no_partial_output",
        "tests/cli/test_error_lines.py",
        "tests/cli/test_stiffness_load_warnings.py",
        "tests/cli/test_warnings_in_json.py",
        "tests/cli/test_model_file_commands.py",
        "tests/cli/test_simulate_model_options.py",
        "tests/cli/test_predict_plot_names.py",
        "tests/cli/test_convert_targets.py",
        "tests/cli/test_reading_messages_grouped.py",
        "tests/cli/test_warnings_through_the_run.py",
        "tests/cli/test_identify_load_warnings.py",
        "tests/cli/test_benchmark_generator_options.py",
        "tests/cli/test_convert_chain_checks.py",
        "tests/dynamics/test_segment_model_effects.py",
    ),
    "report": (
        "tests/cli/test_cli_outputs.py::test_report_force_replaces_only_the_files_it_wrote",
        "tests/cli/test_cli_outputs.py::test_report_force_with_a_bad_input_keeps_every_file",
        "tests/cli/test_cli_outputs.py::test_report_into_the_current_folder",
        "tests/cli/test_cli_outputs.py::test_report_late_failure_or_sigint_leaves_the_old_report",
        "tests/infra/test_files_sacred.py::test_report_force_never_replaces_a_file_it_did_not_write",
        "tests/infra/test_files_sacred.py::test_report_never_replaces_its_data",
        "tests/report/test_markdown_table.py",
        "tests/report/test_report_command.py",
        "--deselect=tests/report/test_report_command.py::test_report_on_builtin_chain",
        "tests/report/test_report_diagnosis.py",
        "tests/report/test_report_driver.py",
        "tests/report/test_report_gap.py",
        "tests/report/test_report_steps.py",
        "tests/report/test_report_table1.py",
        "tests/report/test_eq26_inverse.py",
    ),
}
PACKAGES = tuple(TARGETS)


def _copy_repo(dst: Path) -> None:
    ignore = shutil.ignore_patterns(".git", "__pycache__", ".pytest_cache", "*.egg-info", ".hypothesis", "build",
                                    "mutants", "*.sqlite")
    shutil.copytree(REPO, dst, ignore=ignore, symlinks=True)


def _targets(pkg: str, root: Path) -> list[str]:
    """The package's targeted tests that exist in ``root`` (a listed file may not exist yet)."""
    return [t for t in TARGETS[pkg] if t.startswith("-") or (root / t.split("::")[0]).is_file()]


#: packages whose njit functions are compiled into other modules' njit functions (numba's cache of the caller
#: does not see a change in the callee's file): every mutant gets a fresh NUMBA_CACHE_DIR (slower, but not stale)
FRESH_NUMBA_CACHE = {"dynamics", "model"}


def _test_command(tests: list[str], fresh_cache: bool = False) -> str:
    cmd = " ".join(shlex.quote(a) for a in
                   [sys.executable, "-m", "pytest", "-x", "-q", "-n", "0", "-p", "no:cacheprovider", "--no-header",
                    *tests])
    if not fresh_cache:
        return cmd
    script = f'd=$(mktemp -d); NUMBA_CACHE_DIR="$d" {cmd}; rc=$?; rm -rf "$d"; exit $rc'
    return f"sh -c {shlex.quote(script)}"


def _config(pkg: str, command: str, timeout: float) -> str:
    return (f'[cosmic-ray]\nmodule-path = "chainid/{pkg}"\ntimeout = {timeout:.1f}\nexcluded-modules = []\n'
            f"test-command = {json.dumps(command)}\n\n[cosmic-ray.distributor]\nname = \"local\"\n")


def _env(copy: Path) -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(copy), "NUMBA_CACHE_DIR": str(copy / ".numba_cache"),
            "MPLBACKEND": "Agg", "PYTHONDONTWRITEBYTECODE": "1"}


def _init(pkg: str, copy: Path, timeout: float) -> tuple[Path, Path, int]:
    cfg, session = copy / f"cr_{pkg}.toml", copy / f"cr_{pkg}.sqlite"
    cfg.write_text(_config(pkg, _test_command(_targets(pkg, copy), pkg in FRESH_NUMBA_CACHE), timeout),
                   encoding="utf-8")
    if session.exists():
        session.unlink()
    subprocess.run(["cosmic-ray", "init", str(cfg), str(session)], cwd=copy, env=_env(copy), check=True,
                   capture_output=True)
    from cosmic_ray.work_db import WorkDB, use_db

    with use_db(str(session), WorkDB.Mode.open) as db:
        n = db.num_work_items
    return cfg, session, n


def _annotation_spans(path: Path) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """(start, end) positions of every annotation of a module that has ``from __future__ import annotations``
    (such annotations are never evaluated, so a mutant inside one is equivalent by construction)."""
    text = path.read_text(encoding="utf-8")
    tree = ast.parse(text)
    if not any(isinstance(n, ast.ImportFrom) and n.module == "__future__" and
               any(a.name == "annotations" for a in n.names) for n in tree.body):
        return []
    spans = []
    for node in ast.walk(tree):
        anns = []
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            a = node.args
            anns = [x.annotation for x in (*a.posonlyargs, *a.args, *a.kwonlyargs, a.vararg, a.kwarg)
                    if x is not None and x.annotation is not None] + ([node.returns] if node.returns else [])
        elif isinstance(node, ast.AnnAssign):
            anns = [node.annotation]
        for an in anns:
            spans.append(((an.lineno, an.col_offset), (an.end_lineno, an.end_col_offset)))
    return spans


def _in_annotation(m, spans_of: dict, root: Path) -> bool:
    f = m.module_path
    if f not in spans_of:
        spans_of[f] = _annotation_spans(root / f)
    s = tuple(m.start_pos)
    return any(a <= s < b for a, b in spans_of[f])


def _sample(session: Path, k: int, seed: int, root: Path) -> tuple[int, int]:
    """Keep a seeded random sample of k mutants (after dropping those inside unevaluated annotations).
    Returns (kept, dropped as annotation mutants)."""
    from cosmic_ray.work_db import WorkDB, use_db

    with use_db(str(session), WorkDB.Mode.open) as db:
        # sorted by what the mutant is (job ids are random uuids), so that a seed gives the same sample
        items = sorted(db.work_items, key=lambda w: (str(w.mutations[0].module_path), w.mutations[0].operator_name,
                                                      w.mutations[0].occurrence))
        spans: dict = {}
        real = [w for w in items if not _in_annotation(w.mutations[0], spans, root)]
        keep = random.Random(seed).sample(real, min(k, len(real)))
        db.clear()
        db.add_work_items(keep)
        return len(keep), len(items) - len(real)


def _results(session: Path) -> list[dict]:
    from cosmic_ray.work_db import WorkDB, use_db

    out = []
    with use_db(str(session), WorkDB.Mode.open) as db:
        for item, res in db.completed_work_items:
            m = item.mutations[0]
            out.append({"job": item.job_id, "file": str(m.module_path), "line": m.start_pos[0],
                        "operator": m.operator_name, "occurrence": m.occurrence,
                        "outcome": (res.test_outcome.value if res.test_outcome is not None
                                    else res.worker_outcome.value),
                        "worker": res.worker_outcome.value, "diff": res.diff or ""})
    return out


def run_package(pkg: str, copy: Path, sample: int, seed: int, budget_s: float) -> dict:
    """Baseline, init, sample and exec for one package; its counts and survivors."""
    tests = _targets(pkg, copy)
    t0 = time.perf_counter()
    base = subprocess.run(shlex.split(_test_command(tests, pkg in FRESH_NUMBA_CACHE)), cwd=copy, env=_env(copy), capture_output=True, text=True)
    t_base = time.perf_counter() - t0
    row: dict = {"package": pkg, "tests": tests, "baseline_s": round(t_base, 1)}
    if base.returncode != 0:
        row["error"] = "targeted tests fail on the unmutated copy: " + (base.stdout.strip().splitlines() or ["?"])[-1]
        return row
    timeout = 3.0 * t_base + 10.0
    cfg, session, n_all = _init(pkg, copy, timeout)
    kept, n_ann = _sample(session, sample, seed, copy)
    row.update(mutants_total=n_all, annotation_mutants=n_ann, sampled=kept, timeout_s=round(timeout, 1))
    t1 = time.perf_counter()
    proc = subprocess.Popen(["cosmic-ray", "exec", str(cfg), str(session)], cwd=copy, env=_env(copy),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        proc.wait(timeout=budget_s)
        row["budget_hit"] = False
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, 9)  # the mutant in place is left in this package's copy, which is discarded
        proc.wait()
        row["budget_hit"] = True
    row["exec_s"] = round(time.perf_counter() - t1, 1)
    res = _results(session)
    killed = sum(r["outcome"] == "killed" for r in res)
    survived = [r for r in res if r["outcome"] == "survived"]
    row.update(run=len(res), killed=killed, survived=len(survived),
               incompetent=sum(r["outcome"] not in ("killed", "survived") for r in res),
               kill_rate=killed / (killed + len(survived)) if killed + len(survived) else None,
               survivors=survived)
    return row


def retest(survivors_json: Path, out_md: Path | None, packages: tuple[str, ...] = PACKAGES) -> list[dict]:
    """Apply every survivor of an earlier run again (``cosmic-ray apply``, in a fresh copy of the repository as it
    is now) and run its package's current targeted tests: killed now (a test was added) or still surviving."""
    rows = json.loads(survivors_json.read_text(encoding="utf-8"))
    out = []
    with tempfile.TemporaryDirectory(prefix="chainid-retest-") as tmp:
        shared = REPO.parent / "shared"
        if shared.is_dir():
            (Path(tmp) / "shared").symlink_to(shared)
        pristine = Path(tmp) / "pristine"
        _copy_repo(pristine)
        for r in rows:
            if r["package"] not in packages:
                continue
            for sv in r.get("survivors", []):
                copy = Path(tmp) / "work"
                if copy.exists():
                    shutil.rmtree(copy)
                shutil.copytree(pristine, copy, symlinks=True)
                subprocess.run(["cosmic-ray", "apply", sv["file"], sv["operator"], str(sv["occurrence"])], cwd=copy,
                               env=_env(copy), check=True, capture_output=True)
                cmd = shlex.split(_test_command(_targets(r["package"], copy), r["package"] in FRESH_NUMBA_CACHE))
                try:
                    rc = subprocess.run(cmd, cwd=copy, env=_env(copy), capture_output=True, timeout=600).returncode
                except subprocess.TimeoutExpired:
                    rc = -1
                row = {"package": r["package"], "file": sv["file"], "line": sv["line"], "operator": sv["operator"],
                       "occurrence": sv["occurrence"], "now": "killed" if rc != 0 else "survived"}
                out.append(row)
                print(f"{row['package']:9s} {row['file']}:{row['line']} {row['operator']}: {row['now']}", flush=True)
    if out_md is not None:
        k = sum(r["now"] == "killed" for r in out)
        lines = ["| package | where | operator | with today's targeted tests |", "|---|---|---|---|"]
        lines += [f"| {r['package']} | {r['file']}:{r['line']} | {r['operator']} (#{r['occurrence']}) | {r['now']} |"
                  for r in out]
        lines += ["", f"{k} of {len(out)} survivors are killed by today's targeted tests."]
        out_md.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return out


def _rel(p: Path) -> str:
    """*p* relative to the repository when it lies inside it (the report names files as a reader finds them)."""
    try:
        return p.resolve().relative_to(REPO).as_posix()
    except ValueError:
        return str(p)


def write_markdown(rows: list[dict], args: argparse.Namespace, path: Path, started: str, minutes: float) -> None:
    ver = metadata.version("cosmic-ray")
    cmd = "python benchmarks/mutation.py " + " ".join(
        [f"--packages {' '.join(args.packages)}" if tuple(args.packages) != PACKAGES else "",
         f"--sample {args.sample} --seed {args.seed} --budget {args.budget:g}"]).strip()
    tot_k = sum(r.get("killed", 0) for r in rows)
    tot_s = sum(r.get("survived", 0) for r in rows)
    lines = [
        "# Mutation testing per package (cosmic-ray)", "",
        f"Run {started} UTC, cosmic-ray {ver}, Python {sys.version.split()[0]}"
        + (f", {minutes:.1f} min." if minutes == minutes else "."), "",
        "Commands: " + ", ".join(sorted({f"`{r.get('command', cmd)}` ({r.get('run_started_utc', started)} UTC)"
                                           for r in rows})), "",
        f"A seeded random sample of {args.sample} of cosmic-ray's mutants per package (seed {args.seed}), each run "
        "against the package's targeted tests (`TARGETS` in `benchmarks/mutation.py`); kill rate = killed / "
        "(killed + survived); a timeout counts as killed; incompetent mutants are not counted. Survivors and their "
        f"triage: `{_rel(Path(args.survivors).with_suffix('.md'))}` (raw diffs: `{_rel(Path(args.survivors))}`).", "",
        "Mutants inside type annotations are dropped before sampling: every module has `from __future__ import "
        "annotations`, so its annotations are never evaluated and such a mutant (`str | None` → `str % None`) is "
        "equivalent by construction.", "",
        "| package | mutants (all) | in annotations | sampled | run | killed | survived | incompetent | kill rate "
        "| budget hit |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['package']} | – | – | – | – | – | – | – | not run: {r['error']} | |")
            continue
        kr = f"{100 * r['kill_rate']:.0f} %" if r["kill_rate"] is not None else "–"
        lines.append(f"| {r['package']} | {r['mutants_total']} | {r['annotation_mutants']} | {r['sampled']} | "
                     f"{r['run']} | {r['killed']} | "
                     f"{r['survived']} | {r['incompetent']} | {kr} | {'yes' if r['budget_hit'] else 'no'} |")
    if tot_k + tot_s:
        lines += ["", f"All packages: {tot_k} of {tot_k + tot_s} killed ({100 * tot_k / (tot_k + tot_s):.0f} %)."]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--packages", nargs="+", default=list(PACKAGES), choices=PACKAGES)
    ap.add_argument("--sample", type=int, default=15, help="mutants per package (seeded random sample)")
    ap.add_argument("--seed", type=int, default=20)
    ap.add_argument("--budget", type=float, default=40.0, help="minutes for the whole run (split over packages)")
    ap.add_argument("--list", action="store_true", help="only count the mutants per package")
    ap.add_argument("--out", default=str(REPO / "benchmarks" / "MUTATION.md"))
    ap.add_argument("--survivors", default=str(REPO / "benchmarks" / "mutation_survivors.json"))
    ap.add_argument("--merge", action="store_true",
                    help="keep the other packages' rows of the survivors JSON and MUTATION.md (re-run some packages)")
    ap.add_argument("--retest", metavar="SURVIVORS.json",
                    help="re-apply the survivors of an earlier run and run today's targeted tests on each")
    ap.add_argument("--retest-out", metavar="FILE.md", help="with --retest: write the table to FILE.md")
    args = ap.parse_args(argv)
    if shutil.which("cosmic-ray") is None:
        print("mutation.py: cosmic-ray is not installed: pip install '.[mutation]'", file=sys.stderr)
        return 2
    if args.retest:
        retest(Path(args.retest), Path(args.retest_out) if args.retest_out else None, tuple(args.packages))
        return 0
    started = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M")
    t0 = time.perf_counter()
    rows = []
    with tempfile.TemporaryDirectory(prefix="chainid-mut-") as tmp:
        shared = REPO.parent / "shared"
        if shared.is_dir():
            (Path(tmp) / "shared").symlink_to(shared)
        pristine = Path(tmp) / "pristine"  # one snapshot at the start: edits made during the run do not leak in
        _copy_repo(pristine)
        for i, pkg in enumerate(args.packages):
            copy = Path(tmp) / f"repo_{pkg}"  # a fresh copy per package: a run cut by the budget leaves a mutant
            shutil.copytree(pristine, copy, symlinks=True)
            if args.list:
                _, _, n = _init(pkg, copy, 60.0)
                print(f"{pkg:10s} {n:6d} mutants; tests: {' '.join(_targets(pkg, copy))}")
                continue
            left = args.budget * 60.0 - (time.perf_counter() - t0)
            budget_s = max(60.0, left / (len(args.packages) - i))
            row = run_package(pkg, copy, args.sample, args.seed, budget_s)
            rows.append(row)
            kr = row.get("kill_rate")
            print(f"{pkg:10s} " + (row["error"] if "error" in row else
                  f"{row['killed']}/{row['killed'] + row['survived']} killed"
                  + (f" ({100 * kr:.0f} %)" if kr is not None else "")
                  + f", {row['incompetent']} incompetent, {row['exec_s']:.0f} s"), flush=True)
    if args.list:
        return 0
    minutes = (time.perf_counter() - t0) / 60.0
    for r in rows:
        r["run_started_utc"] = started
        r["command"] = " ".join(["python benchmarks/mutation.py", *(argv if argv is not None else sys.argv[1:])])
    if args.merge and Path(args.survivors).is_file():
        old_rows = json.loads(Path(args.survivors).read_text(encoding="utf-8"))
        new = {r["package"]: r for r in rows}
        rows = [new.pop(r["package"], r) for r in old_rows] + list(new.values())
        minutes = float("nan")
    write_markdown(rows, args, Path(args.out), started, minutes)
    Path(args.survivors).write_text(json.dumps(rows, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
