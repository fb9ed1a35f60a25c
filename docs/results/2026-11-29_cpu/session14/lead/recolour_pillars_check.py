# ruff: noqa: E402, I001
"""The lead's check that the recolour test fails on the ends branch's recolour (PhotoSource.face_parts patched to the
greenhouse part map): prints the blue share on the pillars, fixed and patched."""
import sdn3d.editing.photo.transfer as t
from sdn3d.meshes.parts import Part
import tests.test_photo_parts as m
scene = m._scene([m.BEHIND])
image, covered, parts = m._painted(scene, (0.06, 0.06, 0.07))
faces = t.PhotoSource(image, m.FRAME, scene, settings=m.PARTS).face_parts().view(parts.shape)
pillars = covered & (parts == int(Part.GLASS)) & (faces == int(Part.BODY))
for label, patch in (("fixed", False), ("ends-branch recolour", True)):
    if patch:
        t.PhotoSource.face_parts = lambda self: self.parts
    r = t.render_photo(image, m.FRAME, scene, scene, settings=m.PARTS, recolor={12001: (0.1, 0.2, 0.9)})
    blue = r.image[2] - r.image[0] > 0.2
    print(label, "pillars", int(pillars.sum()), "blue share on pillars", round(float(blue[pillars].float().mean()), 3))
