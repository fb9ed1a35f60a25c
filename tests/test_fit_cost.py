"""The test-time fit's cost (issue 40: 10 objects at 624x192 within 3 s): the search's survivors, the fine stage's
simplified meshes, and one fit for several callers' objects (:func:`sdn3d.geometric.fit.fit_many`)."""

from __future__ import annotations

import dataclasses
import math

import pytest
import torch
from test_box_objects import HEIGHT, WORK, _render

import sdn3d.geometric.fit as fit_module
from sdn3d.geometric.fit import FitRequest, FitSettings, fit_many, fit_to_masks
from sdn3d.image_ops import mask_boxes

SMALL = FitSettings(coarse_steps=3, fine_steps=2, coarse_size=16, fine_size=24, coarse_survivors=0, parts=1)


@pytest.fixture(scope="module")
def two_cars():
    """Two cars apart on the road, each rendered alone: ``(masks (2, H, W), boxes (2, 4))``."""
    _, masks = _render([0, 3], [(4.0, 1.5, 1.7), (4.2, 1.45, 1.75)], [-1.3, 0.6],
                       [(-2.5, HEIGHT, 10.0), (2.5, HEIGHT, 12.0)])
    return masks, mask_boxes(masks).float()


def _rows_per_stage(monkeypatch) -> list[tuple[int, int]]:
    """``(hypotheses, steps)`` of every stage the fit runs, recorded as it runs."""
    calls: list[tuple[int, int]] = []
    stage = fit_module._stage

    def recorded(bank, template, *args, **kwargs):
        calls.append((len(template), args[7]))  # args: start, dims0, ry0, mask, ign, K, size, steps, ...
        return stage(bank, template, *args, **kwargs)

    monkeypatch.setattr(fit_module, "_stage", recorded)
    return calls


def test_the_search_goes_on_with_its_survivors_only_and_still_finds_the_car(two_cars, monkeypatch):
    masks, boxes = two_cars
    calls = _rows_per_stage(monkeypatch)
    settings = FitSettings(coarse_survivors=6)
    result = fit_to_masks(masks[1:], boxes[1:], WORK, start_ry=torch.tensor([0.8]), settings=settings)
    starts = len(fit_module.default_bank()) * len(fit_module.YAW_OFFSETS)
    # every start for a third of the steps, the 6 best for the rest, then the fine stage
    third = settings.coarse_steps // 3
    assert calls[:2] == [(starts, third), (6, settings.coarse_steps - third)] and len(calls) == 3
    assert float(result.iou[0]) > 0.85
    assert abs(math.remainder(float(result.ry[0]) - 0.6, 2 * math.pi)) < math.radians(20)
    calls.clear()
    fit_to_masks(masks[1:], boxes[1:], WORK, start_ry=torch.tensor([0.8]), settings=FitSettings(coarse_survivors=0))
    assert calls[0] == (starts, FitSettings().coarse_steps) and len(calls) == 2  # 0: every start to the end


def test_the_fine_stage_can_fit_simplified_meshes_and_measures_the_full_one(two_cars, monkeypatch):
    masks, boxes = two_cars
    banks = []
    stage = fit_module._stage

    def recorded(bank, *args, **kwargs):
        banks.append(int(bank.num_faces.max()))
        return stage(bank, *args, **kwargs)

    monkeypatch.setattr(fit_module, "_stage", recorded)
    result = fit_to_masks(masks[1:], boxes[1:], WORK, start_ry=torch.tensor([0.8]),
                          settings=FitSettings(fine_faces=500))
    full = int(fit_module.default_bank().num_faces.max())
    assert banks[-1] <= 500 < full
    assert float(result.iou[0]) > 0.85
    assert abs(math.remainder(float(result.ry[0]) - 0.6, 2 * math.pi)) < math.radians(20)
    with pytest.raises(ValueError, match="fine_faces"):
        FitSettings(fine_faces=2)
    with pytest.raises(ValueError, match="coarse_survivors"):
        FitSettings(coarse_survivors=-1)


