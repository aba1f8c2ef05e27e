"""``python -m noisevar``: see :mod:`noisevar.cli`."""

from noisevar.cli import main

raise SystemExit(main())
