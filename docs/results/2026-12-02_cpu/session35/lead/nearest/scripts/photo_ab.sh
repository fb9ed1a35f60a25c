# usage: photo_ab.sh ROUNDS OUTFILE -- the photo stage's ms per edit, main's HEAD (base) against the working tree
# (new), part smoothing on, and the working tree with smoothing off; variants alternated within each round.
cd /work/main
for r in $(seq 1 $1); do
  for s in t1 t1_180 t2 t2_45 d1; do
    for v in base new new_off; do
      case $v in base) pp=/tmp/s35_base/src; ps=true;; new) pp=/work/main/src; ps=true;; new_off) pp=/work/main/src; ps=false;; esac
      ms=$(PYTHONPATH=$pp .venv/bin/python -m sdn3d.cli.edit input.image=tests/data/0006_30-deg-right_00043.png edits=/work/notes/s35/photo/$s.yaml run=/tmp/w35/outputs/demo/runs proposals=boxes threads=1 output_dir=/tmp/s35_ab/$v/$s overwrite=true progress=false photo.part_smoothing=$ps 2>&1 | grep -o "photo [0-9]* ms" | grep -o "[0-9]*")
      echo "$r $s $v $ms" >> $2
    done
  done
done
