# SPDX-License-Identifier: Apache-2.0
"""No duplicate numba compiles: every method on every built-in scene, in a fresh process,
leaves each of the project's numba functions with one compiled signature (a read-only or
non-contiguous array would add a second one, compiled again on every cold start).  The probe:
the same check sees a second signature when one is made on purpose."""

from __future__ import annotations

import json
import subprocess
import sys

SCRIPT = """
import json, sys
import numpy as np
from numba.core.registry import CPUDispatcher
from model.render import scenefile
from model.study import report
for name in scenefile.SCENE_NAMES:
    report.run_methods(scenefile.builtin_scene(name, 48, 48))
if sys.argv[1] == "probe":
    from model.units import fixed
    fixed.saturate(3, 0, 1)
    fixed.saturate(np.float64(3.0), 0, 1)  # a float: a second signature on purpose
found = {}
for mod_name, mod in list(sys.modules.items()):
    if mod_name.startswith("model"):
        for attr, obj in vars(mod).items():
            if isinstance(obj, CPUDispatcher) and obj.__module__ == mod_name:
                found[f"{mod_name}.{attr}"] = [str(s) for s in obj.signatures]
print(json.dumps(found))
"""


def signatures(mode: str) -> dict[str, list[str]]:
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT, mode], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_every_numba_function_is_compiled_once(teapot_file) -> None:
    found = signatures("plain")
    assert len(found) > 30 and any(found.values())
    twice = {name: sigs for name, sigs in found.items() if len(sigs) > 1}
    assert not twice, twice


def test_a_second_signature_is_seen(teapot_file) -> None:
    found = signatures("probe")
    assert len(found["model.units.fixed.saturate"]) >= 2
