#!/bin/bash
# semthreads.sh: is the semantic training thread-count independent? 6 steps of the demo's semantic recipe at threads
# 1 and 2 (session 11's idle demo data, seed 0), then the two last.ckpt state dicts compared tensor by tensor.
for T in 1 2; do
  PYTHONPATH=/work/wt/speed/src:/work/wt/speed OMP_NUM_THREADS=$T SDN3D_CONFIG_DIR=/work/wt/speed/conf nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.train branch=semantic experiment=demo_short data.root=/tmp/s11data/demo_final/data seed=0 threads=$T datamodule.num_workers=0 run_dir=/tmp/s12data/speed/semt$T trainer.max_epochs=1 trainer.limit_train_batches=6 trainer.num_sanity_val_steps=0 trainer.enable_progress_bar=false '~callbacks.progress_bar' summary_file=/tmp/s12data/speed/semt$T.jsonl > /tmp/s12data/speed/semt$T.log 2>&1
done
/work/main/.venv/bin/python -c "
import torch
a=torch.load('/tmp/s12data/speed/semt1/checkpoints/last.ckpt',weights_only=False)['state_dict']; b=torch.load('/tmp/s12data/speed/semt2/checkpoints/last.ckpt',weights_only=False)['state_dict']
d=[k for k in a if not torch.equal(a[k],b[k])]; print(len(a),'tensors;', len(d),'differ; largest difference', max(float((a[k].float()-b[k].float()).abs().max()) for k in d) if d else 0)"
