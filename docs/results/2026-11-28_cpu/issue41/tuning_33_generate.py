"""The seed-33 tuning tree of issue 41 (clone and fog, counterfactual turns and deletes); OUT as the argument."""

import sys

from sdn3d.data.synth import SynthConfig, generate_dataset

generate_dataset(SynthConfig(output_dir=sys.argv[1], seed=33, image_size=(624, 192), worlds=("0001", "0002"),
                             variations=("clone", "fog"), frames_per_sequence=30, edit_pairs=0, occluder_pairs=0,
                             workers=1, threads=1, counterfactual_cars=4, counterfactual_turns=(15, 45, 90, 180),
                             overwrite=True))
