# ruff: noqa: E401, E402, E701, E702, I001, F401, E731
import time, torch, sys
from sdn3d.nets.drn import DRNSeg
torch.set_num_threads(1)
torch.manual_seed(0)
net = DRNSeg(13, instance_head=True, head_channels=64, decoder="skip", channels=[16,16,32,64,64,128,128,128])
x = torch.rand(8, 3, 96, 312)
opt = torch.optim.AdamW(net.parameters(), 1e-3)
def step(fmt):
    xx = x.contiguous(memory_format=fmt)
    out = net(xx)
    loss = sum(v.float().square().mean() for v in (out.values() if isinstance(out, dict) else [out]))
    opt.zero_grad(); loss.backward(); opt.step()
for fmt_name in sys.argv[1:]:
    fmt = torch.channels_last if fmt_name == "cl" else torch.contiguous_format
    net.to(memory_format=fmt)
    step(fmt)
    t = time.process_time()
    for _ in range(8): step(fmt)
    print(fmt_name, (time.process_time() - t) / 8, "s/step")
