"""The tyre command (``python -m drake_car.tyre``): a package, not a module ``tyre.py``, so its
name does not shadow ``systems/tyre.py`` (tests/test_layout.py: no two modules of one name)."""
