"""Shared test settings: deterministic seeds and a small thread count (CI has 2 cores).

``scripts/test.sh`` runs the tests in two pytest-xdist worker processes (``--dist load``), so any test may run in
either, in any order, beside any other: a test keeps its files under ``tmp_path`` (session fixtures under
``tmp_path_factory``), listens on port 0, and sets up what it needs itself, never relying on another test having run
first in the same process (a structured config schema registered, a module imported, a cache filled).
"""

from __future__ import annotations

import os
import random
from pathlib import Path

import numpy as np
import pytest
import torch

# Only for the real Virtual KITTI frame 0006_30-deg-right_00043.png (678 kB, not shipped). The paper's
# benchmark files ship with the package: sdn3d.resources (paper_benchmark_path, paper_example_path).

# One intra-op thread by default: OpenMP worker threads spin-wait, and on a 2-core machine any
# other busy process makes multi-threaded small ops orders of magnitude slower. Benchmarks,
# not tests, measure multi-threaded speed. SDN3D_TEST_THREADS overrides.
torch.set_num_threads(int(os.environ.get("SDN3D_TEST_THREADS", "1")))


@pytest.fixture()
def one_torch_thread():
    """One torch thread for the test, whatever SDN3D_TEST_THREADS says (the synthetic generator's tests: two
    threads contend badly on a shared 2-core machine), restored afterwards."""
    previous = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(previous)


@pytest.fixture(autouse=True)
def _proposal_fit_only_where_tested(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    """The proposals' test-time fit costs about a second per car of the random-weight branches' scenes, and
    ``fit_proposals`` is on by default in every tool: a test that does not test it (marker ``fits``) gets each
    proposal's prediction back as the fit, recorded as not fitted. In-process calls only: a tool started as a
    subprocess fits for real."""
    if request.node.get_closest_marker("fits") is not None:
        return
    import sdn3d.derender as derendering
    from sdn3d.proposal_fit import ProposalFit

    def predictions_kept(intr, masks, ids, rows, geometry, settings, appearance=None, unsure=None, classes=None,
                         unsure_pixels=None, road=None, lane_reg=None):
        return tuple(g.clone() for g in geometry), [ProposalFit(int(i), None, True, None, "not fitted (test stub)")
                                                     for i in ids[rows].tolist()], None

    def boxes_fitted(intr, masks, ids, rows, geometry, settings, appearance, boxes, unsure=None,
                     classes=None, unsure_pixels=None, road=None, lane_reg=None):  # the boxes fitted for real
        from sdn3d.geometric.fit import fit_many

        return (*predictions_kept(intr, masks, ids, rows, geometry, settings),
                fit_many([boxes], intr, settings=settings)[0])

    monkeypatch.setattr(derendering, "fit_proposals", predictions_kept)
    monkeypatch.setattr(derendering, "fit_proposals_and_boxes", boxes_fitted)


@pytest.fixture(autouse=True)
def _seed_everything() -> None:
    random.seed(0)
    np.random.seed(0)
    torch.manual_seed(0)


@pytest.fixture(scope="session")
def real_vkitti_frame() -> Path:
    """The real Virtual KITTI frame ``0006_30-deg-right_00043.png`` (1242x375 RGB), shipped in ``tests/data``."""
    return Path(__file__).resolve().parent / "data" / "0006_30-deg-right_00043.png"


@pytest.fixture(scope="session")
def tiny_synth(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A tiny synthetic Virtual KITTI 1.3.1 dataset (1 world, 1 variation, 8 frames + 1 edit target, 160x64).

    With ``conf/data/synth.yaml``'s split: frames 0-3 train, 4 is the gap, 5 validates, 6-7 and the target test.

    Shared by the training tests of every branch; generated once per test session (~1 s).
    """
    from sdn3d.data.synth import SynthConfig, generate_dataset

    root = tmp_path_factory.mktemp("tiny_synth") / "vkitti"
    generate_dataset(SynthConfig(output_dir=str(root), seed=0, image_size=(160, 64), frames_per_sequence=8,
                                 cars_per_frame=(3, 5), edit_pairs=1, max_edit_operations=2))
    return root
