#!/bin/bash
# held.sh: held-out seed 2093 (generated with gen_t1.py, as 2081), measured once: base (main a03af56) and final (396e0ef), three Table 1 photo rows; the de-rendered scenes cached by the base rows and reused by the final rows (the diff touches only editing/photo/transfer.py, which the de-render does not import)
cd /tmp/s9data/t1rotate
(./run.sh /tmp/s9data/t1rotate/base h_base_gt /tmp/s9data/t1rotate/t1_2093 gt derender /tmp/s9data/t1rotate/cache_held_2093 8; ./run.sh /tmp/s9data/t1rotate/final h_final_gt /tmp/s9data/t1rotate/t1_2093 gt derender /tmp/s9data/t1rotate/cache_held_2093 8; ./run.sh /tmp/s9data/t1rotate/base h_base_oracle /tmp/s9data/t1rotate/t1_2093 gt oracle /tmp/s9data/t1rotate/cache_held_2093 4) > held_a.out 2>&1 &
(./run.sh /tmp/s9data/t1rotate/base h_base_semantic /tmp/s9data/t1rotate/t1_2093 semantic derender /tmp/s9data/t1rotate/cache_held_2093 8; ./run.sh /tmp/s9data/t1rotate/final h_final_semantic /tmp/s9data/t1rotate/t1_2093 semantic derender /tmp/s9data/t1rotate/cache_held_2093 8; ./run.sh /tmp/s9data/t1rotate/final h_final_oracle /tmp/s9data/t1rotate/t1_2093 gt oracle /tmp/s9data/t1rotate/cache_held_2093 4) > held_b.out 2>&1 &
wait
