"""``python -m kin ...``: the ``kin`` command."""

from kin.commands import console

if __name__ == "__main__":
    raise SystemExit(console())
