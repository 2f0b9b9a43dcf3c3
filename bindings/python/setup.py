"""Builds the hgcd Python package: `pip install ./bindings/python` (offline:
needs only Debian's python3-cffi, python3-numpy and python3-setuptools, and
the C library, found as hgcd_build.py describes)."""
from setuptools import setup

setup(
    name="hgcd",
    version="0.1.0",
    description="Exact collision detection between many rigid triangle meshes, from numpy",
    packages=["hgcd"],
    python_requires=">=3.8",
    install_requires=["numpy", "cffi>=1.12"],
    cffi_modules=["hgcd_build.py:make_ffi"],
    zip_safe=False,
)
