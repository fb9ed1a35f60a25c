# ruff: noqa: E402, E501, E701, E702
import json
import sys

for f in sys.argv[1:]:
    d = json.load(open(f)); print(f.split('/')[-1], 'load', [round(x, 1) for x in d['load_average']], 'startup', d['startup_cpu_s'], 'process cpu/wall', d['process_cpu_s'], d['process_wall_s'])
    for k, v in d['phases'].items(): print(f"  {k[:55]:<55} {v['cpu_s']:5.2f} {v['wall_s']:5.2f}")
