"""Every seed case with a checkable answer is read by a test through the API, or listed here with its reason."""

from __future__ import annotations

from pathlib import Path

from conftest import CASES

HERE = Path(__file__).resolve()

# Cases whose answer the service cannot be asked for, and why.
NOT_THROUGH_API = {
    "cw_inertia_loads": "inertia loads from acceleration-plan segment lengths times the drawing scale: the service "
                        "computes accelerations itself (the lecture shaper's kinetostatics are checked instead)",
    "cw_rocker_reaction_F23": "a moment equation with arms measured on the drawing (mm times mu_L); the course "
                              "work's link dimensions are not among the inputs",
    "cw_force_plan_products": "force-plan segment lengths times the plan scale: arithmetic of a drawing",
    "cw_reduced_moment_diagram": "diagram ordinates M/mu_M at a chosen drawing scale",
    "cw_work_diagram_scale": "the scale of a graphical integration, H·mu_M·mu_phi",
    "cw_reduced_inertia_table": "the diagram scale mu_J for a chosen ordinate length",
    "cw_delta_from_speed_table": "delta of a measured table of speeds; no endpoint takes measured speeds (the "
                                 "engine's speed_fluctuation does, tests/test_flywheel_seed.py)",
}

# Cases with no answer at all (tolerance_rel null), and why.
NO_ANSWER = {
    "gear_train_variants_6_7_incomplete": "the train's layout is only in a missing figure",
    "rotor_balancing_variants_incomplete": "the masses' radii, angles and planes are only in missing figures",
}


def _api_test_text() -> str:
    """Source of the test modules that call the service (they take the in-process client), this one aside."""
    files = [p for p in HERE.parent.glob("test_*.py") if p != HERE]
    return "\n".join(t for t in (p.read_text(encoding="utf-8") for p in files) if "client: SynthClient" in t)


def test_every_checkable_seed_case_goes_through_the_api_or_is_listed() -> None:
    text = _api_test_text()
    read = {cid for cid in CASES if f'"{cid}"' in text}
    unanswered = {cid for cid, c in CASES.items() if c["tolerance_rel"] is None}
    assert unanswered == set(NO_ANSWER), "a case without an answer must be listed in NO_ANSWER with its reason"
    missing = set(CASES) - unanswered - read - set(NOT_THROUGH_API)
    assert not missing, f"seed cases neither read through the API nor listed with a reason: {sorted(missing)}"
    stale = read & set(NOT_THROUGH_API)
    assert not stale, f"listed as not through the API but read by an API test: {sorted(stale)}"
    assert set(NOT_THROUGH_API) <= set(CASES) and all(NOT_THROUGH_API.values()) and all(NO_ANSWER.values())


# The seeds' cases beyond the digest's table, each read through the API by the named test.
COVERED_BEYOND_TABLE = {
    "an engine's torque table that drives, the constant torque resisting (seed 002 flywheel, 720° cycle)":
        "tests/test_flywheel_roles.py::test_engine_torque_drives_and_the_constant_torque_resists",
    "an engine's balance shafts at k·w for each order (seed 003 (6.32)-(6.33))":
        "tests/test_balancing_engines.py::test_single_cylinder_orders_and_the_seed_balance_shafts",
    "in-line four, in-line six and 90° V-twin against the classic balance tables":
        "tests/test_balancing_engines.py::test_inline_four_has_only_a_secondary_force",
    "rolling friction k·N of a roller on its guide, pure rolling f > k/r (seed 000 §13.3)":
        "tests/test_rolling_friction.py::test_rolling_guide_matches_the_closed_form",
    "instant centres by Kennedy's theorem and the radius of curvature of a point's path":
        "tests/test_instant_centres.py::test_coupler_centre_is_where_crank_and_rocker_lines_meet",
    "a passive link: the double parallelogram moves though W = 3n - 2p = 0 (seed 001 redundant constraints)":
        "tests/test_passive_and_triads.py::test_double_parallelogram_through_the_api",
    "a class-III Assur group (an eight-bar's triad) placed and analysed (seed 001 groups of higher class)":
        "tests/test_passive_and_triads.py::test_eight_bar_through_the_api",
    "rolling friction k·N of a cam's roller: the dwell's torque k·N·R/r (seed 000 §13.3)":
        "tests/test_cam_rolling.py::test_cam_roller_rolling_friction_in_a_dwell",
}


