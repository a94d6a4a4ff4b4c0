"""Builds the extension vcmm._vcmm with the project's CMake (pyproject.toml, docs/python.md).

The CMake build lives in build-pip/ (ignored by git) and is reused by the next `pip install .`.
The interpreter running pip is the one the module is built for (-DVCMM_PYTHON3). ccache and
Ninja are used when present. VCMM_CMAKE_ARGS (environment) adds configure arguments.
"""

import os
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def project_version():
    """The version of CMakeLists.txt's project() (one place for it)."""
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        match = re.search(r"project\(vcmm VERSION ([0-9.]+)", f.read())
    if not match:
        raise RuntimeError("setup.py: no 'project(vcmm VERSION x.y.z' in CMakeLists.txt")
    return match.group(1)


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        package_dir = os.path.dirname(os.path.abspath(self.get_ext_fullpath(ext.name)))
        build_dir = os.path.join(ROOT, "build-pip", "cmake")
        args = ["-DCMAKE_BUILD_TYPE=Release", "-DVCMM_BUILD_PYTHON=ON",
                "-DVCMM_BUILD_TESTS=OFF", "-DVCMM_BUILD_BENCHMARKS=OFF", "-DVCMM_BUILD_CLI=OFF",
                "-DVCMM_WERROR=OFF", f"-DVCMM_PYTHON3={sys.executable}",
                f"-DVCMM_PYTHON_PACKAGE_DIR={package_dir}"]
        if shutil.which("ninja") and not os.path.exists(os.path.join(build_dir, "CMakeCache.txt")):
            args += ["-G", "Ninja"]
        if shutil.which("ccache"):
            args.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        args += shlex.split(os.environ.get("VCMM_CMAKE_ARGS", ""))
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 2))
        subprocess.check_call(["cmake", "-S", ROOT, "-B", build_dir] + args)
        subprocess.check_call(["cmake", "--build", build_dir, "--target", "_vcmm", "-j", jobs])


setup(
    version=project_version(),
    packages=["vcmm"],
    package_dir={"vcmm": "python/vcmm"},
    ext_modules=[CMakeExtension("vcmm._vcmm")],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": "build-pip"}, "egg_info": {"egg_base": "build-pip"}},
    zip_safe=False,
)
