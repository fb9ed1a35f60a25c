# ruff: noqa: E501
"""gen.py OUT SEED KIND: a Table 1 tree of one kind alone (session 33), from the t1 recipe (gen_t1.py of session 9:
624x192, clone and rain, 40 frames a sequence, 6-14 cars a frame). KIND:
  deletes:   all five worlds (0001, 0002, 0006, 0018, 0020); 12 edit pairs a sequence with edit_delete_share=1.0
             and max_edit_operations=1 (every edit pair deletes one car: entries that delete 1-3 cars chain into one
             group per world when groups join entries sharing a car, as the smoke run on seed 33 showed); no occluder
             pairs;
  occluders: all five worlds (0001, 0002, 0006, 0018, 0020); no edit pairs; 5 occluder-removed pairs a sequence;
  moves:     all five worlds; 12 edit pairs a sequence with edit_delete_share=0 and max_edit_operations=1 (every edit
             pair moves, turns or zooms one car: kinds rotate, zoom and move); no occluder pairs."""
import sys
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

out, seed, kind = sys.argv[1], int(sys.argv[2]), sys.argv[3]
KINDS = {"deletes": dict(worlds=("0001", "0002", "0006", "0018", "0020"), edit_pairs=12, occluder_pairs=0,
                            edit_delete_share=1.0, max_edit_operations=1),
         "occluders": dict(worlds=("0001", "0002", "0006", "0018", "0020"), edit_pairs=0, occluder_pairs=5),
         "moves": dict(worlds=("0001", "0002", "0006", "0018", "0020"), edit_pairs=12, occluder_pairs=0,
                       edit_delete_share=0.0, max_edit_operations=1)}
t = time.time()
generate_dataset(SynthConfig(output_dir=out, seed=seed, image_size=(624, 192), variations=("clone", "rain"),
                             frames_per_sequence=40, cars_per_frame=(6, 14), workers=1, threads=1, overwrite=False,
                             **KINDS[kind]))
print("done", kind, time.time() - t)
