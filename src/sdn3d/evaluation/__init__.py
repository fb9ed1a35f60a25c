"""Measuring the system: image metrics (``image_metrics``), the editing benchmark of the paper's Table 1
(``edit_benchmark``) and its 2D / 2D+ baselines (``baselines``)."""
