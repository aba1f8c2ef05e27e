"""``python -m noisevar``: see :mod:`noisevar.cli`."""

from .cli import main

raise SystemExit(main())
