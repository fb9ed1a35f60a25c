#!/bin/bash
# held.sh: held-out seed 2107 (gen_t1.py, as 2097), measured once: base (main f42d17c) and final (this branch d45d9e3,
# code_g), Table 1 photo rows with semantic proposals and ground-truth masks (oracle), a de-render cache per code
cd /tmp/s10data/semflip
(./gtlane.sh /tmp/s10data/semflip/base hb 2107 semantic gt) > held_a.out 2>&1 &
(./gtlane.sh /tmp/s10data/semflip/code_g hg 2107 semantic gt) > held_b.out 2>&1 &
wait
for s in semantic gt; do ./diagall.sh hb2107_$s 2107 /tmp/s10data/semflip/base hb; ./diagall.sh hg2107_$s 2107 /tmp/s10data/semflip/code_g hg; done
