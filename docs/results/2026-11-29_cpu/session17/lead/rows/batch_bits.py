# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""batch_bits.py [THREADS]: does one row's output of the demo's geometric net depend on the batch? The same crop at row 0
of batches of 8 with other companions and places, and in batches of 1-16 copies (max |difference| to batch 8)."""
import sys, time, torch, glob
from sdn3d.geometric.predict import GeometricPredictor
torch.set_num_threads(int(sys.argv[1]) if len(sys.argv) > 1 else 1)
p = GeometricPredictor.from_checkpoint("/tmp/s11data/demo/out/runs/geometric/checkpoints/inference.pt")
torch.manual_seed(0)
s = 64
crop = torch.rand(16, 3, s, s); box = (torch.rand(16, 4) * 100 + torch.tensor([100., 100, 250, 200])); intr = torch.tensor([[700., 700, 620, 180]]).expand(16, 4).clone()
def run(idx):
    with torch.no_grad():
        return p.net(crop[idx], box[idx], intr[idx])
ref = run([0] + [1]*7)
for idx in ([0, 2, 3, 4, 5, 6, 7, 8], [0] + [9]*7, [3, 0, 4, 5, 6, 7, 8, 9], [5, 6, 7, 0, 1, 2, 3, 4]):
    out = run(idx); j = idx.index(0)
    print(idx, max(float((out[k][j] - ref[k][0]).abs().max()) for k in ref))
for b in (1, 2, 4):
    out = run([0] * b)
    print("batch", b, max(float((out[k][0] - ref[k][0]).abs().max()) for k in ref))
for b in (3, 5, 6, 7, 9, 12, 16):
    out = run([0] * b)
    print("batch", b, max(float((out[k][0] - ref[k][0]).abs().max()) for k in ref))
