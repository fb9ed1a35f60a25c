"""Dataset readers (Virtual KITTI 1.3.1 / 2.0.3, Cityscapes), shared records and the
3D-SDN edit-benchmark format.

Readers index a dataset into :class:`~sdn3d.data.records.FrameRecord` objects
(``vkitti1.read_frames``, ``vkitti2.read_frames``, ``cityscapes.read_frames``);
:mod:`sdn3d.data.records`' loaders read arrays lazily for any record. The package itself imports
nothing, so a user of one module (e.g. the edit-benchmark format) does not load the readers.
:mod:`sdn3d.data.fixtures` writes tiny datasets in the same formats (a test and generator helper).
"""
