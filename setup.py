"""The package list: every package under app/, and static/ installed as app.static (its
files are package data). Everything else is in pyproject.toml."""
from setuptools import find_packages, setup

setup(packages=find_packages(include=["app", "app.*"]) + ["app.static"])
