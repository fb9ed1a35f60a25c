#!/bin/bash
# base.sh: main f42d17c (base/) Table 1 photo rows, semantic proposals and ground-truth masks (oracle), tuning 31/35/37/39, two chains
cd /tmp/s10data/semflip
(./gtlane.sh /tmp/s10data/semflip/base b 31 semantic gt; ./gtlane.sh /tmp/s10data/semflip/base b 37 semantic gt) > base_a.out 2>&1 &
(./gtlane.sh /tmp/s10data/semflip/base b 35 semantic gt; ./gtlane.sh /tmp/s10data/semflip/base b 39 semantic gt) > base_b.out 2>&1 &
wait
