"""Training runs on disk, without Lightning: the run management behind ``sdn3d-train``.

:mod:`lightning_modules.train` composes these stages around Lightning's fit and test:

- :mod:`.resume`: ``resume=<run dir>``, the run's saved config with the command line applied, relocated to where
  the run is now (:func:`~.resume.resolve_config`, :func:`~.resume.resolve_resume`).
- :mod:`.start`: the checks made before anything is written (:func:`~.start.check_start`: the checkpoint training
  continues from and the budget; :func:`~.start.check_threads`).
- :mod:`.rundir`: the run directory (:func:`~.rundir.prepare_run_dir`: writable, stale temp files cleared, the
  saved ``config.yaml``).
- :mod:`.locks`: one writer per run directory (:func:`~.locks.run_lock`).
- :mod:`.summary`: what each attempt records (:func:`~.summary.write_summary`: ``summary.json``,
  ``summary_log.jsonl``, ``summary_file``) and the inference export of a finished run.
- :mod:`.errors`: the run's errors and their one-line prose (:func:`~.errors.error_sentence`,
  :func:`~.errors.error_file`).

This package never imports Lightning (docs/ARCHITECTURE.md's floors); it sits on the floor of :mod:`sdn3d.runs`.
"""