def test_one_fit_for_two_callers_gives_each_its_own_rows_as_two_fits_would(two_cars, monkeypatch):
    """A request with predictions and a yaw belief, one with neither: fitted together, each gets what it would get
    alone (the same templates, yaws and places up to float sums), its notes and warnings by its own indices, and the
    fit runs its two stages once."""
    masks, boxes = two_cars
    thin = torch.zeros_like(masks[:1])
    thin[0, 30, 10:40] = True  # too thin to fit: the prediction is kept, with a note
    first = FitRequest(torch.cat([masks[:1], thin]), torch.cat([boxes[:1], torch.tensor([[10.0, 30.0, 40.0, 31.0]])]),
                       start_ry=torch.tensor([-1.2, 0.3]), start_dims=torch.tensor([[4.0, 1.5, 1.7], [4.0, 1.5, 1.7]]),
                       start_template=torch.tensor([0, 2]),
                       start_location=torch.tensor([[-2.4, HEIGHT, 10.2], [0.0, HEIGHT, 20.0]]),
                       yaw_belief=lambda ry: torch.cos(ry + 1.3))
    second = FitRequest(masks[1:], boxes[1:], ignore=masks[:1])
    alone = [fit_many([r], WORK, settings=SMALL)[0] for r in (first, second)]
    calls = _rows_per_stage(monkeypatch)
    together = fit_many([first, second], WORK, settings=SMALL)
    assert len(calls) == 2 and calls[0][0] == 3 * len(fit_module.default_bank()) * len(fit_module.YAW_OFFSETS)
    for one, both, n in zip(alone, together, (2, 1), strict=True):
        assert len(both.template) == n and torch.equal(one.template, both.template)
        assert torch.equal(one.fitted, both.fitted) and torch.equal(one.hypothesis, both.hypothesis)
        assert torch.allclose(one.ry, both.ry, atol=1e-3) and torch.allclose(one.location, both.location, atol=1e-2)
        assert torch.allclose(one.iou, both.iou, atol=0.02)
        assert one.notes == both.notes and one.warnings == both.warnings
    assert set(together[0].notes) == {1} and together[0].warnings[0].startswith("object 1:")
    assert not together[1].notes and float(together[1].iou[0]) > 0.7


def test_the_fit_runs_on_one_torch_thread_whatever_the_callers_count(two_cars, monkeypatch):
    """A stage's small tensor operations run on one torch thread (more threads only wait for each other): the fit at
    two threads is the fit at one, to the last bit, and the caller gets its thread count back."""
    masks, boxes = two_cars
    inside: list[int] = []
    adam = fit_module.adam_fit

    def recorded(*args, **kwargs):
        inside.append(torch.get_num_threads())
        return adam(*args, **kwargs)

    monkeypatch.setattr(fit_module, "adam_fit", recorded)
    before = torch.get_num_threads()
    try:
        results = []
        for threads in (1, 2):
            torch.set_num_threads(threads)
            results.append(fit_to_masks(masks[1:], boxes[1:], WORK, start_ry=torch.tensor([0.8]), settings=SMALL))
            assert torch.get_num_threads() == threads
    finally:
        torch.set_num_threads(before)
    assert inside and set(inside) == {1}
    one, two = results
    for name in ("template", "dims", "ry", "location", "phi", "iou", "loss"):
        assert torch.equal(getattr(one, name), getattr(two, name)), name


@pytest.mark.parametrize("ffd_step", [1.0, 0.1])
def test_the_ffd_moves_by_its_share_of_the_adam_step(two_cars, ffd_step):
    """Adam's first step moves every free value by about ``lr``; the FFD's control values by ``ffd_step`` of that
    (a full step on each of them swung the fine stage's loss)."""
    masks, boxes = two_cars
    settings = FitSettings(coarse_steps=1, fine_steps=1, coarse_size=16, fine_size=24, coarse_survivors=0,
                           ffd_step=ffd_step)
    result = fit_to_masks(masks[1:], boxes[1:], WORK, start_ry=torch.tensor([0.8]), settings=settings)
    moved = float(result.phi.abs().max())
    assert 0.5 * settings.lr * ffd_step < moved <= settings.lr * ffd_step * 1.001
    with pytest.raises(ValueError, match="ffd_step"):
        FitSettings(ffd_step=0.0)


