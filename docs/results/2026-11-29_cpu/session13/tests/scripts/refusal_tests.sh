#!/usr/bin/env bash
# refusal_tests.sh VENV TREE OUT: the sdn3d-train refusal tests of TREE, run serially with VENV's python (TREE installed)
cd "$2"
unset PYTHONDONTWRITEBYTECODE
tests=(tests/test_train_run_safety.py::test_a_refused_training_leaves_no_run_directory_and_no_other_runs_hydra_record
       tests/test_train_ops.py::test_unwritable_output_dir_is_a_clear_error
       tests/test_threads_setting.py::test_sdn3d_train_threads_0_exits_2_in_one_line
       tests/test_threads_setting.py::test_sdn3d_train_refuses_the_old_threads_key)
[ -n "${NEW:-}" ] && tests+=(tests/test_train_run_safety.py::test_a_refused_training_answers_before_importing_lightning)
OMP_NUM_THREADS=1 nice -n 5 "$1/bin/python" -m pytest -q -p no:cacheprovider "${tests[@]}" --durations=0 --durations-min=0.1 > "$3" 2>&1
