#!/bin/bash
# held.sh: held-out seed 2097 (gen_t1.py, as 2093), measured once: base (main fc689d8) and final (this branch), Table 1 photo rows
# gt masks and semantic (derender, a cache per code), then the ground-truth geometry row (scene=oracle; the lamp cue is not used there)
cd /tmp/s9data/fogflip
(./gtlane.sh /tmp/s9data/fogflip/base hb 2097 gt semantic; ./run.sh /tmp/s9data/fogflip/base hb2097_oracle /tmp/s9data/fogflip/t1_2097 gt oracle /tmp/s9data/fogflip/cache_hb_2097 0) > held_a.out 2>&1 &
(./gtlane.sh /tmp/s9data/fogflip/final hf 2097 gt semantic; ./run.sh /tmp/s9data/fogflip/final hf2097_oracle /tmp/s9data/fogflip/t1_2097 gt oracle /tmp/s9data/fogflip/cache_hf_2097 0) > held_b.out 2>&1 &
wait
