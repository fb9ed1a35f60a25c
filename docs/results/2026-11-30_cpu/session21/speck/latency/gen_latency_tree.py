"""The tree benchmarks/photo_latency.py generates when given no --data (seed 3, 1242x375, worlds 0001 and 0018),
written to OUT once so that profiles and identity checks draw the same 14 edits.

    python gen_latency_tree.py OUT
"""

import sys

from sdn3d.data.synth import SynthConfig, generate_dataset

generate_dataset(SynthConfig(output_dir=sys.argv[1], seed=3, image_size=(1242, 375), worlds=("0001", "0018"),
                             variations=("clone",), frames_per_sequence=12, edit_pairs=6, occluder_pairs=2, workers=1))
