"""The Python results equal the C++ ones: the real cloth-ball step (113,854 contacts), every step
of the generated scenes, and the queries' answers, against the contacts the `mccd` command-line
tool of the same build writes (`mccd run --contacts FILE.csv`, times printed to round-trip)."""
import math

import numpy as np
import pytest

import mccd
from conftest import contacts_as_csv_rows, read_contacts_csv, run_cli

SCENES = ["cloth", "spheres", "random", "tube", "drape"]
FRAMES = 6


def test_cloth_ball_step_equals_cpp(cloth_ball, cloth_ball_frames, cli, tmp_path):
    V0, F, V1 = cloth_ball
    csv = tmp_path / "cpp.csv"
    r_cli = run_cli(cli, "run", cloth_ball_frames, "--contacts", csv, "--quiet")
    assert "113,854 contacts (19,032 vertex-face, 94,822 edge-edge)" in r_cli.stdout
    cpp = read_contacts_csv(csv)
    assert len(cpp) == 113854

    scene = mccd.Scene([(V0, F)])
    r = scene.step([V0], [V1])
    assert len(r) == 113854
    assert np.count_nonzero(r.contacts["kind"] == mccd.VERTEX_FACE) == 19032
    assert np.array_equal(contacts_as_csv_rows(r.contacts, 0), cpp)
    assert r.earliest_toi == cpp["t"].min()
    # the queries agree with the C++ step
    assert scene.earliest_impact([V0], [V1]) == cpp["t"].min()
    assert scene.is_collision_free([V0], [V1]) is False
    assert scene.is_collision_free([V0], [V0]) is True
    # and with the front kept, a second step and advance() too
    assert np.array_equal(scene.step([V0], [V1]).contacts, r.contacts)
    assert np.array_equal(mccd.Scene([(V0, F)], threads=1).advance([V1]).contacts, r.contacts)
    # float32 copies read in place: the step of the rounded positions equals C++'s on them
    r32 = mccd.Scene([(V0, F)]).step([V0.astype(np.float32)], [V1.astype(np.float32)])
    r32_ref = mccd.Scene([(V0, F)]).step([V0.astype(np.float32).astype(float)], [V1.astype(np.float32).astype(float)])
    assert len(r32) > 100000 and np.array_equal(r32.contacts, r32_ref.contacts)


def test_cloth_ball_run_writes_the_commands_csv(cloth_ball_frames, cli, tmp_path):
    run_cli(cli, "run", cloth_ball_frames, "--contacts", tmp_path / "cpp.csv", "--quiet")
    res = mccd.run(cloth_ball_frames, contacts=tmp_path / "py.csv")
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cpp.csv").read_bytes()
    assert len(res) == 1 and res.steps[0]["vf"] == 19032 and res.steps[0]["ee"] == 94822
    assert res.summary["vf_contacts"] + res.summary["ee_contacts"] == 113854


@pytest.mark.parametrize("name", SCENES)
def test_generated_scene_every_step_equals_cpp(name, cli, tmp_path):
    csv = tmp_path / "cpp.csv"
    run_cli(cli, "run", "--scene", name, "--size", 1, "--frames", FRAMES, "--contacts", csv, "--quiet")
    cpp = read_contacts_csv(csv)

    meshes, frames = mccd.make_scene(name, 1, FRAMES)
    scene = mccd.Scene(meshes)
    queries = mccd.Scene(meshes, threads=2)
    steps_with_contacts = 0
    for k in range(FRAMES - 1):
        r = scene.advance(frames[k + 1])
        mine = contacts_as_csv_rows(r.contacts, k)
        theirs = cpp[cpp["frame"] == k]
        assert np.array_equal(mine, theirs), f"{name}: step {k}"
        steps_with_contacts += len(theirs) > 0
        # the queries' answers against the C++ step's contacts
        free = queries.is_collision_free(frames[k], frames[k + 1])
        earliest = queries.earliest_impact(frames[k], frames[k + 1])
        assert free == (len(theirs) == 0), f"{name}: step {k}"
        assert earliest == (theirs["t"].min() if len(theirs) else math.inf), f"{name}: step {k}"
        assert r.earliest_toi == earliest
        # every contact is among the broad phase's candidates, no later than its lower bound allows
        cands = queries.candidates(frames[k], frames[k + 1])
        key = lambda c: list(zip(c["kind"].tolist(), c["mesh_a"].tolist(), c["a"].tolist(), c["mesh_b"].tolist(),
                                 c["b"].tolist()))
        lower = dict(zip(key(cands), cands["toi"].tolist()))
        for pair, toi in zip(key(r.contacts), r.contacts["toi"].tolist()):
            assert pair in lower and lower[pair] <= toi
    assert steps_with_contacts >= 1, f"{name}: no step with contacts, nothing compared"


def test_run_of_a_generated_scene_writes_the_commands_files(cli, tmp_path):
    run_cli(cli, "run", "--scene", "tube", "--size", 2, "--frames", 8, "--substeps", 3, "--method", "phc",
            "--contacts", tmp_path / "cpp.csv", "--quiet")
    res = mccd.run(scene="tube", size=2, frame_count=8, substeps=3, method="phc", contacts=tmp_path / "py.csv")
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cpp.csv").read_bytes()
    assert len(res) == 7 and res.summary["vf_contacts"] + res.summary["ee_contacts"] > 0
