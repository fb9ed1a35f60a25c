"""make_ablation.py SRC_TREE OUT_TREE: a copy of SRC_TREE's src/ (and conf/) whose render_photo drops 3D-SDN's
removal parts one at a time, chosen by the environment (diagnosis only, never merged). ABL=
- sil: no fitted silhouette joins the hole;
- shadow: no shadow found around the fitted footprint joins it (nor its pieces past the hole);
- effects: the plain fill of the 2D baseline (no road colour, verge row, shadow keep-out or shadow; the silhouette
  stays);
- verge: the rays blend road and verge (no fitted ground row);
- keepout: shadowed road in the hole's ground rows is a source of the rays;
- keeppieces: only the shadow's pieces past the hole are kept out of the rays' sources;
- thin: no thin things in front kept;
- vp: no fitted yaw as the vanishing point's fallback;
several: comma-separated ("sil,effects,thin,vp": everything 3D off, which must equal the 2D paste on deletes)."""
import shutil
import sys

src, out = sys.argv[1], sys.argv[2]
shutil.rmtree(out, ignore_errors=True)
shutil.copytree(f"{src}/src", f"{out}/src")
shutil.copytree(f"{src}/conf", f"{out}/conf")
path = f"{out}/src/sdn3d/editing/photo/transfer.py"
text = open(path).read()
edits = [
    ("import math\n", "import math\nimport os\n\nABL = set(os.environ.get('ABL', '').split(','))\n"),
    ("    if effects:  # the removed objects' fitted silhouettes join the hole",
     "    if effects and 'sil' not in ABL:  # the removed objects' fitted silhouettes join the hole"),
    ("    if any_set(hole):  # thin things in front are put back over the fill",
     "    if any_set(hole) and 'thin' not in ABL:  # thin things in front are put back over the fill"),
    ("float(before.ry[gone_rows[0]]) if gone_rows else None)",
     "float(before.ry[gone_rows[0]]) if gone_rows and 'vp' not in ABL else None)"),
    ("        elif effects:  # the removed objects' shadows are relit or filled with the hole",
     "        elif effects and 'effects' not in ABL:  # the removed objects' shadows are relit or filled with the"
     " hole"),
    ("    elif settings.delete_shadow:\n        own = dark",
     "    elif settings.delete_shadow and 'shadow' not in ABL:\n        own = dark"),
    ("    if any_set(photo_source.in_front):  # (none found: nothing to put back)",
     "    if any_set(photo_source.in_front) and 'thin' not in ABL:  # (none found: nothing to put back)"),
    ("    keep_out = objects_px | _ground_rows(dark, hole, SHADOW_GROUND)\n",
     "    keep_out = objects_px | (_ground_rows(dark, hole, SHADOW_GROUND) if 'keepout' not in ABL else False)\n"
     "    keep_out = (objects_px | pieces) if 'keeppieces' in ABL else keep_out\n"
     "    ground_row = None if 'verge' in ABL else ground_row\n"),
]
for old, new in edits:
    assert text.count(old) == 1, old
    text = text.replace(old, new)
open(path, "w").write(text)