def test_sdn3d_edit_lets_idle_openmp_threads_sleep_unless_told_otherwise():
    """``sdn3d-edit`` sets ``OMP_WAIT_POLICY=PASSIVE`` before torch loads OpenMP (spinning threads cost one 10-box
    edit 52-111 CPU seconds against 9 on a busy 2-core machine); a caller's own value wins."""
    import os
    import subprocess
    import sys

    code = "import os, sdn3d.cli.edit; print(os.environ['OMP_WAIT_POLICY'])"
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    policies = [subprocess.run([sys.executable, "-c", code], env={**env, **extra}, capture_output=True, text=True,
                               check=True).stdout.strip() for extra in ({}, {"OMP_WAIT_POLICY": "ACTIVE"})]
    assert policies == ["PASSIVE", "ACTIVE"]


def test_sdn3d_edit_imports_without_collecting():
    """``sdn3d-edit``'s imports (about a million long-lived objects, torch's most) run with the cyclic collector paused
    (0.14 CPU s of every call, issue 40): no collection runs once torch starts loading (compiling the module's own
    source may collect before); after the import the collector runs again, what the import made is in the oldest
    generation and nothing is left frozen (``gc.get_referrers`` sees it all); a caller that had stopped the collector
    keeps it stopped, and one that keeps objects frozen keeps them frozen."""
    import subprocess
    import sys

    code = ("import gc, sys\n"
            "runs = []\n"
            "gc.callbacks.append(lambda phase, info: runs.append(info['generation'])\n"
            "                    if phase == 'start' and 'torch' in sys.modules else None)\n"
            "gc.disable() if sys.argv[1] == 'off' else None\n"
            "gc.freeze() if sys.argv[1] == 'frozen' else None\n"
            "import sdn3d.cli.edit\n"
            "young = len(gc.get_objects(0)) + len(gc.get_objects(1))\n"
            "old = len(gc.get_objects(2))\n"
            "print(len(runs), gc.isenabled(), gc.get_freeze_count() > 0, young < 20000, old > 100000)")
    seen = {arg: subprocess.run([sys.executable, "-c", code, arg], capture_output=True, text=True, check=True)
            .stdout.split() for arg in ("on", "off", "frozen")}
    assert seen["on"] == ["0", "True", "False", "True", "True"]
    assert seen["off"] == ["0", "False", "False", "True", "True"]
    assert seen["frozen"][1:3] == ["True", "True"]  # the caller's objects stay frozen (and young, its business)


def test_sdn3d_edit_as_the_program_freezes_what_exists_and_a_caller_does_not(monkeypatch):
    """Run as the program (``main()`` without arguments: its process ends with the call), ``sdn3d-edit`` freezes every
    object that exists (no collection walks them again: the call's one full collection, 0.08 CPU s); called with its
    arguments (a test, an embedding program) it leaves the collector as it is."""
    import gc
    import sys

    import sdn3d.cli.edit as edit

    frozen_at_end: list[int] = []
    monkeypatch.setattr(edit, "_main", lambda argv: 0)
    monkeypatch.setattr(edit, "_end_process", lambda code: frozen_at_end.append(gc.get_freeze_count()))
    monkeypatch.setattr(sys, "argv", ["sdn3d-edit", "list=true"])
    before = gc.get_freeze_count()
    try:
        assert edit.main(["list=true"]) == 0 and gc.get_freeze_count() == before
        assert edit.main() == 0
        assert frozen_at_end and frozen_at_end[0] > max(before, 100000)
    finally:
        gc.unfreeze()


@pytest.mark.parametrize("cull", [True, False])
def test_adam_steps_draw_the_front_faces_and_the_ranking_every_face(two_cars, monkeypatch, cull):
    """``cull_backfaces``: every Adam step of both stages draws only the faces facing the camera; the losses that
    rank the hypotheses (each stage's last, no gradient) draw every face; off, every call draws every face."""
    masks, boxes = two_cars
    drawn: list[tuple[bool, bool]] = []  # (culled, with gradient)
    silhouette = fit_module.silhouette

    def recorded(kind, verts, faces, K, settings):
        drawn.append((settings.cull_backfaces, torch.is_grad_enabled()))
        return silhouette(kind, verts, faces, K, settings)

    monkeypatch.setattr(fit_module, "silhouette", recorded)
    settings = FitSettings(coarse_steps=3, fine_steps=2, coarse_size=16, fine_size=24, coarse_survivors=0,
                           cull_backfaces=cull)
    result = fit_to_masks(masks[:1], boxes[:1], WORK, start_ry=torch.tensor([-1.2]), settings=settings)
    assert len(drawn) == (3 + 1) + (2 + 1)  # two stages: their steps, then their ranking loss
    assert drawn == [(cull, True)] * 3 + [(False, False)] + [(cull, True)] * 2 + [(False, False)]
    assert float(result.iou[0]) > 0.5


