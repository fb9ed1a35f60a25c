"""The photo appearance: every edited object drawn with the input photo's own pixels, carried through its fitted
3D shape.

The textural generator re-synthesises an edited car from a five-number code; at CPU budgets it draws a blob.
``appearance='photo'`` (the default of ``sdn3d-edit``, :func:`sdn3d.editing.render.edit_image` and the demo's
grids) draws nothing from a code. At the **input's resolution** (:class:`~sdn3d.editing.frame.PixelFrame` gives the
input camera, :func:`input_intrinsics`):

1. *Who owns each pixel.* Objects that stay where they were keep their input pixels (their working-size
   masks, upsampled). Moved, turned, zoomed and duplicated objects are rasterized at their new pose
   (:func:`sdn3d.render.rasterize_meshes`, one call) and cover a pixel where they are nearer than the
   object that stays there (its rendered depth in the source rasterization, else its centre's): the edited
   scene's z-buffer decides who is in front.
2. *Vacated pixels* (the source footprint of every moved or deleted object, a few pixels around it, and a
   band of road below it for its old contact shadow) are filled (:data:`FILL_METHODS`; the default ``rays``,
   :mod:`~sdn3d.editing.photo.road`: along the lines through the road's vanishing point, so lane markings and
   verges run on through the hole, the removed car's shadow filled with it; or OpenCV's Telea, PatchMatch, the
   generator's background), before anything is drawn over them.
3. *Transfer.* For each pixel an edited object covers, the surface point (face and barycentrics) is carried
   to the object's source pose (same face, same barycentrics: edits are rigid), projected into the input and
   sampled there (bilinear; from a pre-filtered pyramid level when the car got smaller, so it does not
   alias), but only if that point was visible in the input: the source rasterization shows the same object
   there within :attr:`PhotoSettings.depth_tolerance`, and the pixel is inside the object's instance mask,
   eroded (no other object covers it). Else its **mirror image** across the vehicle's left-right plane
   (``z = 0`` of the canonical frame; templates and FFD are symmetric) is tried the same way. What is still
   unseen is drawn part by part (``unseen='parts'``, the default): the same part seen elsewhere on the car, from
   its input pixels nearest in the car's frame and in the direction they faced (their shading comes with them);
   a part never seen takes its default colour, the body the car's own body colour. An object amodally completed
   behind a deleted one (:func:`sdn3d.editing.apply.apply_edits`) has its freed pixels drawn the same way at its own
   pose.
4. *Shading follows the pose* (:func:`fit_light`, with :attr:`PhotoSettings.relight`, off by default: on exact
   turn pairs it cost 1-2 dB): one directional light and an ambient term are fitted to the visible car pixels of
   the input (per-object albedo, least squares on log luminance, a grid over directions), and each transferred
   colour is multiplied by ``shade(new normal) / shade(source normal)``.
5. *Recolour* (:func:`recolor_pixels`): the body's pixels (the largest colour cluster of the car, in CIE
   Lab) move to the named colour's chroma and lightness, their variation (shading, reflections) kept;
   windows, tyres and lights (other clusters) are untouched.
6. A soft darkened footprint under a moved object is its new contact shadow.

:class:`PhotoResult` carries the picture and a per-pixel *source map* (:data:`SOURCE_NAMES`: input, photo,
mirror, fallback, fill, recolored, shadow) saying where each pixel came from; only ``input`` pixels are the
input's, bit for bit.

The package, by concept: :mod:`~sdn3d.editing.photo.settings` (:class:`~sdn3d.editing.photo.settings.PhotoSettings`,
the fill methods, the source-map codes), :mod:`~sdn3d.editing.photo.light` (step 4),
:mod:`~sdn3d.editing.photo.fill` and :mod:`~sdn3d.editing.photo.road` (step 2), :mod:`~sdn3d.editing.photo.recolor`
(step 5) and
:mod:`~sdn3d.editing.photo.transfer` (steps 1, 3 and 6, and the pipeline:
:func:`~sdn3d.editing.photo.transfer.render_photo`). Pixel-frame geometry is :mod:`sdn3d.editing.frame`'s.
"""
