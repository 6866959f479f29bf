# SPDX-License-Identifier: Apache-2.0
"""The package as a user installs it: the wheel built from the checkout, installed into a fresh
venv outside it, run from another folder.

The sources the checkout holds (``git ls-files``, untracked files not ignored included) are
copied to a temporary folder and built there (``pip wheel --no-build-isolation``, the venv's
setuptools: no network; a build in the checkout would leave build/ behind, whose stale copies
a later wheel can carry).  The new venv has no pip and none of the checkout: a ``.pth`` line
puts .venv's site-packages after its own for numpy, numba and the rest (the editable install's
finder there is a ``.pth`` file of that folder, which a ``.pth`` line does not run).  Then
``shading demo``, ``shading fit --help`` and ``python -m sim --help`` run, every data file the
installed code reads is where it looks (``model.units.rom``, ``model.fit.verilog``,
``model.hw.formal``, ``sim.vector_sets``, the scenes) and a committed vector set replays from the
installed package under Icarus.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# checkout folders that are no part of the package's sources (fetched data, outputs)
NOT_SOURCES = ("data/", "out/", "sim_build/")
# tracked folders whose every file the installed code reads, and where they land in the wheel
DATA = {
    "rtl/": "model/rtl/",
    "formal/": "model/formal/",
    "sim/vectors/": "sim/vectors/",
    "model/render/scenes/": "model/render/scenes/",
}


def checkout_files() -> list[str]:
    out = subprocess.run(
        ["git", "ls-files", "-co", "--exclude-standard"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return [n for n in out.splitlines() if not n.startswith(NOT_SOURCES) and (ROOT / n).is_file()]


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> dict:
    tmp = tmp_path_factory.mktemp("wheel")
    src = tmp / "src"
    for name in checkout_files():
        (src / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, src / name)
    wheels = tmp / "dist"
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "--no-input"]
    build = subprocess.run(
        [*pip, "wheel", "--no-deps", "--no-build-isolation", "-w", str(wheels), str(src)],
        capture_output=True,
        text=True,
    )
    assert build.returncode == 0, build.stdout + build.stderr
    (wheel,) = wheels.glob("*.whl")

    venv = tmp / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    site = subprocess.run(
        [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    (Path(site) / "checkout_venv_deps.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    install = subprocess.run(
        [*pip, "--python", str(python), "install", "--no-deps", "--no-index", str(wheel)],
        capture_output=True,
        text=True,
    )
    assert install.returncode == 0, install.stdout + install.stderr

    work = tmp / "work"  # the commands' folder: outside the checkout
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    return {"wheel": wheel, "venv": venv, "python": python, "work": work, "env": env}


def run(installed: dict, *cmd: str, timeout: float = 600) -> subprocess.CompletedProcess:
    done = subprocess.run(
        [str(installed["venv"] / "bin" / cmd[0]), *cmd[1:]],
        cwd=installed["work"],
        env=installed["env"],
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert done.returncode == 0, f"{' '.join(cmd)}:\n{done.stdout}\n{done.stderr}"
    return done


def test_wheel_holds_every_package_and_data_file(installed: dict) -> None:
    names = set(zipfile.ZipFile(installed["wheel"]).namelist())
    for name in checkout_files():
        if name.startswith(("model/", "sim/")) and name.endswith(".py"):
            assert name in names, f"module {name} is not in the wheel"
        for folder, where in DATA.items():
            if name.startswith(folder):
                inside = where + name[len(folder) :]
                assert inside in names, f"{name} is not in the wheel (as {inside})"


def test_installed_commands_run_outside_the_checkout(installed: dict) -> None:
    out = installed["work"] / "o"
    run(installed, "shading", "demo", "--scene", "sphere", "--size", "32", "--out", str(out))
    assert list(out.glob("*.png")), "shading demo wrote no image"
    assert "usage: shading fit" in run(installed, "shading", "fit", "--help").stdout
    assert "usage: python -m sim" in run(installed, "python", "-m", "sim", "--help").stdout


def test_installed_code_finds_its_files_in_the_installed_package(installed: dict) -> None:
    probe = """
from pathlib import Path
import model, sim
from model.fit import verilog
from model.hw import formal, formal_specular
from model.render import scenefile
from model.units import rom
from sim import runner, vector_run, vector_sets
print(Path(model.__file__).resolve())
print(Path(sim.__file__).resolve())
for folder, names in [
    (rom.ROM_DIR, ["*.hex"]),
    (verilog.RTL_DIR, ["*.v", "*.f", "*.core"]),
    (runner.RTL_DIR, ["*.v"]),
    (formal.FORMAL_DIR, ["*_props.v"]),
    (scenefile.SCENE_DIR, ["*.toml"]),
    (vector_run.VECTOR_DIR, ["tb_*.v", "*.vh", "*/vectors.bin", "*/params.txt"]),
]:
    for name in names:
        assert list(Path(folder).glob(name)), f"no {name} in {folder}"
    print(Path(folder).resolve())
assert formal_specular.REFERENCE_FILE.is_file(), formal_specular.REFERENCE_FILE
"""
    printed = run(installed, "python", "-c", probe).stdout.split()
    site = installed["venv"].resolve()
    for path in map(Path, printed):
        assert not path.is_relative_to(ROOT), f"{path}: the checkout leaked into the venv"
        assert path.is_relative_to(site), f"{path} is not in the installed package"


def test_installed_package_replays_a_committed_vector_set(installed: dict) -> None:
    # make test installs Icarus first (make tools): a missing iverilog fails here, it is not
    # skipped
    assert shutil.which("iverilog"), "iverilog is not on PATH: make tools installs it"
    probe = """
from pathlib import Path
from sim import vector_sets
build = Path("build").resolve()  # the builds' folder, absolute (vector_run runs in it)
r = vector_sets.replay(vector_sets.VECTOR_DIR / "divider_default", "icarus", build)
assert r.passed and r.mismatches == 0, r.log
print("replayed", r.cycles, "cycles from", vector_sets.VECTOR_DIR)
"""
    out = run(installed, "python", "-c", probe).stdout
    assert "replayed" in out and str(installed["venv"]) in out, out
