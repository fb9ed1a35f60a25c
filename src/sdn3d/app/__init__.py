"""``sdn3d-app``: the browser editor (issue 30).

- :mod:`sdn3d.app.editor`: the editor's state: one :class:`~sdn3d.editing.session.EditSession` (the models, loaded
  once), the browser sessions (each its own image, its own directory under the output directory, its current spec
  and picture), the spec and ``sdn3d-edit`` command line that reproduce a picture.
- :mod:`sdn3d.app.server`: the HTTP interface (Starlette; JSON in and out, images as PNG) and the page.
- ``static/``: the page (one HTML file, plain JavaScript on a canvas, no build step).

The command line is :mod:`sdn3d.cli.app` (``conf/app.yaml``).
"""
