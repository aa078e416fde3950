"""``python -m rcm_pin``: the ``rcm-pin`` command line."""

from rcm_pin.cli import main

raise SystemExit(main())
