"""``python -m dh2urdf``: the ``dh2urdf`` command (see :mod:`dh2urdf.command`)."""

from .command import console

raise SystemExit(console())
