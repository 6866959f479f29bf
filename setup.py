# SPDX-License-Identifier: Apache-2.0
"""The package list, the one thing pyproject.toml cannot say: every package under model/ and sim/,
found (a new one is installed with no edit here; a data folder such as sim/vectors/<set> is a
namespace package, so its files are package data), plus the folders installed under other names
(pyproject.toml's package-dir): rtl/ as ``model.rtl`` and formal/ as ``model.formal``.
Everything else is in pyproject.toml; tests/test_wheel.py installs the wheel and runs it."""

from setuptools import find_namespace_packages, setup

setup(
    packages=[
        *find_namespace_packages(
            include=["model", "model.*", "sim", "sim.*"], exclude=["*.__pycache__"]
        ),
        "model.rtl",
        "model.rtl.rom",
        "model.formal",
    ]
)
