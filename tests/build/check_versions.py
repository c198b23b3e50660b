#!/usr/bin/env python3
"""Every artefact carries package.xml's version (CTest build.versions_agree; .ci/packages adds the
DEBs and the pip-installed module).

  check_versions.py SOURCE_DIR BUILD_DIR [--deb FILE ...] [--python EXE ...]

Checked: package.xml (the one place it is written), setup.py --version (pip's metadata), the
build's CMake package version file, its pkg-config files, its CPack config (the DEBs' version),
the built Python package's __version__ (when the build has one), each --deb file's control field,
and lieservo.__version__ as each --python interpreter imports it.
"""
import argparse
import os
import re
import subprocess
import sys
from pathlib import Path


def read(path, pattern):
    """The first group of `pattern` in the file at `path`, or None when absent."""
    if not path.exists():
        return None
    m = re.search(pattern, path.read_text())
    return m.group(1) if m else "(no version in the file)"


def python_version(python, env=None):
    out = subprocess.run([python, "-c", "import lieservo; print(lieservo.__version__, lieservo.__file__)"],
                         capture_output=True, text=True, env=env, cwd="/")
    if out.returncode != 0:
        return f"(import failed: {out.stderr.strip().splitlines()[-1] if out.stderr.strip() else out.returncode})"
    version, where = out.stdout.split()
    print(f"  {python} imports {where}")
    return version


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("source", type=Path)
    ap.add_argument("build", type=Path)
    ap.add_argument("--deb", nargs="*", default=[], type=Path)
    ap.add_argument("--python", nargs="*", default=[])
    a = ap.parse_args()

    expected = read(a.source / "package.xml", r"<version>([^<]+)</version>")
    found = {
        "setup.py --version": subprocess.run([sys.executable, "setup.py", "--version"], cwd=a.source,
                                             capture_output=True, text=True).stdout.strip().splitlines()[-1:],
        "lieservoConfigVersion.cmake": read(a.build / "lieservoConfigVersion.cmake", r'set\(PACKAGE_VERSION "([^"]+)"\)'),
        "lieservo.pc": read(a.build / "lieservo.pc", r"\nVersion: (\S+)"),
        "lieservo-ceres.pc": read(a.build / "examples/adapters/ceres/lieservo-ceres.pc", r"\nVersion: (\S+)"),
        "CPackConfig.cmake (the DEBs)": read(a.build / "CPackConfig.cmake", r'set\(CPACK_PACKAGE_VERSION "([^"]+)"\)'),
    }
    found["setup.py --version"] = (found["setup.py --version"] or ["(no output)"])[0]
    if (a.build / "python/lieservo/__init__.py").exists():
        env = dict(os.environ, PYTHONPATH=str((a.build / "python").resolve()))
        found["the built Python package"] = python_version(sys.executable, env)
    for deb in a.deb:
        found[deb.name] = subprocess.run(["dpkg-deb", "-f", str(deb), "Version"], capture_output=True,
                                         text=True).stdout.strip() or "(no Version field)"
    for python in a.python:
        found[f"lieservo.__version__ under {python}"] = python_version(python)

    bad = 0
    print(f"package.xml: {expected}")
    for what, version in found.items():
        if version is None:
            print(f"  {what}: not in this build (skipped)")
            continue
        ok = version == expected
        bad += not ok
        print(f"  {what}: {version}{'' if ok else '   <-- differs'}")
    if bad:
        print(f"FAILED: {bad} artefact(s) do not carry package.xml's version {expected}")
    return 1 if bad or expected is None else 0


if __name__ == "__main__":
    sys.exit(main())
