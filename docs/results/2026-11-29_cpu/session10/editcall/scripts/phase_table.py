# ruff: noqa: E501
"""phase_table.py FILE.json ...: edit_cost.py's phases side by side, thread CPU s / process CPU s / wall s per cell."""
import json
import sys

files = sys.argv[1:]
data = {f: json.load(open(f)) for f in files}
keys = list(data[files[0]]["phases"].keys())
print("| phase | " + " | ".join(f.split("/")[-1][:-5] for f in files) + " |")
print("|---|" + "---|" * len(files))
print("| start-up (imports), CPU | " + " | ".join(f"{data[f]['startup_cpu_s']:.2f}" for f in files) + " |")
for k in keys:
    print(f"| {k} | " + " | ".join(f"{e['thread_cpu_s']:.2f} / {e['cpu_s']:.2f} / {e['wall_s']:.2f}" if (e := data[f]["phases"].get(k)) else "-" for f in files) + " |")
print("| whole process to the end of main: main thread CPU / process CPU / wall | " + " | ".join(f"{data[f]['main_thread_cpu_s']:.2f} / {data[f]['process_cpu_s']:.2f} / {data[f]['process_wall_s']:.2f}" for f in files) + " |")
print("| load average (1 min) | " + " | ".join(f"{data[f]['load_average'][0]:.1f}" for f in files) + " |")
