"""The `dsr` offline verbs, run as the installed console script (no ROS node needed)."""

import json
import shutil
import subprocess

import numpy as np
import pytest

DSR = shutil.which("dsr")


def dsr(*args, timeout=60):
    assert DSR, (
        "dsr is not on PATH: run the tests through scripts/test.sh (it sources scripts/env.sh)"
    )
    return subprocess.run([DSR, *map(str, args)], capture_output=True, text=True, timeout=timeout)


def test_validate_exit_codes_and_one_line_per_violation(cortex_dir):
    ok = dsr("validate", cortex_dir / "Robot_viriato.json")
    assert ok.returncode == 0, ok.stderr
    assert "valid cortex world: 14 nodes, 13 edges" in ok.stdout
    bad = dsr("validate", cortex_dir / "autonomyLab_objects.simscene.json")
    assert bad.returncode == 1
    lines = bad.stdout.strip().splitlines()
    assert len(lines) == 2 and all("no-self-loop" in line for line in lines)
    assert "'fridge'->'fridge'" in lines[0] and "'table'->'table'" in lines[1]


def test_validate_unreadable_file(tmp_path):
    p = tmp_path / "x.json"
    p.write_text("{nope")
    r = dsr("validate", p)
    assert r.returncode == 1 and "is not JSON" in r.stderr
    r = dsr("validate", tmp_path / "missing.json")
    assert r.returncode == 1 and "cannot read" in r.stderr


def test_transform_prints_matrix_translation_quaternion(cortex_dir):
    r = dsr("transform", cortex_dir / "Robot_viriato.json", "robot", "laser1")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert set(out) == {"matrix", "translation", "quaternion_wxyz"}
    assert np.allclose(out["translation"], [0.1, 0.4, 0.1])  # CORTEX's mm, printed in metres
    assert np.allclose(out["quaternion_wxyz"], [1, 0, 0, 0])
    back = json.loads(dsr("transform", cortex_dir / "Robot_viriato.json", "laser1", "robot").stdout)
    assert np.allclose(np.array(out["matrix"]) @ np.array(back["matrix"]), np.eye(4))


def test_transform_on_a_world_with_violations_warns_and_answers(cortex_dir):
    r = dsr("transform", cortex_dir / "Robot_giraff.json", "robot", "battery")
    assert r.returncode == 0
    assert np.allclose(json.loads(r.stdout)["translation"], [0, -0.2, 0.2])
    assert "node-missing" in r.stderr


@pytest.mark.parametrize(
    "frm, to, fragment",
    [
        ("robot", "ghost", "no node 'ghost'"),
        ("robot", "mind", "not geometric"),
    ],
)
def test_transform_errors(cortex_dir, frm, to, fragment):
    r = dsr("transform", cortex_dir / "Robot_viriato.json", frm, to)
    assert r.returncode == 1 and fragment in r.stderr and r.stdout == ""


def test_convert_both_ways_keeps_transforms(cortex_dir, tmp_path):
    src = cortex_dir / "autonomyLab_complete.simscene.json"
    ours, back = tmp_path / "lab.dsr.json", tmp_path / "lab.cortex.json"
    assert dsr("convert", src, ours, "--format", "dsr").returncode == 0
    assert json.loads(ours.read_text())["format"] == "dsr-graph"
    assert dsr("validate", ours).returncode == 0
    assert dsr("convert", ours, back, "--format", "cortex").returncode == 0
    assert "DSRModel" in json.loads(back.read_text())
    for f in (src, ours, back):
        t = json.loads(dsr("transform", f, "world", "camera_pose").stdout)
        assert np.allclose(
            t["translation"],
            json.loads(dsr("transform", src, "world", "camera_pose").stdout)["translation"],
        )


def test_convert_strict_refuses_a_world_with_violations(cortex_dir, tmp_path):
    out = tmp_path / "o.json"
    r = dsr("convert", cortex_dir / "Robot_giraff.json", out, "--strict")
    assert r.returncode == 1 and not out.exists() and "node-missing" in r.stderr
    r = dsr("convert", cortex_dir / "Robot_giraff.json", out)
    assert r.returncode == 0 and out.exists() and "left out" in r.stderr


def test_a_vocabulary_extension_makes_unknown_types_valid(tmp_path):
    world = tmp_path / "w.json"
    world.write_text(
        json.dumps(
            {
                "format": "dsr-graph",
                "version": 1,
                "kind": "world",
                "nodes": [{"name": "dock", "type": "charger"}],
                "edges": [],
            }
        )
    )
    r = dsr("validate", world)
    assert r.returncode == 1 and "unknown-node-type" in r.stdout
    vocab = tmp_path / "v.json"
    vocab.write_text(
        json.dumps(
            {
                "format": "dsr-vocabulary",
                "version": 1,
                "extends": "default",
                "node_types": {"charger": "a docking station"},
            }
        )
    )
    assert dsr("validate", world, "--vocabulary", vocab).returncode == 0
