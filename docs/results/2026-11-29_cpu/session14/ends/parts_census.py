"""parts_census.py: per template, how much of the face area the synthetic generator's glass rule covers (a face whose
centre lies above the belt line and whose outward normal rises under 0.93, not a tyre) carries the loft's BODY label
(main's labels; the per-pixel rule of this branch is not in them)."""

from __future__ import annotations

import numpy as np

from sdn3d.meshes.parts import Part
from sdn3d.meshes.templates import TEMPLATE_NAMES, TEMPLATE_SPECS, template_arrays, template_parts
from sdn3d.meshes.vehicle_family import canonical_belt


def main() -> None:
    for name in TEMPLATE_NAMES:
        verts, faces = template_arrays(name)
        parts = template_parts(name)
        belt = canonical_belt(TEMPLATE_SPECS[name])
        a, b, c = (verts[faces[:, k]] for k in range(3))
        normal = np.cross(b - a, c - a)
        area = np.linalg.norm(normal, axis=1)
        normal /= np.maximum(area[:, None], 1e-12)
        centre = (a + b + c) / 3
        glass = (centre[:, 1] < belt) & (-normal[:, 1] < 0.93) & (centre[:, 1] > -0.49) & (parts != Part.TYRE)
        body = glass & (parts == Part.BODY)
        share = area[body].sum() / area[glass].sum()
        print(f"{name}: belt {belt:+.2f}, generator-glass area labelled body {share:.0%}")


if __name__ == "__main__":
    main()