def _same(a, b) -> bool:
    return all(torch.equal(getattr(a, k), getattr(b, k))
               for k in ("template", "dims", "ry", "location", "phi", "iou", "loss", "hypothesis"))


def test_the_fit_in_parts_is_each_part_fitted_alone_one_group_per_thread(two_cars, monkeypatch):
    """Up to ``parts`` groups of whole objects, one per torch thread the caller has, each on its own thread: each
    group's fit is its objects' fit alone (one group each), the same at 2 and 3 threads; on one thread one group."""
    import threading

    masks, boxes = two_cars
    ry = torch.tensor([-1.0, 0.8])
    settings = dataclasses.replace(SMALL, parts=2)
    threads, seen = torch.get_num_threads(), []
    stage = fit_module._stage

    def recorded(bank, template, *args, **kwargs):
        seen.append((threading.get_ident(), len(template)))
        return stage(bank, template, *args, **kwargs)

    monkeypatch.setattr(fit_module, "_stage", recorded)
    results = {}
    try:
        for count in (1, 2, 3):
            torch.set_num_threads(count)
            seen.clear()
            results[count] = fit_to_masks(masks, boxes, WORK, start_ry=ry, settings=settings)
            assert torch.get_num_threads() == count  # the caller's count given back
            others = {t for t, _ in seen} - {threading.get_ident()}
            assert len(seen) == 2 * min(count, 2) and bool(others) == (count > 1)  # each group on its own thread
            per = len(fit_module.default_bank()) * len(fit_module.YAW_OFFSETS)
            assert seen[0][1] == (2 if count == 1 else 1) * per  # the search's rows: both objects, or one
    finally:
        torch.set_num_threads(threads)
    assert _same(results[2], results[3])
    alone = [fit_to_masks(masks[i:i + 1], boxes[i:i + 1], WORK, start_ry=ry[i:i + 1], settings=SMALL) for i in (0, 1)]
    for key in ("template", "dims", "ry", "location", "phi", "iou", "loss", "hypothesis"):
        assert torch.equal(getattr(results[2], key), torch.cat([getattr(a, key) for a in alone])), key
    assert _same(results[1], fit_to_masks(masks, boxes, WORK, start_ry=ry, settings=SMALL))  # one thread: one group
    with pytest.raises(ValueError, match="parts"):
        FitSettings(parts=0)


def test_the_kernel_takes_the_callers_threads_inside_the_fits_one_torch_thread(two_cars, monkeypatch):
    """The fit's stages run torch on one thread, its fused soft-raster kernel on the caller's count (its sums do not
    depend on it: the fit is the same)."""
    import sdn3d.render.soft as soft

    if soft.soft_kernel() is None:
        pytest.skip("no C++ compiler: the PyTorch path draws")
    masks, boxes = two_cars
    counts: list[int] = []
    call = soft._call

    def recorded(kernel, direction, *args):
        counts.append(soft._KERNEL_THREADS.get() or torch.get_num_threads())
        return call(kernel, direction, *args)

    monkeypatch.setattr(soft, "_call", recorded)
    threads = torch.get_num_threads()
    settings = dataclasses.replace(SMALL, parts=1)
    try:
        torch.set_num_threads(1)
        one = fit_to_masks(masks, boxes, WORK, settings=settings)
        assert set(counts) == {1}
        counts.clear()
        torch.set_num_threads(2)
        two = fit_to_masks(masks, boxes, WORK, settings=settings)
        assert counts and set(counts) == {2}
    finally:
        torch.set_num_threads(threads)
    assert _same(one, two)
    with pytest.raises(ValueError, match="positive"), soft.kernel_threads(0):
        pass