def test_cases_beyond_the_table_name_a_test_that_exists() -> None:
    for where in COVERED_BEYOND_TABLE.values():
        path, name = where.split("::")
        text = (HERE.parent.parent / path).read_text(encoding="utf-8")
        assert f"def {name}(client: SynthClient)" in text, where


# Where each model stops: every edge of validity the service refuses or warns about, with the test that holds it
# (each reproduces the case and checks what the answer now says against an independent figure).
EDGES = {
    "a load beyond the motor's breakdown torque at the crank: 422 motor_stalls with the torque lacking":
        "tests/test_regulation.py::test_a_load_beyond_the_breakdown_torque_is_refused_with_the_torque_it_lacks",
    "peaks of the cycle beyond the breakdown torque: the whole characteristic, motor_breakdown":
        "tests/test_regulation.py::test_the_motor_never_gives_more_than_its_breakdown_torque",
    "a PI loop tuned with its filter (third order) at the asked damping":
        "tests/test_regulation.py::test_tuning_places_the_real_loop_with_its_filter",
    "the tuned loop's simulated overshoot and settling held against what was asked":
        "tests/test_regulation.py::test_the_filtered_example_reports_what_it_achieves_against_what_was_asked",
    "settling judged in 2 % of the dip, a wide band not allowed to say settled at once":
        "tests/test_regulation.py::test_settling_is_judged_in_two_percent_of_the_dip",
    "a PI loop without a filter takes time to settle":
        "tests/test_regulation.py::test_a_pi_loop_without_a_filter_settles_after_a_time",
    "a barely damped loop refused at once with its poles":
        "tests/test_regulation.py::test_a_barely_damped_loop_is_refused_at_once_with_its_poles",
    "the cam follower leaving the cam (follower_jump)":
        "tests/test_cam_validity.py::test_the_follower_leaving_the_cam_is_named_with_its_angles",
    "a cam's pressure angle and profile radius beyond their limits":
        "tests/test_cam_validity.py::test_pressure_angle_and_profile_radius_of_a_tiny_knife_edge_cam",
    "infinite jerk where simple harmonic motion meets a dwell":
        "tests/test_cam_validity.py::test_simple_harmonic_motion_beside_a_dwell_steps_its_acceleration",
    "the cam spring designed as a coil, not a zero-rate preload":
        "tests/test_cam_validity.py::test_the_designed_spring_is_a_spring_and_its_coil_holds_together",
    "the least cam on its hub": "tests/test_cam_validity.py::test_the_least_cam_encloses_its_hub",
    "a frame driven at resonance: transmissibility, frequency ratio, damping near a mode":
        "tests/test_foundation_validity.py::test_a_frame_at_resonance_is_named_with_its_transmissibility",
    "an undamped frame a hair off resonance":
        "tests/test_foundation_validity.py::test_an_undamped_frame_a_hair_off_resonance_is_not_calm",
    "an isolator lifting off over the cycle":
        "tests/test_foundation_validity.py::test_an_isolator_lifting_off_is_named_with_its_crank_angles",
    "a frame centre outside its isolators (an isolator in tension)":
        "tests/test_foundation_validity.py::test_a_centre_outside_its_isolators_is_named",
    "the frame's run-up with the crank's angular acceleration and the drive's reaction":
        "tests/test_foundation_validity.py::"
        "test_the_run_up_with_the_cranks_acceleration_against_an_independent_integration",
    "the drawn assembly of a class-III group is the one analysed":
        "tests/test_passive_and_triads.py::test_the_drawn_assembly_is_the_one_analysed",
    "a study of lengths keeps the drawn assembly":
        "tests/test_passive_and_triads.py::test_a_study_of_lengths_keeps_the_drawn_assembly",
    "a drawing between two assemblies refused":
        "tests/test_passive_and_triads.py::test_a_drawing_between_two_assemblies_is_refused",
    "the in-line five as built (1-2-4-5-3) and any even firing order":
        "tests/test_balancing_engines.py::test_the_inline_five_as_built_and_by_its_firing_order",
    "every in-line arrangement's throws from its firing order":
        "tests/test_balancing_engines.py::test_every_inline_arrangement_is_its_firing_order",
    "a gear pair in the resonance ranges of ISO 6336-1":
        "tests/test_gearing_rating.py::test_the_resonance_ranges_of_iso_6336_1_are_named",
}


def test_every_edge_names_a_test_that_exists() -> None:
    for where in EDGES.values():
        path, name = where.split("::")
        text = (HERE.parent.parent / path).read_text(encoding="utf-8")
        assert f"def {name}(" in text, where
