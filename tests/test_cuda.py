"""The same code on CUDA: renderers, de-render / edit / render and training agree with the CPU.

Skipped without a GPU (CI has none); run on a GPU machine with ``pytest tests/test_cuda.py``.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import torch
from helpers.tiny_models import geometric_net, textural_spec
from hydra import compose, initialize_config_dir

from sdn3d.data import vkitti1
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth
from sdn3d.derender import derender
from sdn3d.editing.apply import Rotate, Zoom, apply_edits
from sdn3d.editing.render import render
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.meshes import MeshBank
from sdn3d.models import Models
from sdn3d.render import RasterSettings, SoftSilhouetteSettings, rasterize_meshes, soft_silhouette
from sdn3d.scene.maps import scene_maps
from sdn3d.textural.renderer import TexturalRenderer

pytestmark = pytest.mark.skipif(not torch.cuda.is_available(), reason="needs a CUDA GPU")
CUDA = torch.device("cuda")
REPO = Path(__file__).resolve().parents[1]
SIZE = (160, 64)


def _posed_templates(count: int = 6) -> tuple[torch.Tensor, torch.Tensor]:
    bank = MeshBank.templates()
    ids = torch.arange(count) % len(bank)
    verts, faces = bank.verts[ids].clone(), bank.faces[ids]
    verts[..., 2] += torch.linspace(6.0, 30.0, count)[:, None]
    verts[..., 0] += torch.linspace(-3.0, 3.0, count)[:, None]
    return verts.float(), faces


def test_hard_rasterizer_matches_the_cpu():
    verts, faces = _posed_templates()
    K = torch.tensor([[110.0, 0.0, 79.5], [0.0, 110.0, 31.5], [0.0, 0.0, 1.0]])
    settings = RasterSettings(image_size=(64, 160))
    owner = torch.zeros(len(verts), dtype=torch.long)
    cpu = rasterize_meshes(verts, faces, K, settings, owner, 1)
    gpu = rasterize_meshes(verts.to(CUDA), faces.to(CUDA), K.to(CUDA), settings, owner.to(CUDA), 1)
    assert gpu.pix_to_face.device.type == "cuda"
    same = (gpu.pix_to_face.cpu() == cpu.pix_to_face).float().mean()
    assert same > 0.999  # ties on shared edges may resolve differently
    hit = cpu.pix_to_face >= 0
    torch.testing.assert_close(gpu.depth.cpu()[hit & (gpu.pix_to_face.cpu() == cpu.pix_to_face)],
                               cpu.depth[hit & (gpu.pix_to_face.cpu() == cpu.pix_to_face)], rtol=1e-4, atol=1e-4)


def test_soft_silhouette_and_its_gradient_match_the_cpu():
    verts, faces = _posed_templates(3)
    K = torch.tensor([[60.0, 0.0, 31.5], [0.0, 60.0, 31.5], [0.0, 0.0, 1.0]]).expand(3, 3, 3)
    settings = SoftSilhouetteSettings(image_size=(64, 64))
    grads = []
    for device in ("cpu", CUDA):
        v = verts.detach().clone().to(device).requires_grad_(True)
        sil = soft_silhouette(v, faces.to(device), K.to(device), settings)
        sil.square().sum().backward()
        grads.append((sil.detach().cpu(), v.grad.cpu()))
    torch.testing.assert_close(grads[1][0], grads[0][0], rtol=1e-3, atol=1e-3)
    torch.testing.assert_close(grads[1][1], grads[0][1], rtol=1e-2, atol=1e-2)


@pytest.fixture
def no_tf32():
    """Full float32 on the GPU: TF32 convolutions (the Ampere+ default) differ from the CPU by ~1e-3."""
    saved = torch.backends.cudnn.allow_tf32, torch.backends.cuda.matmul.allow_tf32
    torch.backends.cudnn.allow_tf32 = torch.backends.cuda.matmul.allow_tf32 = False
    yield
    torch.backends.cudnn.allow_tf32, torch.backends.cuda.matmul.allow_tf32 = saved


def test_derender_edit_render_on_cuda_match_the_cpu(tiny_synth, no_tf32):
    record = vkitti1.read_frames(tiny_synth)[4]
    frame = load_frame(record, SIZE, semantic=True, instances=True)
    torch.manual_seed(0)
    cpu_models = Models(None, GeometricPredictor(geometric_net()), TexturalRenderer(textural_spec()).eval(),
                        crop_size=32, margin=0.1)
    gpu_models = Models(None, GeometricPredictor(geometric_net()), TexturalRenderer(textural_spec()).eval(),
                        crop_size=32, margin=0.1)
    gpu_models.geometric.net.load_state_dict(cpu_models.geometric.net.state_dict())
    gpu_models.textural.load_state_dict(cpu_models.textural.state_dict())
    gpu_models.geometric.net.to(CUDA).eval()
    cpu_models.geometric.net.eval()
    gpu_models.textural.to(CUDA)
    images = []
    for models, bank in ((cpu_models, MeshBank.templates()), (gpu_models, MeshBank.templates().to(CUDA))):
        gt = ground_truth(record, (frame.intrinsics.width, frame.intrinsics.height))
        scene = derender(frame.image, frame.intrinsics, models, "gt", gt, min_pixels=1)
        obj = int(scene.objects.instance_id[0])
        edited = apply_edits(scene, [Rotate(obj, 0.5), Zoom(obj, 1.2)])
        maps = scene_maps(edited, bank, num_bins=models.textural.spec.pose_bins)
        assert maps.instance.device == bank.device
        images.append((scene, render(edited, models.textural, bank)))
    (cpu_scene, cpu_image), (gpu_scene, gpu_image) = images
    assert gpu_image.device.type == "cuda"
    torch.testing.assert_close(gpu_scene.objects.location, cpu_scene.objects.location, rtol=1e-3, atol=1e-3)
    assert (gpu_image.cpu() - cpu_image).abs().mean() < 2e-3


@pytest.mark.parametrize("branch", ["semantic", "geometric", "textural"])
def test_each_branch_trains_on_the_gpu(branch, tiny_synth, tmp_path):
    from lightning_modules.train import run_training

    tiny = {"semantic": ["datamodule.batch_size=2"],
            "geometric": ["datamodule.batch_size=4", "datamodule.crop_size=32", "datamodule.min_pixels=0"],
            "textural": ["datamodule.batch_size=1"]}[branch]
    run_dir = tmp_path / "run"
    overrides = [f"branch={branch}", "experiment=demo", "trainer=gpu", f"data.root={tiny_synth}",
                 "data.image_size=[160,64]", f"run_dir={run_dir}", f"summary_file={tmp_path / 's.jsonl'}",
                 "trainer.max_epochs=2", "trainer.limit_train_batches=2", "trainer.limit_val_batches=1",
                 "trainer.limit_test_batches=1", "trainer.enable_progress_bar=false", "~callbacks.progress_bar",
                 *tiny]
    if branch == "geometric":  # both stages: L_pred, then L_reproj + REINFORCE (soft silhouettes on the GPU)
        overrides += ["model.pred_epochs=1", "model.joint_epochs=1"]
    with initialize_config_dir(config_dir=str(REPO / "conf"), version_base="1.3"):
        cfg = compose("train", overrides=overrides)
    summary = run_training(cfg, [])
    assert summary["status"] == "ok" and summary["global_step"] >= 2
    metrics = json.loads((run_dir / "summary.json").read_text())["metrics"]
    assert metrics and all(v == v for v in metrics.values() if isinstance(v, float)), metrics  # no NaN
    ckpt = torch.load(run_dir / "checkpoints" / "last.ckpt", map_location="cpu", weights_only=True)
    assert any(v.dtype == torch.float32 for v in ckpt["state_dict"].values())
