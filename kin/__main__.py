"""``python -m kin ...``: the ``kin`` command."""

from kin.commands import main

if __name__ == "__main__":
    raise SystemExit(main())
