"""Where the Hydra configs live, composing one in-process (:func:`compose_config`), and the ``@hydra.main`` of the
tools that run as Hydra apps (:func:`hydra_cli`).

The configs sit in ``conf/`` at the repository root (one config group per axis of
variation). The package is installed editable, so the entry points find them next to
``src/``; ``SDN3D_CONFIG_DIR`` overrides the location (e.g. for a copied config tree).
"""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from sdn3d.errors import InputError


def config_dir() -> str:
    override = os.environ.get("SDN3D_CONFIG_DIR")
    if override:
        path = Path(override).expanduser().resolve()
        if not path.is_dir():
            raise FileNotFoundError(f"SDN3D_CONFIG_DIR={override!r} is not a directory")
        return str(path)
    path = Path(__file__).resolve().parents[3] / "conf"
    if not path.is_dir():
        raise FileNotFoundError(
            f"sdn3d configs not found at {path}; install sdn3d editable from a checkout "
            "(pip install -e .) or set SDN3D_CONFIG_DIR to the conf/ directory"
        )
    return str(path)


CONFIG_DIR = config_dir()


def print_help_if_asked(argv: Sequence[str], doc: str | None, config_name: str) -> bool:
    """For the commands that compose ``conf/<config_name>.yaml`` themselves: on ``-h`` / ``--help`` in ``argv``, print
    the command's ``doc`` and that config (every setting it takes) and return True."""
    if not any(a in ("-h", "--help") for a in argv):
        return False
    print(doc)
    print(Path(CONFIG_DIR, f"{config_name}.yaml").read_text())
    return True


def synth_data_source(root: str | os.PathLike, image_size: Sequence[int] | None = None) -> Any:
    """A synthetic (Virtual KITTI 1.3.1-format) dataset at ``root`` as a :class:`~sdn3d.data.sources.SourceConfig`
    with the settings of ``conf/data/synth.yaml``, at ``image_size [W, H]`` (None: that file's size)."""
    from omegaconf import OmegaConf

    from sdn3d.data.sources import SourceConfig

    data = OmegaConf.load(Path(CONFIG_DIR, "data", "synth.yaml"))
    data.root = str(Path(root).resolve())
    if image_size is not None:
        data.image_size = [int(v) for v in image_size]
    return SourceConfig.from_mapping(data)


def compose_config(overrides: Sequence[str], name: str) -> Any:
    """Compose ``conf/<name>.yaml`` with Hydra ``overrides`` (no run directory, no logging set-up)."""
    from hydra import compose, initialize_config_dir
    from hydra.core.global_hydra import GlobalHydra
    from hydra.errors import HydraException
    from omegaconf.errors import OmegaConfBaseException

    from sdn3d.cli._schemas import register

    register(name)  # the structured schemas the config names first (conf/edit.yaml, app.yaml, bench.yaml, demo.yaml)
    GlobalHydra.instance().clear()  # an earlier in-process Hydra app (e.g. a test) may have left it set
    try:
        with initialize_config_dir(config_dir=CONFIG_DIR, version_base="1.3"):
            return compose(name, overrides=list(overrides))
    except (HydraException, OmegaConfBaseException) as exc:
        wrong = _wrong_type(exc)
        raise InputError(wrong or f"bad configuration override: {exc}") from exc


def _wrong_type(exc: BaseException) -> str | None:
    """A schema's refusal of a value (an OmegaConf ValidationError, the cause of Hydra's exception) as
    ``<key> must be <kind>[ or null], got <value>``; None for any other mistake."""
    from omegaconf import nodes
    from omegaconf.errors import ValidationError

    cause = exc if isinstance(exc, ValidationError) else exc.__cause__
    node = getattr(cause, "child_node", None)
    kinds = {nodes.BooleanNode: "true or false", nodes.IntegerNode: "an integer", nodes.FloatNode: "a number",
             nodes.StringNode: "a string"}
    if not isinstance(cause, ValidationError) or not getattr(cause, "full_key", None) or type(node) not in kinds:
        return None
    null = " or null" if node._is_optional() else ""
    return f"{cause.full_key} must be {kinds[type(node)]}{null}, got {cause.value!r}"


def _one_line(exc: BaseException) -> str:
    """Hydra's message of a configuration mistake in one line, naming the override (a syntax error) or with its
    OmegaConf cause (which names the key); Hydra's config search path is left out."""
    text = " ".join(str(exc).split("Config search path:")[0].split())
    override = getattr(exc, "override", None)
    if override:
        text = f"bad override {override!r}: {text}"
    cause = exc.__cause__
    if cause is not None and str(cause).strip():
        reason = str(cause).strip().splitlines()[0].strip()
        if reason not in text:
            text = f"{text} ({reason})"
    return text


def hydra_cli(tool: str, config_name: str) -> Callable[[Callable[[Any], Any]], Callable[..., Any]]:
    """``@hydra.main`` on ``conf/<config_name>.yaml`` for the tool ``sdn3d-<tool>``, with the command line's
    configuration mistakes (an unknown key, bad override syntax, a config group option that does not exist)
    reported as every sdn3d tool reports a user's mistake: ``sdn3d-<tool>: error: <message naming the key>``, one
    line, exit status 2 (Hydra itself prints several lines and exits 1).

    Hydra finds such a mistake before the task starts; it raises it instead of printing when ``HYDRA_FULL_ERROR`` is
    set, so that is set until the task starts, then restored (the task's own errors are reported as Hydra reports
    them). A user who set ``HYDRA_FULL_ERROR`` gets Hydra's full traceback, as before. Called with a config (as
    ``@hydra.main`` allows), the decorated function runs the task on it directly.
    """
    import hydra

    def decorate(task: Callable[[Any], Any]) -> Callable[..., Any]:
        state: dict[str, Any] = {}

        @functools.wraps(task)
        def task_started(cfg: Any) -> Any:
            if not state.get("started"):
                state["started"] = True
                _restore(state.get("user_set"))
            return task(cfg)

        app = hydra.main(config_path=CONFIG_DIR, config_name=config_name, version_base="1.3")(task_started)

        @functools.wraps(task)
        def main(cfg_passthrough: Any = None) -> Any:
            if cfg_passthrough is not None:
                return app(cfg_passthrough)
            from hydra.errors import ConfigCompositionException, MissingConfigException, OverrideParseException
            from omegaconf.errors import OmegaConfBaseException

            from sdn3d.cli._errors import EXIT_USER_ERROR, PATH_ERRORS

            mistakes = (ConfigCompositionException, MissingConfigException, OverrideParseException,
                        OmegaConfBaseException, *PATH_ERRORS)
            user_set = os.environ.get("HYDRA_FULL_ERROR")
            state.update(started=False, user_set=user_set)
            os.environ["HYDRA_FULL_ERROR"] = "1"
            try:
                return app()
            except mistakes as exc:
                if state["started"] or user_set is not None:
                    raise
                print(f"sdn3d-{tool}: error: {_one_line(exc)}", file=sys.stderr)
                sys.exit(EXIT_USER_ERROR)
            finally:
                if not state["started"]:
                    _restore(user_set)

        return main

    return decorate


def _restore(value: str | None) -> None:
    """``HYDRA_FULL_ERROR`` back to ``value`` (None: unset)."""
    if value is None:
        os.environ.pop("HYDRA_FULL_ERROR", None)
    else:
        os.environ["HYDRA_FULL_ERROR"] = value
