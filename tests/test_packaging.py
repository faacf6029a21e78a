"""Every package directory is a regular package that setuptools' ``find_packages`` ships.

A directory of modules without ``__init__.py`` is a namespace package: an editable install
imports it, but ``find_packages`` leaves it out of a wheel (and pytest's doctest collection
imports its modules under their bare names).
"""

from pathlib import Path

from setuptools import find_packages

ROOT = Path(__file__).resolve().parents[1]


def test_every_module_directory_is_a_shipped_package():
    dirs = {p.parent for p in (ROOT / "uio_ring").rglob("*.py") if "__pycache__" not in p.parts}
    names = {".".join(d.relative_to(ROOT).parts) for d in dirs}
    shipped = set(find_packages(str(ROOT), include=["uio_ring*"]))
    assert names <= shipped, f"not shipped (no __init__.py): {sorted(names - shipped)}"
