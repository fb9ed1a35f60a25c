"""make_variant.py SRC_TREE OUT_TREE: a copy of SRC_TREE's src/ and conf/ (the branch's code, 4749dcb) whose keep-out
of shadowed road from the rays' sources also takes, with KEEP_REACH=R in the environment, the shadowed road pieces
that touch the hole's shadow and lie wholly within R of the hole's height of it (fill.shadow_pieces with reach R; the
shadow's pieces filled after the hole use photo.shadow_reach, 0.1), from KEEP_GROUND of the hole's height down (default
0.5, SHADOW_GROUND; 0: every row, and those pieces then kept out on every row): a tuning variant, diagnosis only."""
import shutil
import sys

src, out = sys.argv[1], sys.argv[2]
shutil.rmtree(out, ignore_errors=True)
shutil.copytree(f"{src}/src", f"{out}/src")
shutil.copytree(f"{src}/conf", f"{out}/conf")
path = f"{out}/src/sdn3d/editing/photo/transfer.py"
text = open(path).read()
edits = [
    ("import math\n", "import math\nimport os\n\nKEEP_REACH = float(os.environ.get('KEEP_REACH', '0'))\n"
     "KEEP_GROUND = float(os.environ.get('KEEP_GROUND', '0.5'))\n"),
    ("    keep_out = objects_px | _ground_rows(_removed_shadow(dark, search, pieces), hole, SHADOW_GROUND)\n",
     "    wide = shadow_pieces(dark, hole, KEEP_REACH, KEEP_GROUND) if KEEP_REACH > 0 else pieces\n"
     "    keep_out = objects_px | _ground_rows(_removed_shadow(dark, search, pieces), hole, SHADOW_GROUND) | wide\n"),
]
for old, new in edits:
    assert text.count(old) == 1, old
    text = text.replace(old, new)
open(path, "w").write(text)
