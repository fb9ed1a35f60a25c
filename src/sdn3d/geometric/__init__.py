"""The geometric branch of 3D-SDN: per-object 3D attributes, mesh choice and FFD from a masked crop.

Plain PyTorch (no Lightning): the network (:class:`GeometricNet`), its losses (L_pred, L_reproj,
REINFORCE for the mesh choice), Table-2 metrics, a checkpoint predictor, per-image refinement by
reprojection (Cityscapes), and the independent Deep3DBox baseline of Table 2 (:class:`Deep3DBoxNet`,
MultiBin orientation). Training orchestration
lives in ``lightning_modules.geometric``.

The Table-2 metrics live in :mod:`sdn3d.geometric.metrics` and are not re-exported here: they need
torchmetrics, whose import alone takes 1-2 s on a CPU, and inference (the predictor, ``sdn3d-edit``) never
imports it.
"""

from sdn3d.geometric.decode import decode_outputs, template_distribution
from sdn3d.geometric.deep3dbox_net import Deep3DBoxNet, decode_deep3dbox
from sdn3d.geometric.losses import (
    PRED_KEYS,
    ffd_regularizer,
    outside_image_mask,
    prediction_loss,
    prediction_losses,
    render_silhouettes,
    reprojection_error,
)
from sdn3d.geometric.model import OUTPUT_KEYS, GeometricNet, box_features
from sdn3d.geometric.multibin import decode_multibin, encode_multibin, multibin_losses
from sdn3d.geometric.predict import GeometricPredictor, net_kwargs_from_hparams
from sdn3d.geometric.refine import RefineResult, RefineSettings, refine_by_reprojection
from sdn3d.geometric.reinforce import (
    BASELINES,
    MovingAverageBaseline,
    expected_reward_loss,
    leave_one_out_baseline,
    reinforce_loss,
    sample_templates,
)

__all__ = [
    "GeometricNet",
    "box_features",
    "OUTPUT_KEYS",
    "decode_outputs",
    "template_distribution",
    "net_kwargs_from_hparams",
    "GeometricPredictor",
    "PRED_KEYS",
    "prediction_losses",
    "prediction_loss",
    "ffd_regularizer",
    "outside_image_mask",
    "reprojection_error",
    "render_silhouettes",
    "BASELINES",
    "sample_templates",
    "reinforce_loss",
    "expected_reward_loss",
    "leave_one_out_baseline",
    "MovingAverageBaseline",
    "RefineSettings",
    "RefineResult",
    "refine_by_reprojection",
    "Deep3DBoxNet",
    "decode_deep3dbox",
    "encode_multibin",
    "decode_multibin",
    "multibin_losses",
]
