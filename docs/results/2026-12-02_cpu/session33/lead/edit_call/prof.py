# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
import cProfile, pstats, sys, time
t = time.perf_counter()
import sdn3d.cli.edit as E
print("import", time.perf_counter() - t, file=sys.stderr)
IMG = "/tmp/s33/t1_31/vkitti_1.3.1_rgb/0001/clone/00000.png"
SPEC = "/work/main/docs/results/2026-12-01_cpu/session30/lead/edit_call/spec31_w30.yaml"
sys.argv = ["sdn3d-edit", f"input.image={IMG}", "threads=2", "run=/tmp/s33/democlone/outputs/demo/runs",
            f"edits={SPEC}", f"output_dir=/tmp/s33/editcall/out_{sys.argv[1]}", "overwrite=true"]
pr = cProfile.Profile()
pr.enable()
try:
    E.main(sys.argv[1:])
except SystemExit:
    pass
pr.disable()
pr.dump_stats(f"/tmp/s33/editcall/{sys.argv[0] if False else 'prof'}.out")
