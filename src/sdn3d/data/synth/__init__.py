"""Synthetic street scenes written in the real Virtual KITTI 1.3.1 format (the embedded default data).

Every frame is a 3D scene (road, scenery, cars from the held-out vehicle family or the 8 templates, FFD)
rendered by the project's hard rasterizer, so RGB, classes, instances, depth and the motgt
annotations agree exactly. Modules: ``layout`` (worlds, cars, camera), ``scenery`` (static
meshes), ``appearance`` (lighting and textures per variation), ``scene_render`` (one frame),
``stats`` (2D boxes, truncation, occupancy), ``writer`` (file format), ``edits`` (benchmark
pairs), ``generate`` (the whole dataset).
"""

from sdn3d.data.synth.generate import (
    BENCHMARK_NAME,
    MANIFEST_NAME,
    SynthConfig,
    generate_dataset,
    generate_sequences,
)
from sdn3d.data.synth.layout import VARIATIONS, World, build_world, frame_objects
from sdn3d.data.synth.scene_render import RenderedFrame, render_frame

__all__ = [
    "SynthConfig",
    "generate_dataset",
    "generate_sequences",
    "BENCHMARK_NAME",
    "MANIFEST_NAME",
    "VARIATIONS",
    "World",
    "build_world",
    "frame_objects",
    "RenderedFrame",
    "render_frame",
]
