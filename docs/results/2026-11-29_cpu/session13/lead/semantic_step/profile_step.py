# ruff: noqa: E401, E402, E701, E702, I001, F401, E731
import torch
from torch.profiler import profile, ProfilerActivity
from sdn3d.nets.drn import DRNSeg
torch.set_num_threads(1)
torch.manual_seed(0)
net = DRNSeg(13, instance_head=True, head_channels=64, decoder="skip", channels=[16,16,32,64,64,128,128,128])
x = torch.rand(8, 3, 96, 312)
opt = torch.optim.AdamW(net.parameters(), 1e-3)
def step():
    out = net(x)
    loss = sum(v.float().square().mean() for v in out.values())
    opt.zero_grad(); loss.backward(); opt.step()
step()
with profile(activities=[ProfilerActivity.CPU], record_shapes=True) as p:
    for _ in range(2): step()
print(p.key_averages(group_by_input_shape=True).table(sort_by="self_cpu_time_total", row_limit=22))
