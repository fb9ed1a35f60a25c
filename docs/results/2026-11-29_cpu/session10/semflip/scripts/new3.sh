#!/bin/bash
# new2.sh: this branch (code_g) Table 1 photo rows, semantic proposals, tuning 31/35/37/39, two chains
cd /tmp/s10data/semflip
(./gtlane.sh /tmp/s10data/semflip/code_g g 31 semantic; ./gtlane.sh /tmp/s10data/semflip/code_g g 37 semantic) > new3_a.out 2>&1 &
(./gtlane.sh /tmp/s10data/semflip/code_g g 35 semantic; ./gtlane.sh /tmp/s10data/semflip/code_g g 39 semantic) > new3_b.out 2>&1 &
wait
