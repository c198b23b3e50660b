"""`pip install .` builds the lieservo Python package with scikit-build and the project's own
CMakeLists.txt (the Python module alone: no tests, examples or benchmarks). The version is
package.xml's, as for every other artefact."""
import re
from pathlib import Path

from skbuild import setup

HERE = Path(__file__).resolve().parent
VERSION = re.search(r"<version>([0-9]+\.[0-9]+\.[0-9]+)</version>", (HERE / "package.xml").read_text()).group(1)

setup(
    name="lieservo",
    version=VERSION,
    description="Lie-group estimation and control for pose-and-shear tactile servoing (Python binding)",
    long_description=(HERE / "docs" / "python.md").read_text(encoding="utf-8"),
    long_description_content_type="text/markdown",
    license="MIT",
    python_requires=">=3.9",
    install_requires=["numpy"],
    # The package's source is examples/python/lieservo_package; CMake installs the compiled module
    # into the same path under scikit-build's staging prefix, where scikit-build looks for it.
    packages=["lieservo"],
    package_dir={"lieservo": "examples/python/lieservo_package"},
    cmake_args=[
        "-DCMAKE_BUILD_TYPE=Release",
        "-DLIESERVO_BUILD_PYTHON=ON",
        "-DLIESERVO_BUILD_TESTS=OFF",
        "-DLIESERVO_BUILD_EXAMPLES=OFF",
        "-DLIESERVO_BUILD_BENCHMARKS=OFF",
        "-DLIESERVO_WARNINGS_AS_ERRORS=OFF",  # a user's newer compiler may warn where ours do not
        "-DLIESERVO_PYTHON_PACKAGE_DIR=examples/python/lieservo_package",
    ],
    cmake_install_target="lieservo_install_python",
)
