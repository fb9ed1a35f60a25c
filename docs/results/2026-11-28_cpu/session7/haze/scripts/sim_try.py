# ruff: noqa: E402, E501, E701, E702
import sys

sys.path.insert(0, "/tmp/s7data/haze")
import sim


def plaus(c):
    f = c["fit"]; return all(-0.05 <= a + b <= 1.05 for a, b in zip(f["fog"], f["delta"], strict=False))


rows = sim.t1_rows() + sim.cf_rows()
for th in [float(x) for x in sys.argv[1:]]:
    sim.report(rows, lambda c, th=th: c.get("fog_vs_hz", 9) <= th, f"airlight <= {th}")
    sim.report(rows, lambda c, th=th: c.get("fog_vs_hz", 9) <= th and plaus(c), f"airlight <= {th} and plausible")
sim.report(rows, plaus, "plausible")
