"""Every package of chainid is installed: pyproject's explicit package list names each folder holding an
``__init__.py`` (a sub-package left out installs fine in editable mode and breaks the wheel ``.ci/run`` builds), and
the data folder is listed with the files the runtime reads."""
from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _listed() -> set[str]:
    with open(ROOT / "pyproject.toml", "rb") as fh:
        return set(tomllib.load(fh)["tool"]["setuptools"]["packages"])


def test_every_chainid_sub_package_is_in_the_package_list():
    found = {".".join(p.parent.relative_to(ROOT).parts) for p in (ROOT / "chainid").rglob("__init__.py")
             if "__pycache__" not in p.parts}
    assert "chainid.model.effects" in found  # the check sees nested packages
    missing = sorted(found - _listed())
    assert missing == [], f"add to [tool.setuptools] packages in pyproject.toml: {missing}"


#: folders listed as packages for their data files alone (setuptools installs package data of listed packages)
DATA_ONLY = {"chainid.data"}


def test_the_package_list_names_no_missing_folder():
    dirs = {"chainid.derive": ROOT / "derive", "chainid.generated": ROOT / "generated"}
    for name in sorted(_listed() - DATA_ONLY):
        folder = dirs.get(name, ROOT.joinpath(*name.split(".")))
        assert (folder / "__init__.py").is_file(), f"{name}: no {folder / '__init__.py'}"


def test_the_data_folder_is_listed_with_its_files_and_holds_no_code():
    with open(ROOT / "pyproject.toml", "rb") as fh:
        data = tomllib.load(fh)["tool"]["setuptools"]["package-data"]
    for name in sorted(DATA_ONLY):
        folder = ROOT.joinpath(*name.split("."))
        assert not list(folder.glob("*.py")), f"{name} holds code: list it as a package with an __init__.py"
        shipped = {f.name for pattern in data[name] for f in folder.glob(pattern)}
        assert {"chains.toml", "table1.csv"} <= shipped  # the catalogue and the paper's Table 1
