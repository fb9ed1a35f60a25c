# ruff: noqa: UP006, UP007, UP045 (OmegaConf reads the annotations at run time: typing.List / Optional)
"""The structured schemas of the inference configs (``conf/edit.yaml``, ``conf/app.yaml``, ``conf/bench.yaml``,
``conf/demo.yaml``):
dataclasses registered with Hydra's ConfigStore (:func:`register`) and named first in each config's defaults list,
so that Hydra itself refuses a value of the wrong type, naming the key (:func:`sdn3d.cli._config.compose_config`
words it as ``<key> must be <kind>, got <value>``).

Every field is ``MISSING`` here: the values (and their comments) live in the YAML files alone; a schema gives
types. Mode fields (``proposals``, ``appearance``, ``compose``, ``photo.fill``, ``scene``) are strings here and
become enums at the edge (:func:`sdn3d.editing.settings.session_settings`, :meth:`sdn3d.proposals.Proposals.parse`):
OmegaConf matches an Enum field by member name (``SEMANTIC``), not by the lower-case value users write.
"""

from dataclasses import dataclass, field
from typing import Any, List, Optional  # noqa: UP035

from omegaconf import MISSING

__all__ = ["EditSchema", "AppSchema", "BenchSchema", "DemoSchema", "register"]


@dataclass
class FitSchema:
    """``box_objects.fit``: :class:`sdn3d.geometric.fit.FitSettings`' fields as conf/edit.yaml lists them (its order:
    edit.json records the config in it), typed as FitSettings types them (``silhouette`` is not offered)."""

    camera_height: float = MISSING
    coarse_size: int = MISSING
    coarse_steps: int = MISSING
    coarse_faces: int = MISSING
    coarse_survivors: int = MISSING
    fine_size: int = MISSING
    fine_steps: int = MISSING
    fine_faces: int = MISSING
    keep: int = MISSING
    tie: float = MISSING
    facing_tie: float = MISSING
    mirror: bool = MISSING
    appearance: bool = MISSING
    cut_inward: float = MISSING
    lr: float = MISSING
    margin: float = MISSING
    sigma: float = MISSING
    yaw_reg: float = MISSING
    lane_reg: float = MISSING
    proposal_lane_reg: float = MISSING
    lane_width_deg: float = MISSING
    dims_reg: float = MISSING
    shape_reg: float = MISSING
    template_size_reg: float = MISSING
    ffd_reg: float = MISSING
    ffd_step: float = MISSING
    cull_backfaces: bool = MISSING
    parts: int = MISSING
    poor_iou: float = MISSING
    join_overlap: Optional[float] = MISSING
    unsure_vehicle: Optional[float] = MISSING


@dataclass
class InputSchema:
    image: Optional[str] = MISSING
    intrinsics: Any = MISSING  # {fx, fy, cx, cy[, width, height]}: checked by sdn3d.math3d.camera.Intrinsics
    camera: Optional[str] = MISSING
    frame: Any = MISSING  # a key (string) or an index (integer)


@dataclass
class BoxObjectsSchema:
    prior: Any = MISSING  # auto | true | false
    iterations: int = MISSING
    refine_masks: bool = MISSING
    fit: FitSchema = field(default_factory=FitSchema)


@dataclass
class CheckpointsSchema:
    semantic: Optional[str] = MISSING
    geometric: Optional[str] = MISSING
    textural: Optional[str] = MISSING


@dataclass
class GeometricSchema:
    crop_size: Optional[int] = MISSING
    margin: Optional[float] = MISSING
    min_pixels: int = MISSING
    traffic: str = MISSING


@dataclass
class SemanticSchema:
    size: Optional[List[int]] = MISSING  # noqa: UP006


@dataclass
class EditSchema:
    """``conf/edit.yaml``."""

    data: Any = None  # a dataset group (conf/data/*), or null
    renderer: Any = MISSING
    refine: Any = MISSING
    input: InputSchema = field(default_factory=InputSchema)
    image_size: Optional[List[int]] = MISSING
    edits: Optional[str] = MISSING
    list: bool = MISSING
    entry: int = MISSING
    frame_size: Optional[List[int]] = MISSING
    strict: bool = MISSING
    pick_radius: Optional[float] = MISSING
    max_ops: int = MISSING
    proposals: str = MISSING
    fit_proposals: bool = MISSING
    box_objects: BoxObjectsSchema = field(default_factory=BoxObjectsSchema)
    run: Optional[str] = MISSING
    checkpoints: CheckpointsSchema = field(default_factory=CheckpointsSchema)
    code_bank: Optional[str] = MISSING
    geometric: GeometricSchema = field(default_factory=GeometricSchema)
    semantic: SemanticSchema = field(default_factory=SemanticSchema)
    appearance: str = MISSING
    photo: Any = MISSING  # checked by sdn3d.editing.photo.settings.PhotoSettings.from_mapping (one home)
    compose: str = MISSING
    compose_dilate_px: int = MISSING
    compose_feather_px: int = MISSING
    diagnostics: bool = MISSING
    output_dir: str = MISSING
    overwrite: bool = MISSING
    device: str = MISSING
    threads: Optional[int] = MISSING
    progress: Any = MISSING  # true | false | auto
    seed: int = MISSING


