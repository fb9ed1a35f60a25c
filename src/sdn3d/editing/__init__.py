"""Editing a :class:`~sdn3d.scene.code.SceneCode`: the operations (``ops``), applying them (``apply``),
the YAML edit-spec format of ``sdn3d-edit`` (``spec``) and drawing the edited image (``render``)."""
