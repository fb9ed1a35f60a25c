# usage: ab.sh OUTROOT  -- runs each photo spec once into OUTROOT/<spec>
set -e
for s in t1 t1_180 t2 t2_45 d1 d2; do
  .venv/bin/sdn3d-edit input.image=tests/data/0006_30-deg-right_00043.png edits=/work/notes/s35/photo/$s.yaml run=/tmp/w35/outputs/demo/runs proposals=boxes threads=1 output_dir=$1/$s overwrite=true progress=false 2>&1 | grep -o "photo [0-9]* ms" | sed "s/^/$s /"
done