@dataclass
class AppSchema(EditSchema):
    """``conf/app.yaml``: ``conf/edit.yaml`` and the server's keys (named after ``edit`` in its defaults list, so
    every field the edit config set is kept: ``data`` too)."""

    data: Any = MISSING
    host: str = MISSING
    port: int = MISSING
    max_upload_bytes: int = MISSING
    max_upload_pixels: int = MISSING
    max_edit_pixels: int = MISSING
    max_request_bytes: int = MISSING
    max_sessions: int = MISSING
    session_idle_s: int = MISSING
    open_browser: bool = MISSING


@dataclass
class BenchCheckpointsSchema(CheckpointsSchema):
    textural_2d: Optional[str] = MISSING


@dataclass
class BenchSchema:
    """``conf/bench.yaml``."""

    data: Any = MISSING
    benchmark: Optional[str] = MISSING
    image_size: Optional[List[int]] = MISSING
    scene: str = MISSING
    proposals: Any = MISSING  # one source or a list of them
    fit_proposals: bool = MISSING
    run: Optional[str] = MISSING
    checkpoints: BenchCheckpointsSchema = field(default_factory=BenchCheckpointsSchema)
    geometric: GeometricSchema = field(default_factory=GeometricSchema)
    semantic: SemanticSchema = field(default_factory=SemanticSchema)
    lpips_weights: Optional[str] = MISSING
    frame_size: List[int] = MISSING
    strict: bool = MISSING
    pick_radius: Optional[float] = MISSING
    modify_anchor: str = MISSING
    include_identity: bool = MISSING
    limit: Optional[int] = MISSING
    allow_empty: bool = MISSING
    examples: int = MISSING
    compose: Any = MISSING  # one mode or a list of them
    photo: Any = MISSING  # as sdn3d-edit's photo.* (PhotoSettings.from_mapping checks it)
    compose_dilate_px: int = MISSING
    compose_feather_px: int = MISSING
    counterfactual: bool = MISSING
    counterfactual_sources: Any = MISSING  # one source or a list of them, or null
    counterfactual_fills: List[str] = MISSING
    counterfactual_kinds: List[str] = MISSING
    counterfactual_reference: str = MISSING
    output_dir: str = MISSING
    overwrite: bool = MISSING
    device: str = MISSING
    threads: Optional[int] = MISSING


@dataclass
class DemoTrainSchema:
    branches: List[str] = MISSING
    parallel: bool = MISSING
    experiment: Any = MISSING  # {branch: sdn3d-train experiment}: free-form, read per branch
    common: List[str] = MISSING
    semantic: List[str] = MISSING
    geometric: List[str] = MISSING
    textural: List[str] = MISSING


@dataclass
class DemoBenchSchema:
    limit: Optional[int] = MISSING
    examples: int = MISSING
    proposals: List[str] = MISSING


@dataclass
class DemoEditsSchema:
    frame: Optional[str] = MISSING
    proposals: str = MISSING
    zoom: float = MISSING
    angles_deg: List[float] = MISSING
    recolor: str = MISSING
    appearance: str = MISSING
    photo: Any = MISSING  # photo.*: checked by sdn3d.editing.photo.settings.PhotoSettings.from_mapping
    compose: str = MISSING


@dataclass
class DemoSchema:
    """``conf/demo.yaml`` and its ``budget`` group (``conf/budget/*.yaml``, merged at the top level)."""

    output_dir: str = MISSING
    data_dir: str = MISSING
    seed: int = MISSING
    threads: int = MISSING
    lanes: int = MISSING
    semantic_threads_after_epochs: Optional[int] = MISSING
    device: str = MISSING
    workers: int = MISSING
    render_size: Optional[List[int]] = MISSING
    synth: Any = MISSING  # conf/synth.yaml's fields: checked by sdn3d.data.synth.SynthConfig
    train: DemoTrainSchema = field(default_factory=DemoTrainSchema)
    bench: DemoBenchSchema = field(default_factory=DemoBenchSchema)
    edits: DemoEditsSchema = field(default_factory=DemoEditsSchema)
    budget_name: str = MISSING
    gpu_budget: bool = MISSING


SCHEMAS = {"edit_schema": EditSchema, "app_schema": AppSchema, "bench_schema": BenchSchema,
           "demo_schema": DemoSchema}

#: The schemas each config of ``conf/`` names in its defaults, its own and those of the configs it composes
#: (``app`` composes ``edit``); a config absent here names none. Storing one costs milliseconds (OmegaConf builds
#: the dataclass's node): a call stores only its config's.
CONFIG_SCHEMAS: dict[str, tuple[str, ...]] = {"edit": ("edit_schema",), "app": ("edit_schema", "app_schema"),
                                              "bench": ("bench_schema",), "demo": ("demo_schema",)}


def register(config: str) -> None:
    """Store the schemas ``conf/<config>.yaml`` names (:data:`CONFIG_SCHEMAS`) in Hydra's ConfigStore; idempotent."""
    from hydra.core.config_store import ConfigStore

    store = ConfigStore.instance()
    for name in CONFIG_SCHEMAS.get(config, ()):
        store.store(name=name, node=SCHEMAS[name])
