# ruff: noqa: E402, E501, E701, E702
"""synth.py: a rendered car 12-30 m ahead, its mask whole and with its bottom quarter cut; the fitted distance without and with the unsure band."""
import sys

import torch

sys.path.insert(0, "tests")
from test_box_objects import HEIGHT, WORK, _render

from sdn3d.geometric.fit import FitSettings
from sdn3d.proposal_fit import fit_proposals, unsure_below

torch.set_num_threads(1)
for z, frac_cut in [(20.0, 0.25), (30.0, 0.25), (12.0, 0.25)]:
    _, masks = _render([0], [(4.0, 1.5, 1.7)], [-1.5], [(0.5, HEIGHT, z)])
    rs = masks[0].any(1).nonzero().flatten()
    cut = masks.clone(); cut[0, int(rs.max()) - int(len(rs) * frac_cut) + 1:] = False
    geometry = (torch.tensor([0]), torch.tensor([[4.0, 1.5, 1.7]], dtype=torch.float64), torch.tensor([-1.5], dtype=torch.float64), torch.tensor([[0.5, HEIGHT, 1.6 * z]], dtype=torch.float64), torch.zeros(1, 64, 3))
    ids, rows = torch.tensor([13001]), torch.tensor([0]); st = FitSettings(camera_height=HEIGHT)
    full, _ = fit_proposals(WORK, masks, ids, rows, geometry, st)
    fullb, _ = fit_proposals(WORK, masks, ids, rows, geometry, st, unsure=unsure_below(masks))
    plain, _ = fit_proposals(WORK, cut, ids, rows, geometry, st)
    band, _ = fit_proposals(WORK, cut, ids, rows, geometry, st, unsure=unsure_below(cut))
    print(f"z {z} rows {len(rs)} cut {int(len(rs) * frac_cut)}: full {float(full[3][0,2]):.1f} full+band {float(fullb[3][0,2]):.1f} cut {float(plain[3][0,2]):.1f} cut+band {float(band[3][0,2]):.1f}")
